#pragma once
#include <stdexcept>

namespace iga {

/// Bad input: the message is one line naming the file, the key (or line) and the value.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace iga
