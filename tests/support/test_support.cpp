#include "support/test_support.hpp"

namespace penumbra::test {

std::string data_path(const std::string& relative) {
  return std::string(PENUMBRA_TEST_DATA) + "/" + relative;
}

}  // namespace penumbra::test
