// Bad input answered by a clear one-line error or a documented fallback: option parsing, message
// quoting, special files, malformed mesh headers, non-finite geometry, extreme scales.
#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/core/suggest.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const MethodInfo& method(const char* name) {
  return MethodRegistry::builtin().get(name);
}

// Integers are parsed once, whole string, base 10: a hex or exponent spelling is refused instead
// of being validated by one parser and read by another (0x10 once crashed ssm, 0x20 hung gears,
// 1e3 silently became 1).
TEST(OptionParsing, IntegersAreWholeStringBase10) {
  for (const char* bad : {"0x10", "1e3", "16.0", " 16", "16 ", "+16", "", "16abc"}) {
    const std::string e = error_of([&] { resolve_options(method("ssm"), {{"resolution", bad}}); });
    EXPECT_NE(e.find("is not a base-10 integer"), std::string::npos) << bad << ": " << e;
  }
  const MethodOptions o = resolve_options(method("ssm"), {{"resolution", "0128"}});
  EXPECT_EQ(o.get_int("resolution"), 128);
  EXPECT_EQ(o.values().at("resolution"), "128");  // the parsed value is what stats.json records
  EXPECT_NE(error_of([&] { resolve_options(method("gears"), {{"chunk", "0x20"}}); }), "");
  EXPECT_NE(error_of([&] { resolve_options(method("shadow_map"), {{"resolution", "1e3"}}); }), "");
  EXPECT_NE(error_of([&] {
              resolve_options(method("ssm"), {{"resolution", "99999999999999999999"}});
            }).find("not a base-10 integer"),
            std::string::npos);
}

TEST(OptionParsing, RealsAreFiniteAndStoredParsed) {
  const MethodOptions o = resolve_options(method("shadow_map"), {{"bias", "1e-3"}});
  EXPECT_DOUBLE_EQ(o.get_real("bias"), 1e-3);
  EXPECT_EQ(o.values().at("bias"), "0.001");
  for (const char* bad : {"nan", "inf", "0x1p-3", "1e400", "1,5", ""})
    EXPECT_NE(error_of([&] { resolve_options(method("shadow_map"), {{"bias", bad}}); }), "") << bad;
}

TEST(OptionParsing, RangeIsCheckedOnTheParsedValue) {
  const std::string e = error_of([&] { resolve_options(method("ssm"), {{"resolution", "1"}}); });
  EXPECT_NE(e.find("is outside ["), std::string::npos) << e;
}

TEST(Messages, QuoteEscapesControlCharactersAndCutsLongStrings) {
  EXPECT_EQ(quote("fov\nPWNED"), "'fov\\nPWNED'");
  EXPECT_EQ(quote("a\x1b[2Jb"), "'a\\x1b[2Jb'");
  const std::string huge(3'000'000, 'x');
  const std::string q = quote(huge);
  EXPECT_LT(q.size(), 120u);
  EXPECT_NE(q.find("3000000 bytes"), std::string::npos);
  const std::string line = one_line("first\nsecond" + huge);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_LT(line.size(), 700u);
}

TEST(Messages, DidYouMean) {
  EXPECT_EQ(nearest_name("exct", {"exact", "raytrace"}), "exact");
  EXPECT_EQ(nearest_name("quadd", {"quad", "spheres"}), "quad");
  EXPECT_EQ(nearest_name("zzzzzz", {"quad", "spheres"}), "");
  const std::string e = error_of([] { MethodRegistry::builtin().get("raytrac"); });
  EXPECT_NE(e.find("did you mean 'raytrace'?"), std::string::npos) << e;
}

}  // namespace
}  // namespace penumbra
