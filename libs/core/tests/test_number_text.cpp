#include <icrkit/core/length.hpp>
#include <icrkit/core/number_text.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <locale>
#include <string>
#include <vector>

using namespace icrkit;

TEST(NumberText, FixedDecimals) {
  EXPECT_EQ(formatFixed(12.3456, 2), "12.35");
  EXPECT_EQ(formatFixed(0.25, 1), "0.2") << "exact halves round to even";
  EXPECT_EQ(formatFixed(-1.5, 0), "-2");
  EXPECT_EQ(formatFixed(7.0, 3), "7.000");
  EXPECT_EQ(formatFixed(1.0, -4), "1") << "negative decimals mean none";
  EXPECT_EQ(formatFixed(std::numeric_limits<double>::max(), 100).size(), 309u + 1u + 100u) << "no overflow";
}

TEST(NumberText, ShortestRoundTrips) {
  EXPECT_EQ(formatShortest(0.1), "0.1");
  EXPECT_EQ(formatShortest(1e-7), "1e-07");
  EXPECT_EQ(formatShortest(-42.0), "-42");
  const double third = 1.0 / 3.0;
  EXPECT_EQ(std::stod(formatShortest(third)), third);
}

namespace {
// A decimal comma, as many users' locales have, without needing one installed.
struct DecimalComma : std::numpunct<char> {
  char do_decimal_point() const override { return ','; }
};
}  // namespace

TEST(NumberText, IgnoresTheGlobalLocale) {
  const std::locale previous = std::locale::global(std::locale(std::locale::classic(), new DecimalComma));
  const std::string fixed = formatFixed(0.5, 1);
  const std::string shortest = formatShortest(0.5);
  const Length length = parseLength("test", "0.5x");
  std::locale::global(previous);
  EXPECT_EQ(fixed, "0.5");
  EXPECT_EQ(shortest, "0.5");
  EXPECT_EQ(length.value, 0.5);
  EXPECT_TRUE(length.relative);
}

TEST(Length, ParsesMetresAndSpacings) {
  EXPECT_EQ(parseLength("--radius", "0.004"), Length::metres(0.004));
  EXPECT_EQ(parseLength("--radius", "4x"), Length::spacings(4.0));
  EXPECT_EQ(parseLength("--radius", "2.5X"), Length::spacings(2.5));
  EXPECT_DOUBLE_EQ(Length::spacings(4.0).metresFor(0.001), 0.004);
  EXPECT_DOUBLE_EQ(Length::metres(0.003).metresFor(0.5), 0.003);
  EXPECT_EQ(formatLength(Length::spacings(1.5)), "1.5x");
  EXPECT_EQ(formatLength(Length::metres(0.004)), "0.004");
  EXPECT_TRUE(Length::metres(1e-9).valid());
  EXPECT_FALSE(Length::metres(0.0).valid());
  EXPECT_FALSE(Length::spacings(std::numeric_limits<double>::infinity()).valid());
  const std::vector<Length> radii = parseLengths("--radii", "1.5x,2.5x");
  ASSERT_EQ(radii.size(), 2u);
  EXPECT_EQ(radii[1], Length::spacings(2.5));
}

TEST(Length, RefusesWhatIsNotALength) {
  for (const char* bad : {"", "x", "4y", "abc", "nan", "1e999", "4xx"})
    EXPECT_EQ(test::expectInputError([&] { parseLength("--radius", bad); }).source(), "--radius") << bad;
  for (const char* bad : {"0", "-1", "0x", "-2x"})
    EXPECT_NE(std::string(test::expectInputError([&] { parseLength("--radius", bad); }).what()).find("positive"),
              std::string::npos)
        << bad;
  EXPECT_NE(
      std::string(test::expectInputError([&] { parseLengths("--radii", "2x,0.004"); }).what()).find("all as multiples"),
      std::string::npos);
  EXPECT_EQ(test::expectInputError([&] { parseLengths("--radii", ""); }).source(), "--radii");
}
