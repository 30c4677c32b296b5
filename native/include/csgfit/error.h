// Errors the user can act on.
#pragma once

#include <stdexcept>
#include <string>

namespace csgfit {

/// Bad input or options: the message is one line that names the problem (and the file), meant
/// to be shown to the user as it is. The CLI prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace csgfit
