// What wiredem writes as JSON is JSON: a number that is not finite becomes
// null wherever it sits, and every other value is written as it was.
#include "api/json_text.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <limits>

namespace json = boost::json;
using wiredem::api::json_document_text;
using wiredem::api::parse_json_text;

TEST(JsonDocumentText, NumbersThatAreNotFiniteAreNullWhereverTheySit)
{
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    json::object doc;
    doc["nan"] = nan;
    doc["tests"] = json::array{json::object{{"peak", -inf}, {"steps", 12}}, 0.5, json::array{inf, 1.25}};
    doc["name"] = "NaN";
    const std::string text = json_document_text(doc);
    const auto parsed = parse_json_text(text);
    ASSERT_TRUE(parsed.ok()) << parsed.error() << " in " << text;
    const json::value& v = parsed.value();
    EXPECT_TRUE(v.at("nan").is_null());
    EXPECT_TRUE(v.at("tests").at(0).at("peak").is_null());
    EXPECT_EQ(v.at("tests").at(0).at("steps"), 12);
    EXPECT_EQ(v.at("tests").at(1), 0.5);
    EXPECT_TRUE(v.at("tests").at(2).at(0).is_null());
    EXPECT_EQ(v.at("tests").at(2).at(1), 1.25);
    EXPECT_EQ(v.at("name"), "NaN");
}

TEST(JsonDocumentText, AFiniteDocumentIsWrittenAsBoostWritesIt)
{
    const json::value doc = json::object{{"x", 0.1}, {"big", 1e308}, {"tiny", 5e-324}, {"list", json::array{1, -2, 3.5}}};
    EXPECT_EQ(json_document_text(doc), json::serialize(doc));
    EXPECT_EQ(parse_json_text(json_document_text(doc)).value(), doc);
}
