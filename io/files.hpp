#pragma once
// Writing output files so that a failure never leaves a file that looks complete.
//
//  * Every file is written whole to `<name>.part`, flushed to the disk (one syncfs for the
//    files of a load step, FileBatch), closed and only then renamed to its name; every system call is checked. On any failure the `.part`
//    is removed and OutputError is thrown: no file of that name is created or replaced.
//  * HDF5 files are built in memory (HDF5's core driver, no backing store) and their image is
//    written by the same checked path: HDF5 itself never writes to the disk, so a full disk
//    cannot leave it with a half-flushed file it later trips over (it used to crash in
//    MPI_Finalize after an unchecked H5Dwrite).
//  * The output directory is checked (created, a directory, writable) before anything is
//    solved, and the files a previous run left there (our names only) are removed when a run
//    starts writing, so one directory never mixes two runs. Every file of a run carries its
//    run id where the format has room for it (summary.json, the HDF5 root attribute, XDMF
//    Information, VTK field data); summary.json, written last, lists each file with its size
//    and CRC-32, which identifies the CSV files too. A run without summary.json is incomplete.
//  * On several ranks only rank 0 writes; `on_root` runs its writing there and tells every
//    rank whether it failed, so all ranks stop together (no rank left waiting in a collective).
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <hdf5.h>
#include <nlohmann/json.hpp>

#include "solver/types.hpp"

namespace iga {

/// The output could not be written: one line naming the path and the reason.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Writes bytes to path atomically (see above). Throws OutputError.
void write_file_atomic(const std::string& path, const std::string& bytes);

/// Files made durable together (one load step's): add() writes each whole to <path>.part;
/// commit() flushes them all with one syncfs of their file system (one journal commit, not
/// one fsync per file), then renames each .part to its name. On failure the .part files are
/// removed and OutputError is thrown; files committed before stay as they were. A batch
/// destroyed uncommitted (an exception between add and commit) removes its .part files.
class FileBatch {
 public:
  FileBatch() = default;
  ~FileBatch();
  FileBatch(const FileBatch&) = delete;
  FileBatch& operator=(const FileBatch&) = delete;
  void add(const std::string& path, const std::string& bytes);
  /// The file's bytes as pieces written in turn.
  void add(const std::string& path, const std::vector<std::string_view>& pieces);
  void commit();
  /// Removes the .part files added since the last commit.
  void abandon() noexcept;

 private:
  std::vector<std::string> paths_;   // written to <path>.part, not yet renamed
  std::vector<int> slots_;           // their slots in the interrupt handler's list (-1: none)
  void release_slots() noexcept;
};

/// SIGINT, SIGTERM and SIGHUP remove the .part files of every uncommitted FileBatch, then end
/// the process by the signal as before (an interrupted run leaves its committed steps and no
/// half-written file; summary.json, written last, is absent).
void remove_part_files_on_interrupt();

/// CRC-32 (zlib) of bytes, as 8 hex digits; of pieces, that of their bytes in turn.
std::string crc32_hex(const std::string& bytes);
std::string crc32_hex(const std::vector<std::string_view>& pieces);

/// A new run id: UTC time, host and process, e.g. "20261123T104512Z-host-12345-3f2a".
std::string new_run_id();

/// An HDF5 file built in memory; every HDF5 call is checked (OutputError naming the file
/// and the object). `image()` gives the bytes of the finished file.
class H5Memory {
 public:
  explicit H5Memory(std::string name);   // name: for messages only
  ~H5Memory();
  H5Memory(const H5Memory&) = delete;
  H5Memory& operator=(const H5Memory&) = delete;
  void group(const std::string& path);
  void write(const std::string& path, const std::vector<double>& v, const std::vector<hsize_t>& dims);
  void write_float(const std::string& path, const std::vector<float>& v, const std::vector<hsize_t>& dims);
  void write_int(const std::string& path, const std::vector<int>& v, const std::vector<hsize_t>& dims);
  /// A string attribute on the root group.
  void attribute(const std::string& name, const std::string& value);
  /// Flushes and returns the file's bytes.
  std::string image();

 private:
  std::string name_;
  hid_t file_ = -1;
  [[noreturn]] void fail(const std::string& what) const;
};

/// The files a run writes into its output directory, by name (used to remove those of a
/// previous run): result.h5, result.xdmf, result.pvd, result_<n>.{h5,vtu}, summary.json,
/// contact_<n>.csv, geometry_<body>.xml (an interrupted rerun left the previous run's), and
/// leftover <name>.part files.
bool is_run_output(const std::string& filename);

/// Creates the output directory if needed and checks that it is a directory this process can
/// write (creates and removes a probe file). Returns "" or the reason it is not usable.
std::string check_output_directory(const std::string& dir);

/// Removes what a previous run left in dir (is_run_output names only). Throws OutputError.
void remove_previous_outputs(const std::string& dir);

/// Runs f on rank 0 and tells every rank whether it threw: on failure every rank throws
/// OutputError with rank 0's message. Collective.
void on_root(const Comm& comm, const std::function<void()>& f);

}  // namespace iga
