// Loads libigacontact_amg.so (solver/amg.hpp) the first time a multigrid preconditioner is
// built: from the program's own folder (build/bin, where CMake puts both), else by the
// dynamic loader's search path (LD_LIBRARY_PATH).
#include "solver/amg_loader.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <mutex>
#include <stdexcept>

namespace iga {

namespace {

constexpr const char* kModuleName = "libigacontact_amg.so";

struct Loaded {
  void* handle = nullptr;
  std::string path;
  std::string error;
};

const Loaded& load() {
  static Loaded loaded;
  static std::once_flag once;
  std::call_once(once, [] {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    loaded.path = ec ? kModuleName : (exe.parent_path() / kModuleName).string();
    // RTLD_GLOBAL: MueLu's and hypre's libraries join the program's (one copy of Tpetra's
    // and Kokkos' symbols and type information for both)
    loaded.handle = dlopen(loaded.path.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (!loaded.handle) {
      loaded.error = dlerror();
      loaded.handle = dlopen(kModuleName, RTLD_NOW | RTLD_GLOBAL);
      if (loaded.handle) loaded.path = kModuleName;
    }
  });
  return loaded;
}

}  // namespace

void* amg_module_symbol(const char* symbol) {
  const Loaded& l = load();
  const std::string advice =
      "; keep it beside the program, or choose solver.linear.method: direct or "
      "solver.linear.preconditioner: ilut";
  if (!l.handle)
    throw std::runtime_error("the multigrid preconditioners (BoomerAMG, MueLu) are in " + l.path +
                             ", which could not be loaded (" + l.error + ")" + advice);
  void* s = dlsym(l.handle, symbol);
  if (!s) throw std::runtime_error(l.path + " has no " + symbol + ": a module of another igacontact build" + advice);
  return s;
}

Teuchos::RCP<const Teuchos::ParameterList> muelu_master_list() {
  using Entry = Teuchos::RCP<const Teuchos::ParameterList> (*)();
  return reinterpret_cast<Entry>(amg_module_symbol("igacontact_muelu_master_list"))();
}

}  // namespace iga
