// The message of the Error a call throws: what the scene-format tests compare their one-line
// errors with.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.hpp"

namespace penumbra::test {

/// The message of the Error that `fn` throws ("" and a test failure if it throws none).
template <typename Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected penumbra::Error";
  return "";
}

}  // namespace penumbra::test
