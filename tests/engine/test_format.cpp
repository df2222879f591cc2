// The one number formatter (engine/core/format.hpp): every layer writes its
// numbers with it, so its texts are those that printf and std::to_chars
// wrote where each user had its own formatter (the users' outputs stay as
// they were).
#include "core/format.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

using namespace wiredem::engine;

namespace {

std::string printf_text(const char* format, int precision, double v)
{
    char buf[512];
    std::snprintf(buf, sizeof buf, format, precision, v);
    return buf;
}

const std::vector<double> values{0.0, -0.0, 0.1, 1.0 / 3.0, 2.5e-5, 1.88e-7, 20000.0, -123456.789, 0.05, 99.95,
    0.5, 1.5, 2.5, 1e308, -1e-308, 4.9e-324, std::numeric_limits<double>::max(),
    std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
    std::numeric_limits<double>::quiet_NaN()};

} // namespace

TEST(NumberText, SignificantDigitsAreWhatPercentGWrites)
{
    for (const double v : values)
        for (const int digits : {1, 2, 3, 4, 6, 9, 17}) EXPECT_EQ(format_number(v, digits), printf_text("%.*g", digits, v)) << v;
    EXPECT_EQ(format_number(1.88e-7), "1.88e-07");
    EXPECT_EQ(format_number(20000.0), "2e+04");
}

TEST(NumberText, FixedDecimalsAreWhatPercentFWrites)
{
    for (const double v : values)
        for (const int decimals : {0, 1, 2, 3, 5}) EXPECT_EQ(fixed_number(v, decimals), printf_text("%.*f", decimals, v)) << v;
    EXPECT_EQ(fixed_number(99.6, 0), "100");
    EXPECT_EQ(fixed_number(0.05, 3), "0.050");
    // The largest double in full: 309 digits before the point, and the decimals.
    EXPECT_EQ(fixed_number(std::numeric_limits<double>::max(), 2).size(), 309u + 3u);
}

TEST(NumberText, ExactTextReadsBackAsTheSameDouble)
{
    for (const double v : values) {
        if (v != v) continue; // NaN reads back as NaN, not as itself
        const std::string text = exact_number(v);
        double back = 0.0;
        const auto r = std::from_chars(text.data(), text.data() + text.size(), back);
        if (std::isinf(v)) {
            EXPECT_EQ(text, v > 0 ? "inf" : "-inf");
            continue;
        }
        ASSERT_EQ(r.ec, std::errc()) << text;
        EXPECT_EQ(back, v) << text;
        EXPECT_EQ(std::signbit(back), std::signbit(v)) << text;
    }
    EXPECT_EQ(exact_number(0.1), "0.1");
    EXPECT_EQ(exact_number(2.5e-5), "2.5e-05");
}
