// SPDX-License-Identifier: MIT
#include "dsm/util/parse.h"

#include <limits>

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

TEST(ParseTimestampNs, ExactForNanosecondsAndSeconds) {
  EXPECT_EQ(ParseTimestampNs("1403636584763555584", 1, "t"), 1403636584763555584LL);
  EXPECT_EQ(ParseTimestampNs("1403636584.763555584", 1000000000, "t"), 1403636584763555584LL);
  EXPECT_EQ(ParseTimestampNs("1311868164.363181", 1000000000, "t"), 1311868164363181000LL);
  EXPECT_EQ(ParseTimestampNs("0.5", 1000000000, "t"), 500000000LL);
  EXPECT_EQ(ParseTimestampNs("12", 1000000000, "t"), 12000000000LL);
  EXPECT_EQ(ParseTimestampNs("-1.25", 1000000000, "t"), -1250000000LL);
  // Sub-nanosecond digits round.
  EXPECT_EQ(ParseTimestampNs("1.0000000016", 1000000000, "t"), 1000000002LL);
}

TEST(ParseTimestampNs, ScientificNotation) {
  EXPECT_EQ(ParseTimestampNs("1.403715529112143517e+09", 1000000000, "t"), 1403715529112143517LL);
}

TEST(ParseTimestampNs, RejectsGarbageNamingTheLocation) {
  try {
    ParseTimestampNs("12a.3", 1, "file.csv:7");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("file.csv:7"), std::string::npos);
  }
  EXPECT_THROW(ParseTimestampNs("", 1, "x"), InputError);
  EXPECT_THROW(ParseTimestampNs(".", 1, "x"), InputError);
  EXPECT_THROW(ParseTimestampNs("99999999999999999999", 1, "x"), InputError);
}

TEST(ParseTimestampNs, TheLargestStampsFitAndOneMoreFails) {
  EXPECT_EQ(ParseTimestampNs("9223372036.854775807", 1000000000, "t"), std::numeric_limits<int64_t>::max());
  EXPECT_EQ(ParseTimestampNs("-9223372036.854775807", 1000000000, "t"), -std::numeric_limits<int64_t>::max());
  // The integer part alone fits; with the fraction it does not (found by fuzz/trajectory).
  EXPECT_THROW(ParseTimestampNs("9223372036.9", 1000000000, "x"), InputError);
  EXPECT_THROW(ParseTimestampNs("9223372036.8547758075", 1000000000, "x"), InputError);
}

TEST(FormatSeconds, NineDecimals) {
  EXPECT_EQ(FormatSeconds(1403636584763555584LL), "1403636584.763555584");
  EXPECT_EQ(FormatSeconds(5), "0.000000005");
  EXPECT_EQ(FormatSeconds(-1500000000LL), "-1.500000000");
}

TEST(ParseDouble, AcceptsNumbersRejectsRest) {
  EXPECT_DOUBLE_EQ(ParseDouble(" 4.5e-3 ", "x"), 4.5e-3);
  EXPECT_THROW(ParseDouble("nan", "x"), InputError);
  EXPECT_THROW(ParseDouble("1.5x", "x"), InputError);
  EXPECT_EQ(ParseInt("42", "x"), 42);
  EXPECT_THROW(ParseInt("4.2", "x"), InputError);
}

TEST(SplitFields, SkipsEmptyFields) {
  const auto f = SplitFields("a, b,,c\t d");
  ASSERT_EQ(f.size(), 4u);
  EXPECT_EQ(f[0], "a");
  EXPECT_EQ(f[3], "d");
}

}  // namespace
}  // namespace dsm
