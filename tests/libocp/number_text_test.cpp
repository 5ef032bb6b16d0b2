// Strict number checks for command-line values (number_text.hpp): NaN, infinities, signs on
// unsigned values, empty and trailing text never pass.
#include <gtest/gtest.h>

#include "ocp/number_text.hpp"

namespace ocp {
namespace {

TEST(NumberText, FiniteNumbersOnly) {
  EXPECT_EQ(parse_finite_number("20"), 20.0);
  EXPECT_EQ(parse_finite_number("0.5"), 0.5);
  EXPECT_EQ(parse_finite_number("1e3"), 1000.0);
  EXPECT_EQ(parse_finite_number("-3"), -3.0);
  for (const char* bad : {"nan", "NaN", "-nan", "inf", "-inf", "infinity", "", " 1", "1 ", "+1", "1x", "0x10", "1e999"}) {
    EXPECT_FALSE(parse_finite_number(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(NumberText, UnsignedIsDigitsOnly) {
  EXPECT_EQ(parse_unsigned_number("18446744073709551615"), 18446744073709551615ULL);
  for (const char* bad : {"-1", "+1", "", "18446744073709551616", "1.0", "nan", " 1"}) {
    EXPECT_FALSE(parse_unsigned_number(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(NumberText, ChecksNameTheRangeAndTheValue) {
  EXPECT_EQ(check_real_text("60", 0, 60'000), std::nullopt);
  EXPECT_EQ(check_real_text("nan", 0, 60'000), "expected a number in 0..60000, got 'nan'");
  EXPECT_EQ(check_real_text("", 0, 1), "expected a number in 0..1, got an empty value");
  EXPECT_NE(check_real_text("-1", 0, 1), std::nullopt);
  EXPECT_NE(check_positive_real_text("0", 10), std::nullopt);
  EXPECT_EQ(check_positive_real_text("0.001", 10), std::nullopt);
  EXPECT_EQ(check_unsigned_text("-1", 0, 5), "expected a whole number in 0..5, got '-1'");
}

}  // namespace
}  // namespace ocp
