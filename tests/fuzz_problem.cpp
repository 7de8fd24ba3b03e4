// libFuzzer target for the problem-file loader: any input must either load or raise the
// one-line InputError; anything else (a crash, another exception, a sanitizer report) fails.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "model/problem.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // refinement is kept small by IGACONTACT_MEMORY_LIMIT (tests/fuzz_loader.sh sets 1e8 bytes)
    iga::parse_problem(text, "fuzz.yaml", {});
  } catch (const iga::InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind("fuzz.yaml", 0) != 0 || msg.find('\n') != std::string::npos) std::abort();
  } catch (const std::bad_alloc&) {
    // a huge but valid refinement request
  }
  return 0;
}
