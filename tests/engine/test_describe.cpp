// Numbers in messages (billiard/describe.hpp): the shortest text that reads back as the same
// double, so that a message quotes exactly the refused value.
#include "billiard/describe.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <limits>
#include <random>

namespace {

using billiard::describe;
using billiard::number_text;

// Significant digits of a number's text: the digits of its mantissa after leading zeros.
int significant_digits(const std::string& text) {
  int count = 0;
  bool leading = true;
  for (char c : text.substr(0, text.find('e'))) {
    if (c < '0' || c > '9') continue;
    if (leading && c == '0') continue;
    leading = false;
    ++count;
  }
  return count;
}

TEST(Describe, ShortNumbersStayShort) {
  EXPECT_EQ(number_text(0.1), "0.1");
  EXPECT_EQ(number_text(-2.0), "-2");
  EXPECT_EQ(number_text(1e60), "1e+60");
  EXPECT_EQ(number_text(1000), "1000");
  EXPECT_EQ(number_text(123456), "123456");
  EXPECT_EQ(number_text(1e6), "1e+06");
  EXPECT_EQ(number_text(2500.5), "2500.5");
  EXPECT_EQ(number_text(1e-50), "1e-50");
  EXPECT_EQ(number_text(-0.0), "-0");
  EXPECT_EQ(number_text(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(number_text(std::numeric_limits<double>::denorm_min()), "5e-324");
}

TEST(Describe, EveryNumberReadsBackExactly) {
  EXPECT_EQ(number_text(1.0 / 3), "0.3333333333333333");
  EXPECT_EQ(number_text(0.1 + 0.2), "0.30000000000000004");  // not 0.3: the value refused is not 0.3
  std::mt19937_64 rng(1);
  std::uniform_int_distribution<std::uint64_t> bits;
  for (int k = 0; k < 20000; ++k) {
    const std::uint64_t word = bits(rng);
    double x;
    std::memcpy(&x, &word, sizeof x);
    if (!std::isfinite(x)) continue;
    const std::string text = number_text(x);
    ASSERT_EQ(std::strtod(text.c_str(), nullptr), x) << text;
    // Shortest: with one significant digit fewer it would not read back (whole numbers below a
    // million are written out in full instead).
    const int digits = significant_digits(text);
    if (digits > 1 && !(std::abs(x) >= 1 && std::abs(x) < 1e6)) {
      char shorter[400];  // (%g never needs more than 25; the compiler cannot tell)
      std::snprintf(shorter, sizeof shorter, "%.*g", digits - 1, x);
      ASSERT_NE(std::strtod(shorter, nullptr), x) << text << " could be " << shorter;
    }
  }
}

TEST(Describe, PointsAndPartsMakeOneMessage) {
  EXPECT_EQ(describe("disc ", 3, " at ", billiard::Vector(0.5, -1e-7), ": radius ", 0.25), "disc 3 at (0.5, -1e-07): radius 0.25");
  EXPECT_EQ(describe("g = ", billiard::Vector(0, -9.81)), "g = (0, -9.81)");
}

}  // namespace
