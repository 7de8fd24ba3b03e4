#include "model/problem.hpp"
#include "model/yaml_reader.hpp"

// The problem file: parse, apply --set overrides, and build the Problem part by part
// (model/problem_geometry.cpp, problem_boundary.cpp, problem_contact.cpp, problem_solver.cpp,
// problem_checks.cpp; the reader itself in model/yaml_reader.{hpp,cpp}).

#include <filesystem>
#include <fstream>
#include <sstream>

namespace iga {

const char* linear_method_name(LinearMethod m) {
  switch (m) {
    case LinearMethod::CG: return "cg";
    case LinearMethod::GMRES: return "gmres";
    case LinearMethod::Direct: return "direct";
  }
  return "?";
}

const char* preconditioner_name(Preconditioner p) {
  switch (p) {
    case Preconditioner::MueLu: return "muelu";
    case Preconditioner::BoomerAMG: return "boomeramg";
    case Preconditioner::ILUT: return "ilut";
    case Preconditioner::Relaxation: return "relaxation";
    case Preconditioner::None: return "none";
    case Preconditioner::ControlNet: return "control_net";
  }
  return "?";
}

const char* contact_method_name(ContactMethod m) {
  switch (m) {
    case ContactMethod::KtsPenalty: return "kts_penalty";
    case ContactMethod::KtsAlm: return "kts_alm";
    case ContactMethod::MortarPenalty: return "mortar_penalty";
    case ContactMethod::MortarAlm: return "mortar_alm";
  }
  return "?";
}

const char* material_model_name(MaterialModel m) {
  switch (m) {
    case MaterialModel::Linear: return "linear";
    case MaterialModel::SaintVenantKirchhoff: return "saint_venant_kirchhoff";
    case MaterialModel::NeoHookean: return "neo_hookean";
  }
  return "?";
}

int Problem::find_body(const std::string& name) const {
  for (size_t b = 0; b < bodies.size(); ++b)
    if (bodies[b].name == name) return static_cast<int>(b);
  return -1;
}

namespace {

using namespace detail;

Problem build(Reader& R, const YAML::Node& root) {
  R.stages = 1;
  Problem P;
  P.file = R.file;
  if (!root.IsMap()) R.fail("(top level)", root, "expected a mapping with analysis, bodies, ...");
  R.keys(root, "", {"analysis", "bodies", "contact", "solver", "output"});

  if (root["analysis"]) {
    const YAML::Node a = root["analysis"];
    R.keys(a, "analysis", {"type", "kinematics", "thickness", "load_steps", "stages"});
    if (a["kinematics"]) {
      const std::string t = R.string(a["kinematics"], "analysis.kinematics");
      if (t == "small") P.kinematics = Kinematics::Small;
      else if (t == "finite") P.kinematics = Kinematics::Finite;
      else R.fail("analysis.kinematics", a["kinematics"], "expected small or finite");
    }
    if (a["type"]) {
      const std::string t = R.string(a["type"], "analysis.type");
      if (t == "plane_strain") P.analysis = Analysis::PlaneStrain;
      else if (t == "plane_stress") P.analysis = Analysis::PlaneStress;
      else if (t == "solid") P.analysis = Analysis::Solid;
      else R.fail("analysis.type", a["type"], "expected plane_strain, plane_stress or solid (3-D)");
    }
    R.dim = P.dim();
    if (P.analysis == Analysis::Solid && a["thickness"])
      R.fail("analysis.thickness", a["thickness"], "a solid (3-D) has no thickness; remove the key");
    if (P.kinematics == Kinematics::Finite && P.analysis == Analysis::PlaneStress)
      R.fail("analysis.type", a["type"], "finite kinematics is plane strain only (plane_stress is not supported with analysis.kinematics: finite)");
    if (a["thickness"]) P.thickness = R.positive(a["thickness"], "analysis.thickness");
    if (a["load_steps"] && a["stages"])
      R.fail("analysis.stages", a["stages"], "give either load_steps or stages (load steps per stage), not both");
    if (a["load_steps"]) {
      P.load_steps = R.integer(a["load_steps"], "analysis.load_steps");
      if (P.load_steps < 1 || P.load_steps > kMaxLoadSteps)
        R.fail("analysis.load_steps", a["load_steps"], "must be 1.." + std::to_string(kMaxLoadSteps));
    }
    P.stages = {P.load_steps};
    if (a["stages"]) {
      const YAML::Node st = a["stages"];
      if (!st.IsSequence() || st.size() == 0) R.fail("analysis.stages", st, "expected a list of load steps per stage, e.g. [4, 10, 10]");
      P.stages.clear();
      long total = 0;
      for (size_t k = 0; k < st.size(); ++k) {
        const int n = R.integer(st[k], "analysis.stages[" + std::to_string(k) + "]");
        if (n < 1) R.fail("analysis.stages[" + std::to_string(k) + "]", st[k], "must be >= 1");
        total += n;
        P.stages.push_back(n);
      }
      if (total > kMaxLoadSteps)
        R.fail("analysis.stages", st, "more than " + std::to_string(kMaxLoadSteps) + " load steps in all");
      P.load_steps = static_cast<int>(total);
    }
    R.stages = P.num_stages();
  }

  // the output sampling counts in the size checks made while the bodies are refined
  if (root["output"] && root["output"].IsMap() && root["output"]["samples_per_element"]) {
    const YAML::Node n = root["output"]["samples_per_element"];
    const int s = R.samples(n);
    if (s > 0) R.samples_per_element = s;   // auto: at most 4, the bound used
  }

  if (!root["bodies"]) R.missing("bodies");
  const YAML::Node bodies = root["bodies"];
  if (!bodies.IsSequence() || bodies.size() == 0) R.fail("bodies", bodies, "expected a non-empty list of bodies");
  for (size_t k = 0; k < bodies.size(); ++k) {
    const std::string path = "bodies[" + std::to_string(k) + "]";
    Body b = read_body(R, bodies[k], path);
    if (P.find_body(b.name) >= 0) R.fail(path + ".name", bodies[k]["name"], "duplicate body name");
    if (b.model != MaterialModel::Linear && P.kinematics == Kinematics::Small)
      R.fail(path + ".material.model", bodies[k]["material"]["model"],
             std::string(material_model_name(b.model)) + " is a finite-strain model; set analysis.kinematics: finite");
    P.bodies.push_back(std::move(b));
  }

  for (std::string& w : R.warnings) P.warnings.push_back(std::move(w));   // (the bodies' geometry files)
  R.warnings.clear();
  read_contact_pairs(R, root, P);

  read_solver(R, root, P);

  if (root["output"]) {
    const YAML::Node o = root["output"];
    R.keys(o, "output", {"directory", "samples_per_element", "probes", "steps", "cells", "compression"});
    if (o["compression"]) {
      const std::string c = R.string(o["compression"], "output.compression");
      if (c == "auto") P.output.compression = -1;
      else if (c == "none") P.output.compression = 0;
      else if (c == "zlib") P.output.compression = 1;
      else R.fail("output.compression", o["compression"], "expected auto, none or zlib");
    }
    if (o["steps"]) {
      const std::string st = R.string(o["steps"], "output.steps");
      if (st == "all") P.output.all_steps = true;
      else if (st == "last") P.output.all_steps = false;
      else R.fail("output.steps", o["steps"], "expected all or last");
    }
    if (o["directory"]) {
      P.output.directory = R.string(o["directory"], "output.directory");
      if (P.output.directory.empty()) R.fail("output.directory", o["directory"], "must not be empty");
    }
    if (o["samples_per_element"]) {
      P.output.samples_per_element = R.samples(o["samples_per_element"]);
    }
    if (o["cells"]) {
      const std::string c = R.string(o["cells"], "output.cells");
      if (c == "faces") P.output.volume_cells = false;
      else if (c == "volume") P.output.volume_cells = true;
      else R.fail("output.cells", o["cells"], "expected faces or volume");
      if (P.dim() != 3) R.fail("output.cells", o["cells"], "output.cells is for solids (analysis.type: solid); 2-D writes every element");
    }
    if (o["probes"]) {
      const YAML::Node pr = o["probes"];
      if (!pr.IsSequence()) R.fail("output.probes", pr, "expected a list of {body, at}");
      for (size_t k = 0; k < pr.size(); ++k) {
        const std::string path = "output.probes[" + std::to_string(k) + "]";
        R.keys(pr[k], path, {"body", "patch", "at"});
        if (!pr[k]["body"]) R.missing(path + ".body");
        if (!pr[k]["at"]) R.missing(path + ".at");
        Probe p;
        p.body = P.find_body(R.string(pr[k]["body"], path + ".body"));
        if (p.body < 0) R.fail(path + ".body", pr[k]["body"], "no body of that name");
        if (pr[k]["patch"]) {
          p.patch = R.integer(pr[k]["patch"], path + ".patch");
          const int np = static_cast<int>(P.bodies[p.body].patches.size());
          if (p.patch < 0 || p.patch >= np)
            R.fail(path + ".patch", pr[k]["patch"], "body '" + P.bodies[p.body].name + "' has patches 0.." + std::to_string(np - 1));
        }
        const auto at = R.numbers(pr[k]["at"], path + ".at", P.dim());
        for (int d = 0; d < P.dim(); ++d) {
          if (at[d] < 0 || at[d] > 1) R.fail(path + ".at", pr[k]["at"], "parametric coordinates must lie in [0, 1]");
          p.at[d] = at[d];
        }
        P.output.probes.push_back(p);
      }
    }
  }

  P.linear.dofs_per_node = P.dim();
  choose_linear_method(R, root, P);

  check_problem(R, root, P);
  return P;
}

}  // namespace

using namespace detail;

Problem parse_problem(const std::string& text, const std::string& file, const std::vector<std::string>& overrides) {
  Reader R;
  R.file = file;
  R.memory_bytes = available_memory_bytes();
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    std::ostringstream os;
    os << file << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": YAML syntax error: " << e.msg;
    // YAML forbids tabs in indentation; yaml-cpp says "illegal map value" or the like there
    {
      std::istringstream lines(text);
      std::string l;
      for (int n = 1; std::getline(lines, l); ++n) {
        const size_t first = l.find_first_not_of(" \t");
        if (l.find('\t') < first || (first == std::string::npos && l.find('\t') != std::string::npos)) {
          os << " (line " << n << " is indented with a tab: YAML allows spaces only)";
          break;
        }
      }
    }
    throw InputError(printable(os.str()));
  }
  try {
    check_duplicate_keys(R, root, "");
    for (const auto& ov : overrides) apply_override(file, root, ov, R.overrides);
    return build(R, root);
  } catch (const InputError& e) {
    throw InputError(printable(e.what()));
  } catch (const YAML::Exception& e) {
    std::ostringstream os;
    os << file << ":" << e.mark.line + 1 << ": " << e.msg;
    throw InputError(printable(os.str()));
  }
}

Problem load_problem(const std::string& file, const std::vector<std::string>& overrides) {
  // Only a regular file of a sane size: a folder, a device (/dev/zero) or a fifo is refused
  // before anything is read.
  std::error_code ec;
  const auto st = std::filesystem::status(file, ec);
  if (ec || !std::filesystem::exists(st)) throw InputError(printable(file + ": cannot open the problem file"));
  if (std::filesystem::is_directory(st)) throw InputError(printable(file + ": the problem file is a directory"));
  if (!std::filesystem::is_regular_file(st)) throw InputError(printable(file + ": the problem file is not a regular file"));
  const auto size = std::filesystem::file_size(file, ec);
  if (!ec && size > kMaxProblemFileBytes)
    throw InputError(printable(file + ": the problem file has " + std::to_string(size) + " bytes, more than the " +
                               std::to_string(kMaxProblemFileBytes) + " a problem file may have"));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(printable(file + ": cannot open the problem file"));
  // read what is there, up to one byte past the limit (a file that grew after the size check),
  // in blocks: a buffer of the limit's size up front made the kernel zero 64 MiB of fresh pages
  // for a 1 kB file (0.015-0.2 s of "0) Read problem")
  std::string text;
  char block[1 << 16];
  while (text.size() <= kMaxProblemFileBytes && in.read(block, sizeof block).gcount() > 0)
    text.append(block, static_cast<size_t>(in.gcount()));
  if (text.size() > kMaxProblemFileBytes) throw InputError(printable(file + ": the problem file is larger than " +
                                                                     std::to_string(kMaxProblemFileBytes) + " bytes"));
  return parse_problem(text, file, overrides);
}

}  // namespace iga
