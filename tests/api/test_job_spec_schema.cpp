// api::job_spec_json_schema: the reader describes itself. Checked against the
// writer (every field to_json writes, with the same default), against the
// reader (a value at a closed bound passes, one just outside fails, for every
// number and integer), and against the schema table of docs/job-spec.md
// (the same fields; the same unit and meaning; the same interval and default
// where the table gives a plain one): when one of them changes alone, a test
// here fails. Every field has a meaning, and every number its unit.
#include "api/job_spec.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

// GCC 12's <regex> warns of its own std::function members where this file
// instantiates it (-Wmaybe-uninitialized, a false positive in libstdc++) when
// built with the sanitizers' flags: off for the whole file.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <regex>

namespace wiredem::api {
namespace {
namespace json = boost::json;

/// Leaf fields of a schema object by dotted path.
void leaves(const json::object& schema, const std::string& prefix, std::map<std::string, json::object>& out)
{
    for (const auto& [key, field] : schema.at("properties").as_object()) {
        const std::string path = prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
        const json::object& f = field.as_object();
        if (auto t = f.find("type"); t != f.end() && t->value() == "object") leaves(f, path, out);
        else out[path] = f;
    }
}

std::map<std::string, json::object> schema_fields()
{
    std::map<std::string, json::object> out;
    leaves(job_spec_json_schema(), "", out);
    return out;
}

/// Sets `path` (dots) in a JSON object, making the objects on the way. The
/// base spec gives the damping directly and lays no wire: parsing it then
/// skips the restitution fit and the wire's checks (a quarter of a second
/// each), which the range checks do not need.
json::object with_field(const std::string& path, json::value v)
{
    json::object root{{"contact", json::object{{"normal_damping_s", 1e-5}}},
        {"specimen", json::object{{"wire", json::object{{"pattern", "none"}}}}}};
    json::object* node = &root;
    std::string_view rest = path;
    for (auto dot = rest.find('.'); dot != std::string_view::npos; dot = rest.find('.')) {
        json::value& child = (*node)[rest.substr(0, dot)];
        if (!child.is_object()) child.emplace_object();
        node = &child.as_object();
        rest.remove_prefix(dot + 1);
    }
    (*node)[rest] = std::move(v);
    return root;
}

/// Whether the reader refuses v at `path` as out of range (the checks across
/// fields may refuse an extreme value too, for another reason).
bool refused(const std::string& path, json::value v)
{
    const auto r = parse_job_spec(json::value(with_field(path, std::move(v))));
    if (r.ok()) return false;
    for (const auto& e : r.error())
        if ((e.path == path || e.path.rfind(path + "[", 0) == 0) && e.message.find("out of range") != std::string::npos)
            return true;
    return false;
}

TEST(JobSpecSchema, IsAnObjectSchemaThatRefusesUnknownKeys)
{
    const json::object s = job_spec_json_schema();
    EXPECT_EQ(s.at("$schema"), "https://json-schema.org/draft/2020-12/schema");
    EXPECT_EQ(s.at("type"), "object");
    EXPECT_EQ(s.at("additionalProperties"), false);
    EXPECT_EQ(s.at("properties").at("specimen").at("properties").at("wire").at("additionalProperties"), false);
    EXPECT_EQ(s.at("properties").at("specimen").at("properties").at("wire").at("properties").at("pattern").at("enum"),
        (json::array{"none", "helix", "spiral_helix", "radial_helix", "toolpath"}));
}

/// Whether a schema field takes numbers (a number, an integer, an array of
/// numbers, or a number or a word such as "auto").
bool is_quantity(const json::object& f)
{
    if (auto one = f.find("oneOf"); one != f.end()) return is_quantity(one->value().at(0).as_object());
    if (auto items = f.find("items"); items != f.end()) return is_quantity(items->value().as_object());
    const json::value& t = f.at("type");
    const auto is_numeric = [](const json::value& x) { return x == "number" || x == "integer"; };
    if (t.is_array()) return std::any_of(t.as_array().begin(), t.as_array().end(), is_numeric);
    return is_numeric(t);
}

TEST(JobSpecSchema, EveryFieldSaysWhatItMeansAndEveryNumberItsUnit)
{
    int quantities = 0;
    for (const auto& [path, f] : schema_fields()) {
        const auto d = f.find("description");
        EXPECT_TRUE(d != f.end() && d->value().is_string() && !d->value().as_string().empty()) << path << " has no description";
        const auto u = f.find("x-unit");
        if (is_quantity(f)) {
            ++quantities;
            EXPECT_TRUE(u != f.end() && u->value().is_string() && !u->value().as_string().empty())
                << path << " is a quantity without x-unit (\"1\" when it has none)";
        } else {
            EXPECT_TRUE(u == f.end()) << path << " is not a number but has a unit";
        }
    }
    EXPECT_GT(quantities, 45);
}

TEST(JobSpecSchema, HasEveryFieldTheWriterWritesWithTheSameDefault)
{
    const auto fields = schema_fields();
    std::map<std::string, json::value> written;
    std::function<void(const json::object&, const std::string&)> walk = [&](const json::object& o, const std::string& prefix) {
        for (const auto& [k, v] : o) {
            const std::string path = prefix.empty() ? std::string(k) : prefix + "." + std::string(k);
            if (v.is_object()) walk(v.as_object(), path);
            else written[path] = v;
        }
    };
    // free_standing is written only when it differs from its defaults
    // (job_spec.hpp): with the test asked for, every field but `enabled`
    // keeps its default.
    EXPECT_FALSE(to_json(JobSpec{}).as_object().contains("free_standing"));
    // So are a breaking strain and cuts (specimen.wire): set, they differ from their defaults.
    JobSpec with_test;
    with_test.free_standing.enabled = true;
    with_test.specimen.wire.breaking_strain = 0.1;
    with_test.specimen.wire.cuts_at_m = {0.5};
    with_test.specimen.wire.cut_every_loops = 2;
    // So are the cell and its box (triaxial): written for the cuboid cell only.
    EXPECT_FALSE(to_json(JobSpec{}).at("triaxial").as_object().contains("cell"));
    EXPECT_FALSE(to_json(JobSpec{}).at("triaxial").as_object().contains("cuboid"));
    with_test.triaxial.cell = CellKind::cuboid;
    // And a toolpath's points, with its pattern.
    with_test.specimen.wire.pattern = WirePattern::toolpath;
    with_test.specimen.wire.toolpath_x_m = {0.01, 0.0};
    with_test.specimen.wire.toolpath_y_m = {0.0, 0.01};
    walk(to_json(with_test).as_object(), "");
    for (const auto& [path, value] : written) {
        ASSERT_TRUE(fields.count(path)) << path << " is written but not in the schema";
        if (path == "free_standing.enabled" || path == "specimen.wire.breaking_strain"
            || path == "specimen.wire.cuts_at_m" || path == "specimen.wire.cut_every_loops"
            || path == "specimen.wire.pattern" || path == "specimen.wire.toolpath_x_m" || path == "specimen.wire.toolpath_y_m"
            || path == "triaxial.cell")
            continue;
        const json::value& d = fields.at(path).at("default");
        if (value.is_number() && d.is_number())
            EXPECT_EQ(value.to_number<double>(), d.to_number<double>()) << path;
        else
            EXPECT_EQ(value, d) << path;
    }
    // The writer leaves out the damping form not taken by default
    // (normal_damping_s), specimen.grain_shape while it is null and
    // specimen.grain_preset while it is none: written only when set, so that
    // every job of spheres writes what it did before (a preset's job is
    // JobSpecGrainPreset.IsWrittenAsItsNameAndReadsBackTheSameSpec).
    for (const auto& [path, f] : fields)
        if (!written.count(path)) {
            EXPECT_TRUE(path == "contact.normal_damping_s" || path == "specimen.grain_shape"
                || path == "specimen.grain_preset") << path;
        }
}

TEST(JobSpecSchema, TheReaderAcceptsEachBoundAndRefusesJustOutside)
{
    int checked = 0;
    for (const auto& [path, f0] : schema_fields()) {
        json::object f = f0;
        if (auto one = f.find("oneOf"); one != f.end()) f = one->value().at(0).as_object();
        if (auto items = f.find("items"); items != f.end()) {
            // An array of numbers: check its entries through a one-entry array.
            const json::object item = items->value().as_object();
            for (const char* bound : {"minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum"}) {
                if (!item.contains(bound)) continue;
                const double b = item.at(bound).to_number<double>();
                const bool low = bound[0] == 'm' ? std::string(bound) == "minimum" : std::string(bound) == "exclusiveMinimum";
                const double outside = std::nextafter(b, low ? -INFINITY : INFINITY);
                EXPECT_TRUE(refused(path, json::array{outside})) << path << " [" << outside << "]";
                ++checked;
            }
            continue;
        }
        for (const char* bound : {"minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"}) {
            if (!f.contains(bound)) continue;
            const bool integer = f.at("type") == "integer";
            const bool low = std::string(bound).find("inimum") != std::string::npos;
            const bool exclusive = std::string(bound).rfind("exclusive", 0) == 0;
            if (integer) {
                const std::uint64_t b = f.at(bound).to_number<std::uint64_t>();
                EXPECT_FALSE(refused(path, b)) << path << " = " << b;
                if (low && b > 0) {
                    EXPECT_TRUE(refused(path, b - 1)) << path << " = " << b - 1;
                }
                if (!low && b < UINT64_MAX) {
                    EXPECT_TRUE(refused(path, b + 1)) << path << " = " << b + 1;
                }
            } else {
                const double b = f.at(bound).to_number<double>();
                const double outside = std::nextafter(b, low ? -INFINITY : INFINITY);
                if (exclusive) {
                    EXPECT_TRUE(refused(path, b)) << path << " = " << b << " (excluded)";
                } else {
                    EXPECT_FALSE(refused(path, b)) << path << " = " << b;
                }
                EXPECT_TRUE(refused(path, outside)) << path << " = " << outside;
            }
            ++checked;
        }
    }
    EXPECT_GT(checked, 80);
}

/// "1e13", "−1", "10⁸", "2π", "π/2", "2⁶⁴ − 1" as numbers; nullopt for prose.
std::optional<double> docs_number(std::string t)
{
    for (auto [from, to] : std::initializer_list<std::pair<std::string, std::string>>{
             {"\u2212", "-"}, {"10\u2078", "1e8"}, {"10\u2079", "1e9"}, {"2\u2076\u2074 - 1", "18446744073709551615"}}) {
        for (auto p = t.find(from); p != std::string::npos; p = t.find(from)) t.replace(p, from.size(), to);
    }
    if (t == "2\u03c0") return 2 * M_PI;
    if (t == "\u03c0/2") return M_PI / 2;
    try {
        std::size_t used = 0;
        const double x = std::stod(t, &used);
        if (used == t.size()) return x;
    } catch (...) {
    }
    return std::nullopt;
}

// x-order (the web form's "allowed" column) says what the reader checks: an
// array of numbers with equal entries is refused as not strictly increasing
// exactly when its schema says "increasing".
TEST(JobSpecSchema, ArraysSayTheOrderTheReaderChecks)
{
    int ordered = 0, unordered = 0;
    for (const auto& [path, f] : schema_fields()) {
        const auto items = f.find("items");
        if (items == f.end() || !items->value().as_object().contains("maximum")) continue;
        const json::object& item = items->value().as_object();
        const double hi = item.at("maximum").to_number<double>();
        const double lo = item.contains("minimum") ? item.at("minimum").to_number<double>()
                                                   : item.at("exclusiveMinimum").to_number<double>();
        const double x = lo + 0.5 * (hi - lo);
        const std::size_t n = std::max<std::size_t>(2, f.at("minItems").to_number<std::size_t>());
        json::array same;
        for (std::size_t i = 0; i < n; ++i) same.push_back(x);
        const auto r = parse_job_spec(json::value(with_field(path, std::move(same))));
        bool refused_order = false;
        if (!r.ok())
            for (const auto& e : r.error())
                refused_order = refused_order || (e.path == path + "[1]" && e.message.find("strictly increasing") != std::string::npos);
        const auto order = f.find("x-order");
        const bool says_increasing = order != f.end() && order->value() == "increasing";
        EXPECT_EQ(refused_order, says_increasing) << path;
        ++(says_increasing ? ordered : unordered);
    }
    EXPECT_GE(ordered, 3);   // the pressures, the snapshot strains, the cuts
    EXPECT_GE(unordered, 2); // the toolpath's x and y
}

TEST(JobSpecSchema, MatchesTheTableOfDocsJobSpec)
{
    std::ifstream in(std::string(WIREDEM_SOURCE_DIR) + "/docs/job-spec.md");
    ASSERT_TRUE(in) << "docs/job-spec.md not found";
    std::string line;
    bool in_schema = false;
    std::map<std::string, std::vector<std::string>> rows;
    const std::regex row(R"(^\| `([a-z_.\[\]0-9]+)` \| ([^|]*) \| ([^|]*) \| ([^|]*) \| ([^|]*) \| (.*) \|$)");
    while (std::getline(in, line)) {
        if (line.rfind("## ", 0) == 0) in_schema = line == "## Schema";
        std::smatch m;
        if (in_schema && std::regex_search(line, m, row) && m[2].str() != "object")
            rows[m[1]] = {m[2], m[3], m[4], m[5], m[6]};
    }
    const auto fields = schema_fields();
    for (const auto& [path, f] : fields) EXPECT_TRUE(rows.count(path)) << path << " is in the schema, not in docs/job-spec.md";
    for (const auto& [path, r] : rows) EXPECT_TRUE(fields.count(path)) << path << " is in docs/job-spec.md, not in the schema";

    // Units and meanings: the table's, as text (without its Markdown: `code`, \|).
    for (const auto& [path, r] : rows) {
        if (!fields.count(path)) continue;
        const json::object& f = fields.at(path);
        const auto u = f.find("x-unit");
        const std::string unit = u == f.end() ? "—" : u->value().as_string() == "1" ? "—" : std::string(u->value().as_string());
        EXPECT_EQ(unit, r[1]) << path << ": the unit";
        std::string meaning = std::regex_replace(r[4], std::regex("`"), "");
        meaning = std::regex_replace(meaning, std::regex(R"(\\\|)"), "|");
        const auto d = f.find("description");
        EXPECT_EQ(d == f.end() ? std::string() : std::string(d->value().as_string()), meaning) << path << ": the meaning";
    }

    int intervals = 0, defaults = 0;
    const std::regex interval(R"(^([\[(])([^,]+), ([^\])]+)([\])]))");
    for (const auto& [path, r] : rows) {
        if (!fields.count(path)) continue;
        json::object f = fields.at(path);
        if (auto one = f.find("oneOf"); one != f.end()) f = one->value().at(0).as_object();
        if (auto items = f.find("items"); items != f.end()) f = items->value().as_object();
        std::smatch m;
        if (std::regex_search(r[3], m, interval)) {
            const auto lo = docs_number(m[2]), hi = docs_number(m[3]);
            if (!lo || !hi) continue;
            const char* lo_key = m[1] == "(" ? "exclusiveMinimum" : "minimum";
            const char* hi_key = m[4] == ")" ? "exclusiveMaximum" : "maximum";
            ASSERT_TRUE(f.contains(lo_key) && f.contains(hi_key)) << path << ": docs say " << r[3] << ", schema " << json::serialize(f);
            EXPECT_DOUBLE_EQ(f.at(lo_key).to_number<double>(), *lo) << path;
            EXPECT_DOUBLE_EQ(f.at(hi_key).to_number<double>(), *hi) << path;
            ++intervals;
        }
        if (auto d = docs_number(r[2]); d && fields.at(path).at("default").is_number()) {
            EXPECT_DOUBLE_EQ(fields.at(path).at("default").to_number<double>(), *d) << path;
            ++defaults;
        }
    }
    EXPECT_GT(intervals, 45);
    EXPECT_GT(defaults, 40);
}

} // namespace
} // namespace wiredem::api
