#pragma once
// What a run writes: result.h5 + result.xdmf (bodies sampled on a grid, Float32, auto: about
// one sample per control point), result_<n>.vtu (the exact geometry, the primary picture),
// result_control_nets.xdmf, result_contact.xdmf (contact sides), summary.json, contact_<n>.csv. Files are written through io/files.hpp (checked,
// atomic, HDF5 built in memory, run id). Only rank 0 writes; the solution is brought there
// with a Tpetra Import.
// 3-D (analysis.type: solid): no sampled grid (no result.xdmf, no sampled datasets in the
// HDF5 files); result_<n>.vtu holds the boundary faces (output.cells: faces, the default) or the
// elements (volume) as Bezier cells, result_control_nets.xdmf the hexahedral control nets;
// probes and reactions with three components (docs/paraview.md). Contact output in 3-D comes
// with 3-D contact.
#include <array>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/files.hpp"
#include "solver/checks.hpp"   // gather_displacements
#include "solver/newton.hpp"

namespace iga {

/// Reactions per body and side ([Rx, Ry], in 3-D per face [Rx, Ry, Rz]), summed over ranks.
nlohmann::json reactions_json(const System& sys, const Vector& residual);

/// The bodies' part of one written state (docs/problem-file.md, "Outputs"): per patch the group
/// /bodies/<body>[.patch<k>] of the state's HDF5 image f (its file name h5name, as the XDMF
/// refers to it), in 2-D the sampled grid and the control net, in 3-D the control net only
/// (control_shape {m2, m1, m0}, control_xyz, control_hexes, control_displacement); appends
/// their grids to `grids` (result.xdmf; nothing in 3-D) and `nets`
/// (result_control_nets.xdmf; 3-D: Hexahedron topology). disp: per body, dim values per
/// control point. Returns the largest |u| at the 2-D samples (0 in 3-D).
double write_bodies(H5Memory& f, const std::string& h5name, const Problem& P,
                    const std::vector<std::vector<double>>& disp, std::ostream& grids, std::ostream& nets);
/// An XDMF file: one temporal collection of the given states' spatial collections.
std::string xdmf_file(const std::string& run_id, const std::vector<std::string>& states);
/// A probe's entry of summary.json: 2-D at [xi, eta], x, y, displacement [ux, uy], stress
/// [sxx, syy, sxy]; 3-D at [xi, eta, zeta], x, y, z, displacement [ux, uy, uz], stress
/// [sxx, syy, szz, syz, sxz, sxy]. body_disp: the probed body's dim values per control point.
nlohmann::json probe_json(const Problem& P, const Probe& pr, const std::vector<double>& body_disp);

/// The files of one run (docs/problem-file.md, "Outputs"): per converged load step
/// result_<n>.h5 (sampled fields, control net, contact points) and result_<n>.vtu (rational
/// Bezier cells), with result.xdmf and result.pvd over all of them rewritten after each step;
/// at the end result.h5 (the kept state), contact_<n>.csv and the summary. Every call is
/// collective; rank 0 writes (io/files.hpp: checked, atomic; an OutputError there is thrown
/// on every rank). With output.steps = last only the kept state is written, at the end.
class ResultWriter {
 public:
  ResultWriter(const System& sys, std::string dir, std::string problem_file, std::string run_id);
  /// A converged load step: its entry in the summary's history and (all steps) its files.
  void step(const StepState& st);
  /// The kept state's files if not written yet, result.h5, contact_<n>.csv; returns the
  /// summary (all ranks; probes, max_displacement and files on rank 0). summary.json is the
  /// caller's, written last.
  nlohmann::json finish(const SolveResult& res);

 private:
  void write_state(int step, double lambda, const Vector& u, const std::vector<ContactPairData>& contact);
  void write(const std::string& name, const std::string& bytes);   // rank 0
  void write(const std::string& name, const std::vector<std::string_view>& pieces);   // rank 0, bytes in turn
  void root_write(const std::function<void()>& f);   // on_root; a failure abandons the batch
  nlohmann::json contact_json(const std::vector<ContactPairData>& contact) const;
  const System& sys_;
  std::string dir_, problem_file_, run_id_;
  struct Written { int step; double lambda; };
  std::vector<Written> written_;
  // per written state, one spatial collection for each of result.xdmf (bodies),
  // result_control_nets.xdmf and result_contact.xdmf
  std::vector<std::array<std::string, 3>> xdmf_grids_;
  nlohmann::json history_, files_;
  FileBatch batch_;   // rank 0: the files of the state being written, committed together
  double max_displacement_ = 0;           // largest |u| at the sample points of the last state written
};

}  // namespace iga
