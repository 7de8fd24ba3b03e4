#pragma once
// What a run writes: result.h5 + result.xdmf (bodies sampled on a refined grid, contact
// sides), summary.json, contact_<n>.csv. Every file is written under a temporary name and
// renamed when complete, so an interrupted run never leaves a truncated file that looks
// finished. Only rank 0 writes; the solution is brought there with a Tpetra Import.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solver/newton.hpp"

namespace iga {

/// Control point displacements of every body, on rank 0 (empty elsewhere).
std::vector<std::vector<double>> gather_displacements(const System& sys, const Vector& u);

/// Reactions per body and side ([Rx, Ry]), summed over ranks.
nlohmann::json reactions_json(const System& sys, const Vector& residual);

/// Writes all outputs into dir (rank 0) and returns the summary (all ranks).
nlohmann::json write_results(const System& sys, const SolveResult& res, const std::string& dir,
                             const std::string& problem_file);

/// Writes text to path atomically (temporary name, then rename).
void write_file_atomic(const std::string& path, const std::string& text);

}  // namespace iga
