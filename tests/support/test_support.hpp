// Shared helpers for the test executables.
#pragma once

#include <string>

namespace penumbra::test {

/// Absolute path of a file under tests/data.
std::string data_path(const std::string& relative);

}  // namespace penumbra::test
