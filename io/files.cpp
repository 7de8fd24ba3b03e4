#include "io/files.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <random>
#include <regex>

namespace iga {

namespace fs = std::filesystem;

namespace {

std::string errno_text(int e) { return std::strerror(e); }

// write(2) until done; false with errno set on failure
bool write_all(int fd, const char* p, size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (w == 0) { errno = EIO; return false; }
    p += w;
    n -= static_cast<size_t>(w);
  }
  return true;
}

// The .part files written and not yet renamed or removed, for the interrupt handler: fixed
// slots of C strings (the handler may not allocate), a slot's path written before its flag.
constexpr int kPendingSlots = 64;
constexpr size_t kPendingPath = 4096;
char g_pending[kPendingSlots][kPendingPath];
volatile std::sig_atomic_t g_pending_used[kPendingSlots];

int note_pending(const std::string& tmp) {
  if (tmp.size() >= kPendingPath) return -1;
  for (int k = 0; k < kPendingSlots; ++k)
    if (!g_pending_used[k]) {
      std::memcpy(g_pending[k], tmp.c_str(), tmp.size() + 1);
      g_pending_used[k] = 1;
      return k;
    }
  return -1;
}

extern "C" void remove_pending_and_die(int sig) {
  for (int k = 0; k < kPendingSlots; ++k)
    if (g_pending_used[k]) ::unlink(g_pending[k]);   // (async-signal-safe)
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

}  // namespace

void remove_part_files_on_interrupt() {
  struct sigaction sa {};
  sa.sa_handler = remove_pending_and_die;
  sigemptyset(&sa.sa_mask);
  // a signal the parent had ignored stays ignored (a job started in the background by a
  // script ignores SIGINT; nohup, SIGHUP)
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(sig, &sa, nullptr);
  }
}

void FileBatch::add(const std::string& path, const std::string& bytes) {
  add(path, std::vector<std::string_view>{std::string_view(bytes)});
}

void FileBatch::add(const std::string& path, const std::vector<std::string_view>& pieces) {
  const std::string tmp = path + ".part";
  slots_.push_back(note_pending(tmp));
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int e = errno;
    abandon();
    throw OutputError("cannot write " + tmp + ": " + errno_text(e));
  }
  int err = 0;
  for (const std::string_view& b : pieces)
    if (!err && !write_all(fd, b.data(), b.size())) err = errno;
  if (::close(fd) != 0 && !err) err = errno;
  paths_.push_back(path);
  if (err) {
    abandon();
    throw OutputError("cannot write " + path + ": " + errno_text(err));
  }
}

void FileBatch::commit() {
  if (paths_.empty()) return;
  // one flush of the file system holding the files: their data is on the disk before any
  // rename makes it visible under its name (EINVAL/EROFS: no syncing on this file system)
  const std::string dir = fs::path(paths_.front()).parent_path().string();
  const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  int err = dfd < 0 ? errno : 0;
  if (!err && ::syncfs(dfd) != 0 && errno != EINVAL && errno != EROFS) err = errno;
  if (dfd >= 0) ::close(dfd);
  if (err) {
    const std::string first = paths_.front();
    abandon();
    throw OutputError("cannot write " + first + ": " + errno_text(err));
  }
  for (size_t k = 0; k < paths_.size(); ++k)
    if (::rename((paths_[k] + ".part").c_str(), paths_[k].c_str()) != 0) {
      err = errno;
      const std::string failed = paths_[k];
      paths_.erase(paths_.begin(), paths_.begin() + static_cast<std::ptrdiff_t>(k));
      abandon();
      throw OutputError("cannot write " + failed + ": " + errno_text(err));
    }
  paths_.clear();
  release_slots();
}

void FileBatch::abandon() noexcept {
  for (const std::string& p : paths_) ::unlink((p + ".part").c_str());
  paths_.clear();
  release_slots();
}

void FileBatch::release_slots() noexcept {
  for (int k : slots_)
    if (k >= 0) g_pending_used[k] = 0;
  slots_.clear();
}

FileBatch::~FileBatch() { abandon(); }

void write_file_atomic(const std::string& path, const std::string& bytes) {
  FileBatch b;
  b.add(path, bytes);
  b.commit();
}

std::string crc32_hex(const std::string& bytes) { return crc32_hex(std::vector<std::string_view>{std::string_view(bytes)}); }

std::string crc32_hex(const std::vector<std::string_view>& pieces) {
  uLong c = crc32(0L, Z_NULL, 0);
  for (const std::string_view& bytes : pieces) {
    size_t off = 0;
    while (off < bytes.size()) {   // zlib takes uInt lengths
      const uInt n = static_cast<uInt>(std::min<size_t>(bytes.size() - off, 1u << 30));
      c = crc32(c, reinterpret_cast<const Bytef*>(bytes.data() + off), n);
      off += n;
    }
  }
  char buf[16];
  std::snprintf(buf, sizeof buf, "%08lx", static_cast<unsigned long>(c));
  return buf;
}

std::string new_run_id() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char when[32];
  std::strftime(when, sizeof when, "%Y%m%dT%H%M%SZ", &tm);
  char host[64] = "host";
  gethostname(host, sizeof host - 1);
  std::string h;
  for (const char* c = host; *c; ++c) h += std::isalnum(static_cast<unsigned char>(*c)) ? *c : '_';
  std::random_device rd;
  char rnd[8];
  std::snprintf(rnd, sizeof rnd, "%04x", static_cast<unsigned>(rd() & 0xffff));
  return std::string(when) + "-" + h + "-" + std::to_string(::getpid()) + "-" + rnd;
}

// ---------------------------------------------------------------- HDF5 in memory

H5Memory::H5Memory(std::string name) : name_(std::move(name)) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);   // errors become OutputError, not a printed stack
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  if (fapl < 0 || H5Pset_fapl_core(fapl, 1 << 20, 0) < 0) {
    if (fapl >= 0) H5Pclose(fapl);
    fail("cannot set up an in-memory file");
  }
  file_ = H5Fcreate("igacontact-memory.h5", H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  if (file_ < 0) fail("cannot create an in-memory file");
}

H5Memory::~H5Memory() {
  if (file_ >= 0) H5Fclose(file_);
}

void H5Memory::fail(const std::string& what) const { throw OutputError("cannot write " + name_ + ": HDF5: " + what); }

void H5Memory::group(const std::string& path) {
  const hid_t g = H5Gcreate2(file_, path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (g < 0) fail("cannot create group " + path);
  if (H5Gclose(g) < 0) fail("cannot close group " + path);
}

namespace {
template <class T>
void h5_write(hid_t file, hid_t type, const std::string& path, const std::vector<T>& v, const std::vector<hsize_t>& dims,
              const std::function<void(const std::string&)>& fail) {
  hsize_t n = 1;
  for (hsize_t d : dims) n *= d;
  if (n != v.size()) fail("dataset " + path + " has " + std::to_string(v.size()) + " values for " + std::to_string(n));
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  if (space < 0) fail("cannot create the dataspace of " + path);
  const hid_t ds = H5Dcreate2(file, path.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (ds < 0) { H5Sclose(space); fail("cannot create dataset " + path); }
  const herr_t w = n > 0 ? H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) : 0;
  const herr_t c1 = H5Dclose(ds), c2 = H5Sclose(space);
  if (w < 0 || c1 < 0 || c2 < 0) fail("cannot write dataset " + path);
}
}  // namespace

void H5Memory::write(const std::string& path, const std::vector<double>& v, const std::vector<hsize_t>& dims) {
  h5_write(file_, H5T_NATIVE_DOUBLE, path, v, dims, [this](const std::string& w) { fail(w); });
}

void H5Memory::write_float(const std::string& path, const std::vector<float>& v, const std::vector<hsize_t>& dims) {
  h5_write(file_, H5T_NATIVE_FLOAT, path, v, dims, [this](const std::string& w) { fail(w); });
}

void H5Memory::write_int(const std::string& path, const std::vector<int>& v, const std::vector<hsize_t>& dims) {
  h5_write(file_, H5T_NATIVE_INT, path, v, dims, [this](const std::string& w) { fail(w); });
}

void H5Memory::attribute(const std::string& name, const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  if (type < 0 || H5Tset_size(type, value.size() + 1) < 0) fail("cannot make a string type");
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = space < 0 ? -1 : H5Acreate2(file_, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t w = a < 0 ? -1 : H5Awrite(a, type, value.c_str());
  if (a >= 0) H5Aclose(a);
  if (space >= 0) H5Sclose(space);
  H5Tclose(type);
  if (w < 0) fail("cannot write attribute " + name);
}

std::string H5Memory::image() {
  if (H5Fflush(file_, H5F_SCOPE_GLOBAL) < 0) fail("cannot flush");
  const ssize_t n = H5Fget_file_image(file_, nullptr, 0);
  if (n < 0) fail("cannot get the file image");
  std::string bytes(static_cast<size_t>(n), '\0');
  if (H5Fget_file_image(file_, bytes.data(), bytes.size()) != n) fail("cannot copy the file image");
  return bytes;
}

// ---------------------------------------------------------------- the output directory

bool is_run_output(const std::string& f) {
  static const std::regex ours(
      R"((result\.(h5|xdmf|pvd)|result_(control_nets|contact)\.xdmf|result_[0-9]+\.(h5|vtu)|summary\.json|contact_[0-9]+\.csv|geometry_[^/]+\.xml)(\.part)?)");
  return std::regex_match(f, ours);
}

std::string check_output_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return "cannot create the directory: " + ec.message();
  if (!fs::is_directory(dir, ec)) return "not a directory";
  const std::string probe = (fs::path(dir) / (".igacontact-probe-" + std::to_string(::getpid()))).string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return "cannot write into it: " + errno_text(errno);
  ::close(fd);
  ::unlink(probe.c_str());
  return "";
}

void remove_previous_outputs(const std::string& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!is_run_output(name)) continue;
    if (::unlink(it->path().c_str()) != 0 && errno != ENOENT)
      throw OutputError("cannot remove the previous run's " + it->path().string() + ": " + errno_text(errno));
  }
  if (ec) throw OutputError("cannot list " + dir + ": " + ec.message());
}

void on_root(const Comm& comm, const std::function<void()>& f) {
  std::string msg;
  int failed = 0;
  if (comm.getRank() == 0) {
    try {
      f();
    } catch (const std::exception& e) {
      msg = e.what();
      if (msg.empty()) msg = "output failed";
      failed = 1;
    }
  }
  Teuchos::broadcast(comm, 0, &failed);
  if (failed) throw OutputError(broadcast_string(comm, msg));
}


}  // namespace iga
