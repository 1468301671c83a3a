// write_shortest writes what std::to_chars writes (the CSV rows' bytes before it) and reads back
// to the same double: over every binade, both neighbours of every power of 2, decimals of 1 to 17
// digits over the exponents where fixed and scientific forms trade places, integers, and random
// bit patterns (seeded).
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include "experiments/output/shortest.hpp"
#include "test_support.hpp"

namespace lgvi::experiments {
namespace {

/// Empty when write_shortest(x) equals std::to_chars(x) and reads back to x; else both texts.
std::string mismatch(double x) {
  char expected[64];
  char written[kShortestRoom + 8];
  const char* want_end = std::to_chars(expected, expected + 64, x).ptr;
  const std::string_view want(expected, static_cast<std::size_t>(want_end - expected));
  const char* end = write_shortest(written, x);
  const std::string_view got(written, static_cast<std::size_t>(end - written));
  if (got == want && got.size() <= kShortestMaxChars &&
      (std::isnan(x) || std::bit_cast<std::uint64_t>(std::strtod(std::string(got).c_str(), nullptr)) ==
                            std::bit_cast<std::uint64_t>(x))) {
    return {};
  }
  return "to_chars " + std::string(want) + ", write_shortest " + std::string(got);
}

#define EXPECT_AS_TO_CHARS(x)                  \
  do {                                         \
    const double value_ = (x);                 \
    EXPECT_EQ(mismatch(value_), "") << value_; \
  } while (0)

TEST(WriteShortest, SpecialValuesAndLimits) {
  constexpr auto lim = std::numeric_limits<double>();
  for (const double x : {0.0, -0.0, 1.0, -1.0, 0.1, 0.5, 2.0, 10.0, 100.0, 1e15, 1e16, 1e21, 1e22, 1e23, 1e-5, 1e-4,
                         1.5e-4, 1.25e-3, 0.3333333333333333, 6.02214076e23, -2.2250738585072014e-308,
                         lim.min(), lim.max(), lim.lowest(), lim.denorm_min(), lim.epsilon(), lim.infinity(),
                         -lim.infinity(), lim.quiet_NaN(), 4503599627370496.0, 4503599627370495.5,
                         9007199254740991.0, 9007199254740992.0, 123456789012345680.0}) {
    EXPECT_AS_TO_CHARS(x);
    EXPECT_AS_TO_CHARS(-x);
  }
}

TEST(WriteShortest, PowersOfTwoAndTheirNeighbours) {
  // A power of 2 has an interval half as wide below it (the three-quarters branch).
  for (int e = -1074; e <= 1023; ++e) {
    const double x = std::ldexp(1.0, e);
    EXPECT_AS_TO_CHARS(x);
    EXPECT_AS_TO_CHARS(std::nextafter(x, 0.0));
    EXPECT_AS_TO_CHARS(std::nextafter(x, 2.0 * x));
  }
}

TEST(WriteShortest, DecimalsOfEveryLengthAndTheirNeighbours) {
  std::mt19937_64 rng = test::make_rng(35);
  for (int digits = 1; digits <= 17; ++digits) {
    std::uint64_t modulus = 1;
    for (int i = 0; i < digits; ++i) modulus *= 10;
    for (int exponent = -40; exponent <= 40; ++exponent) {
      for (int i = 0; i < 200; ++i) {
        const std::string text = std::to_string(rng() % modulus) + "e" + std::to_string(exponent);
        const double x = std::strtod(text.c_str(), nullptr);
        EXPECT_AS_TO_CHARS(x);
        EXPECT_AS_TO_CHARS(-x);
        EXPECT_AS_TO_CHARS(std::nextafter(x, 0.0));
        EXPECT_AS_TO_CHARS(std::nextafter(x, 1e300));
      }
    }
  }
}

TEST(WriteShortest, IntegersAndGridTimes) {
  std::mt19937_64 rng = test::make_rng(36);
  for (int k = 0; k <= 200000; ++k) {
    EXPECT_AS_TO_CHARS(static_cast<double>(k));
    EXPECT_AS_TO_CHARS(1e-3 * k);  // the times of a run's rows
    EXPECT_AS_TO_CHARS(static_cast<double>(rng() >> 11));  // below 2^53
  }
}

TEST(WriteShortest, RandomBitPatterns) {
  std::mt19937_64 rng = test::make_rng(37);
  for (int i = 0; i < 2000000; ++i) EXPECT_AS_TO_CHARS(std::bit_cast<double>(rng()));
}

}  // namespace
}  // namespace lgvi::experiments
