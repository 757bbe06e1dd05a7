// User-facing errors: bad input, bad options. The CLI prints what() on one line and exits 1.
#pragma once

#include <stdexcept>
#include <string>

namespace penumbra {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace penumbra
