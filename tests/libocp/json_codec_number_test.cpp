// The codec's doubles. The encoder's short-decimal path (JsonWriter::short_decimal) must write
// exactly what the shortest round-trip std::to_chars writes, for the decimals it takes and for
// every double it declines, and what it writes must read back to the same double. The
// decoder's (Clinger's fast path, else from_chars) must read every number as from_chars does.
#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>

#include "json_codec_writer.hpp"
#include "ocp/json_codec.hpp"

namespace {

// What the encoder wrote for `value`, and to_chars's shortest text (with ".0" after a whole
// number, as the encoder keeps doubles visibly floating point).
std::string written(double value) {
  std::string out;
  {
    ocp::json_detail::JsonWriter writer(out);
    writer.number(value);
  }
  return out;
}

std::string shortest(double value) {
  char buffer[40];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
  std::string text(buffer, end);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

void expect_same(double value) {
  const std::string ours = written(value);
  ASSERT_EQ(ours, shortest(value)) << "value bits " << std::bit_cast<std::uint64_t>(value);
  double back = 0.0;
  std::from_chars(ours.data(), ours.data() + ours.size(), back);
  ASSERT_EQ(std::bit_cast<std::uint64_t>(back), std::bit_cast<std::uint64_t>(value)) << ours;
}

TEST(JsonCodecNumber, ShortDecimalsAsToChars) {
  for (const double value : {57.7089, 11.9746, -0.25, 0.1, -0.1, 0.5, 0.999, 1.4, 9999.5,
                             123456.789, 0.30000000000000004, 0.1 + 0.2, 1e14 + 0.5, 0.12345678901234,
                             999999999999999.9, 0.09999999999999999, 2.5e-1, 1.0 / 3.0}) {
    expect_same(value);
    expect_same(-value);
  }
}

TEST(JsonCodecNumber, RandomDecimalsOfOneToFifteenFractionDigitsAsToChars) {
  std::mt19937_64 random(20261127);
  for (int fraction_digits = 1; fraction_digits <= 15; ++fraction_digits) {
    std::uniform_int_distribution<std::uint64_t> digits(1, 999'999'999'999'999ULL);
    for (int i = 0; i < 20'000; ++i) {
      const std::string text = std::to_string(digits(random));
      const std::string decimal =
          text.size() > static_cast<std::size_t>(fraction_digits)
              ? text.substr(0, text.size() - static_cast<std::size_t>(fraction_digits)) + "." +
                    text.substr(text.size() - static_cast<std::size_t>(fraction_digits))
              : "0." + std::string(static_cast<std::size_t>(fraction_digits) - text.size(), '0') + text;
      double value = 0.0;
      std::from_chars(decimal.data(), decimal.data() + decimal.size(), value);
      expect_same(value);
    }
  }
}

TEST(JsonCodecNumber, RandomDoublesAsToChars) {
  std::mt19937_64 random(41);
  for (int i = 0; i < 200'000; ++i) {
    const double value = std::bit_cast<double>(random());
    if (!std::isfinite(value)) continue;
    expect_same(value);
  }
  std::uniform_real_distribution<double> near_one(-2.0, 2.0);
  for (int i = 0; i < 200'000; ++i) expect_same(near_one(random));
}

TEST(JsonCodecNumber, NonFiniteIsNullAndNegativeZeroKeepsItsSign) {
  EXPECT_EQ(written(std::nan("")), "null");
  EXPECT_EQ(written(INFINITY), "null");
  EXPECT_EQ(written(-0.0), "-0.0");
  EXPECT_EQ(written(-1.0), "-1.0");
  EXPECT_EQ(written(1e300), shortest(1e300));
}

TEST(JsonCodecNumber, WriterGrowsPastItsBuffer) {
  std::string out;
  {
    ocp::json_detail::JsonWriter writer(out);
    for (int i = 0; i < 1000; ++i) writer.number(57.7089 + i);
  }
  std::string expected;
  for (int i = 0; i < 1000; ++i) expected += shortest(57.7089 + i);
  EXPECT_EQ(out, expected);
}

// lat read by the decoder against from_chars, bit for bit.
void expect_read_as_from_chars(const std::string& number) {
  const std::string text = R"({"ack_time":1,"ack_time_mac":2,"vehicle_user_data":{"pos":{"lat":)" + number +
                           R"(,"lon":0.5},"user_data":null}})";
  const auto decoded = ocp::decode_vehicle_response(text);
  ASSERT_TRUE(decoded.ok()) << number;
  double expected = 0.0;
  std::from_chars(number.data(), number.data() + number.size(), expected);
  ASSERT_EQ(std::bit_cast<std::uint64_t>(decoded->vehicle_user_data->pos->lat), std::bit_cast<std::uint64_t>(expected))
      << number;
}

TEST(JsonCodecNumber, DecimalsReadAsFromChars) {
  for (const char* number : {"0", "-0", "-0.0", "57.7089", "9007199254740992", "9007199254740993", "0.1",
                             "0.0000000000000000000001", "1234567890123456789", "12345678901234567890",
                             "4.35", "-1.5e3", "1E-7", "0.30000000000000004", "9007199254740993.5"}) {
    expect_read_as_from_chars(number);
  }
  std::mt19937_64 random(7);
  for (int i = 0; i < 100'000; ++i) {
    const std::string digits = std::to_string(random() >> (random() % 64));
    const std::size_t point = random() % (digits.size() + 1);
    std::string number = random() % 2 ? "-" : "";
    if (point == 0 || point >= digits.size()) {
      number += digits;
    } else {
      number += digits.substr(0, point);
      number += '.';
      number += digits.substr(point);
    }
    expect_read_as_from_chars(number);
  }
}

}  // namespace
