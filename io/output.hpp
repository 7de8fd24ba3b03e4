#pragma once
// What a run writes: result.h5 + result.xdmf (bodies sampled on a refined grid, contact
// sides), summary.json, contact_<n>.csv. Files are written through io/files.hpp (checked,
// atomic, HDF5 built in memory, run id). Only rank 0 writes; the solution is brought there
// with a Tpetra Import.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/files.hpp"
#include "solver/newton.hpp"

namespace iga {

/// Control point displacements of every body, on rank 0 (empty elsewhere).
std::vector<std::vector<double>> gather_displacements(const System& sys, const Vector& u);

/// Reactions per body and side ([Rx, Ry]), summed over ranks.
nlohmann::json reactions_json(const System& sys, const Vector& residual);

/// Writes all outputs but summary.json into dir (rank 0; io/files.hpp says how) and returns
/// the summary (all ranks; its "files" lists what was written). Collective: an OutputError
/// on rank 0 is thrown on every rank.
nlohmann::json write_results(const System& sys, const SolveResult& res, const std::string& dir,
                             const std::string& problem_file, const std::string& run_id);

}  // namespace iga
