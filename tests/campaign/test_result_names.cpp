// One home for result.h5's names (engine/triaxial/result_names.hpp): the
// readers that cannot include the table (docs/results.md, the Python
// package, the web page) name only its names, and the docs name every one.
// A renamed or removed name fails here, naming the file that still has the
// old one. (The file the writer writes is held to the table by
// CampaignFiles.AResultFileHoldsOnlyTheTablesNames and by the real binary's
// result.h5 in Stages.PrepareTestAnalyseWritesOnlyTheTablesNames.)
#include "source_tree.hpp"
#include "triaxial/result_names.hpp"
#include "triaxial/series_columns.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;
namespace eng = wiredem::engine;
using wiredem::test_support::read_text;
using wiredem::test_support::source;

namespace {

/// Whether `name` is a name of result.h5: of the table (a group named by a
/// number or a pressure: its prefix and digits), or a series column.
bool is_result_name(const std::string& name)
{
    for (const eng::ResultNameSpec& s : eng::result_name_specs) {
        if (s.name == name) return true;
        if (eng::result_name_is_prefix(s) && name.size() > s.name.size() && name.starts_with(s.name)
            && name.find_first_not_of("0123456789.", s.name.size()) == std::string::npos)
            return true;
    }
    for (const eng::SeriesColumnSpec& c : eng::series_column_specs)
        if (c.name == name) return true;
    return false;
}

/// Every submatch 1 of `pattern` in `text`.
std::vector<std::string> matches(const std::string& text, const std::string& pattern)
{
    std::vector<std::string> out;
    const std::regex re(pattern);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
        out.push_back((*it)[1].str());
    return out;
}

/// Each of `names` (found in `file`) is a name of result.h5.
void expect_names_of_the_table(const std::vector<std::string>& names, const std::string& file)
{
    for (const std::string& n : names)
        EXPECT_TRUE(is_result_name(n)) << file << " names " << n
                                       << " in result.h5, which engine/triaxial/result_names.hpp does not have";
}

/// docs/results.md's section on result.h5.
std::string result_h5_section()
{
    const std::string doc = read_text(source("docs/results.md"));
    const std::size_t at = doc.find("## `result.h5`");
    EXPECT_NE(at, std::string::npos) << "docs/results.md: the section ## `result.h5`";
    if (at == std::string::npos) return {};
    return doc.substr(at, doc.find("\n## ", at + 1) - at);
}

/// The names the section lists: every `name` or `/path/of/names` in
/// backquotes (a placeholder <…> cut off: `snapshot_<k>` lists snapshot_);
/// code (`api::to_json`), files, wildcards and quoted values ("wire") are not names.
std::vector<std::string> documented_names()
{
    std::vector<std::string> out;
    for (std::string span : matches(result_h5_section(), "`([^`]+)`")) {
        span = std::regex_replace(span, std::regex("<[^>]*>"), "");
        span = std::regex_replace(span, std::regex("…"), "");
        if (!std::regex_match(span, std::regex("[a-z0-9_/]+"))) continue;
        std::size_t from = 0;
        while (from <= span.size()) {
            const std::size_t slash = std::min(span.find('/', from), span.size());
            if (slash > from) out.push_back(span.substr(from, slash - from));
            from = slash + 1;
        }
    }
    return out;
}

} // namespace

TEST(ResultNames, EveryNameIsDocumentedInDocsResults)
{
    const std::vector<std::string> named = documented_names();
    const std::set<std::string> documented(named.begin(), named.end());
    for (const eng::ResultNameSpec& s : eng::result_name_specs)
        EXPECT_TRUE(documented.contains(std::string(s.name)))
            << "docs/results.md's section on result.h5 does not list " << s.name << " (" << s.meaning << ")";
}

TEST(ResultNames, DocsResultsListsOnlyNamesOfTheTable)
{
    const std::vector<std::string> named = documented_names();
    EXPECT_GE(named.size(), 150u) << "the section's names were not found: has its layout changed?";
    expect_names_of_the_table(named, "docs/results.md");
}

TEST(ResultNames, EveryDatasetOfTheTableHasUnitsAndEveryNameAMeaning)
{
    for (const eng::ResultNameSpec& s : eng::result_name_specs) {
        EXPECT_FALSE(s.meaning.empty()) << s.name;
        EXPECT_TRUE(s.kind != eng::ResultKind::dataset || !s.units.empty() || s.place == eng::ResultPlace::root)
            << s.name << ": a numeric dataset without units";
        EXPECT_TRUE(std::regex_match(std::string(s.name), std::regex("[a-z][a-z0-9_]*"))) << s.name;
    }
}

TEST(ResultNames, ThePythonPackageReadsOnlyNamesOfTheTable)
{
    const std::string py = read_text(source("python/wiredem/results.py"));
    std::vector<std::string> names;
    // Arrays by name (self.array("…")), attributes (self.attributes["…"],
    // .get("…"); a = self.attributes: a["…"], a.get("…"), "…" in a), groups
    // and datasets of an h5py file or group (f["…"], g["…"], "…" in f), the
    // position datasets by body kind ({0: "…", …}) and snapshot_ prefixes.
    for (const char* p : {R"re(\.array\("([a-z0-9_]+)"\))re", R"re(attributes(?:\.get\(|\[)"([a-z0-9_]+)")re",
             R"re(\ba(?:\.get\(|\[)"([a-z0-9_]+)")re", R"re("([a-z0-9_]+)" (?:not )?in a\b)re",
             R"re(\b[fg]\["([a-z0-9_]+)"\])re", R"re("([a-z0-9_]+)" (?:not )?in [fg]\b)re",
             R"re(\d: "([a-z0-9_]+_position_m)")re"}) {
        const std::vector<std::string> n = matches(py, p);
        names.insert(names.end(), n.begin(), n.end());
    }
    expect_names_of_the_table(names, "python/wiredem/results.py");
    // Names told by how they begin (startswith("profile_")): some name begins so.
    for (const std::string& prefix : matches(py, R"re(startswith\("([a-z0-9_]+)"\))re")) {
        bool begins_a_name = false;
        for (const eng::ResultNameSpec& s : eng::result_name_specs) begins_a_name |= s.name.starts_with(prefix);
        EXPECT_TRUE(begins_a_name) << "python/wiredem/results.py looks for names beginning " << prefix
                                   << ", and engine/triaxial/result_names.hpp has none";
        names.push_back(prefix);
    }
    EXPECT_GE(names.size(), 30u) << "the package's reads of result.h5 were not found: has the pattern of the Python changed?";
}

TEST(ResultNames, TheWebPageReadsOnlyNamesOfTheTable)
{
    std::size_t found = 0;
    for (const auto& entry : fs::directory_iterator(source("web/src/js"))) {
        if (entry.path().extension() != ".js") continue;
        const std::string js = read_text(entry.path());
        std::vector<std::string> names;
        // Arrays fetched by name (get('…'), `${url}/…` but the routes that are
        // not arrays), arrays looked for (a.name === '…', names.has('…')),
        // the free-standing test's profiles and a group's attributes.
        for (const char* p : {R"(\bget\('([a-z0-9_]+)'\))", R"(\}/([a-z][a-z0-9]*_[a-z0-9_]+)`)",
                 R"(name === '([a-z0-9_]+)')", R"(names\.has\('([a-z0-9_]+)'\))", R"(\['(profile_[a-z_]+)')",
                 R"(attributes\??\.([a-z0-9_]+))"}) {
            for (const std::string& n : matches(js, p))
                if (n != "wire_autocorrelation") names.push_back(n);  // a route of the API (docs/api.md)
        }
        expect_names_of_the_table(names, entry.path().filename().string());
        found += names.size();
    }
    EXPECT_GE(found, 15u) << "the page's reads of result.h5 were not found: has the pattern of the JavaScript changed?";
}
