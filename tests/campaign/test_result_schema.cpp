// One home for the columns of a time series (engine/triaxial/series_columns.hpp):
// the writer writes them in the table's order with the table's units, and the
// consumers that cannot include the table (docs/results.md, the web page's
// JavaScript, the Python package) name only its columns, and the docs name
// every one. A renamed column fails here, naming the file that still has the
// old name.
#include "files.hpp"
#include "source_tree.hpp"
#include "triaxial/series_columns.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
namespace eng = wiredem::engine;
using wiredem::test_support::read_text;
using wiredem::test_support::source;

namespace {

std::set<std::string> table_names()
{
    std::set<std::string> out;
    for (const eng::SeriesColumnSpec& c : eng::series_column_specs) out.emplace(c.name);
    return out;
}

/// Every submatch 1 of `pattern` in `text`, split at commas.
std::vector<std::string> names_matching(const std::string& text, const std::regex& pattern)
{
    std::vector<std::string> out;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern); it != std::sregex_iterator(); ++it) {
        std::stringstream list((*it)[1].str());
        for (std::string name; std::getline(list, name, ',');)
            if (!name.empty()) out.push_back(name);
    }
    return out;
}

/// Each of `names` (found in `file`) is a column of the table.
void expect_columns_of_the_table(const std::vector<std::string>& names, const std::string& file)
{
    const std::set<std::string> known = table_names();
    for (const std::string& n : names)
        EXPECT_TRUE(known.contains(n)) << file << " names the series column " << n
                                       << ", which engine/triaxial/series_columns.hpp does not have";
}

} // namespace

TEST(SeriesColumns, TheWriterWritesEveryColumnOfTheTableInItsOrderWithItsUnits)
{
    eng::TriaxialSeries s;
    eng::TriaxialSample row;
    row.time_s = 1.0;
    s.push_back(row);
    s.volumetric_strain = {0.0};
    const std::vector<wiredem::api::SeriesColumn> written = wiredem::campaign::series_columns(s);
    ASSERT_EQ(written.size(), eng::series_column_specs.size());
    for (std::size_t k = 0; k < written.size(); ++k) {
        EXPECT_EQ(written[k].name, eng::series_column_specs[k].name) << "column " << k;
        EXPECT_EQ(written[k].units, eng::series_column_specs[k].units) << written[k].name;
        EXPECT_EQ(written[k].values.size(), 1u) << written[k].name;
    }
    EXPECT_EQ(eng::series_column_specs.back().name, "phase") << "for_each_series_column leaves phase to the last";
}

TEST(SeriesColumns, DocsResultsNamesEveryColumnAndNoOther)
{
    const std::string doc = read_text(source("docs/results.md"));
    // The row of result.h5's table that lists the series: "| `…/time_s`, `phase` (…), … | the time series …".
    const std::size_t at = doc.find("| `…/time_s`");
    ASSERT_NE(at, std::string::npos) << "docs/results.md: the row of the time series columns";
    const std::string first_cell = doc.substr(at + 1, doc.find(" | ", at + 1) - at - 1);
    std::vector<std::string> named = names_matching(first_cell, std::regex("`(?:…/)?([a-z0-9_]+)`"));
    std::set<std::string> documented(named.begin(), named.end());
    EXPECT_EQ(documented.size(), named.size()) << "a column named twice";
    for (const std::string& n : table_names())
        EXPECT_TRUE(documented.contains(n)) << "docs/results.md does not list the series column " << n;
    expect_columns_of_the_table(named, "docs/results.md");
}

TEST(SeriesColumns, TheWebPageNamesOnlyColumnsOfTheTable)
{
    std::size_t found = 0;
    for (const auto& entry : fs::directory_iterator(source("web/src/js"))) {
        if (entry.path().extension() != ".js") continue;
        const std::string js = read_text(entry.path());
        std::vector<std::string> names;
        // ?columns=a,b in a route, the lists kept as constants (curveColumns = 'a,b'),
        // series.columns.a (not a method: t.columns.some(…)) and curves('a', …).
        for (const char* p : {R"(columns=([a-z0-9_,]+))", R"([cC]olumns = '([a-z0-9_,]+)')", R"(\.columns\.([a-z0-9_]+)\b(?!\())",
                 R"(curves\('([a-z0-9_]+)')"}) {
            const std::vector<std::string> n = names_matching(js, std::regex(p));
            names.insert(names.end(), n.begin(), n.end());
        }
        expect_columns_of_the_table(names, entry.path().filename().string());
        found += names.size();
    }
    EXPECT_GE(found, 20u) << "the page's column names were not found: has the pattern of the JavaScript changed?";
}

TEST(SeriesColumns, ThePythonPackageNamesOnlyColumnsOfTheTable)
{
    std::size_t found = 0;
    for (const char* file : {"python/wiredem/plots.py", "python/wiredem/results.py", "docs/python.md"}) {
        const std::string py = read_text(source(file));
        std::vector<std::string> names;
        // The curve helpers' table (CURVES = {"a": (…)}), the default column lists
        // (columns: Sequence[str] = ("a", "b")), curve("a") and column: str = "a".
        const std::size_t curves = py.find("CURVES:");
        if (curves != std::string::npos) {
            const std::string block = py.substr(curves, py.find("\n}", curves) - curves);
            const std::vector<std::string> n = names_matching(block, std::regex(R"re(\n\s+"([a-z0-9_]+)": \()re"));
            names.insert(names.end(), n.begin(), n.end());
        }
        for (const char* p : {R"re(curve\("([a-z0-9_]+)")re", R"re(column: str = "([a-z0-9_]+)")re"}) {
            const std::vector<std::string> n = names_matching(py, std::regex(p));
            names.insert(names.end(), n.begin(), n.end());
        }
        std::string lists;
        for (const std::string& l : names_matching(py, std::regex(R"re(columns: Sequence\[str\] = \(([^)]*)\))re"))) lists += l + ",";
        const std::vector<std::string> n = names_matching(lists, std::regex(R"re("([a-z0-9_]+)")re"));
        names.insert(names.end(), n.begin(), n.end());
        expect_columns_of_the_table(names, file);
        found += names.size();
    }
    EXPECT_GE(found, 10u) << "the package's column names were not found: has the pattern of the Python changed?";
}

// The package's own list (results.py's SERIES_COLUMNS, by which a series
// frame orders its columns) is the table, name for name and in its order.
TEST(SeriesColumns, ThePythonPackagesColumnListIsTheTable)
{
    const std::string py = read_text(source("python/wiredem/results.py"));
    const std::size_t at = py.find("SERIES_COLUMNS: Tuple[str, ...] = (");
    ASSERT_NE(at, std::string::npos) << "python/wiredem/results.py: SERIES_COLUMNS";
    const std::size_t end = py.find("\n)", at);
    ASSERT_NE(end, std::string::npos);
    const std::vector<std::string> listed =
        names_matching(py.substr(at, end - at), std::regex(R"re("([a-z0-9_]+)")re"));
    std::vector<std::string> table;
    for (const eng::SeriesColumnSpec& c : eng::series_column_specs) table.emplace_back(c.name);
    EXPECT_EQ(listed, table) << "python/wiredem/results.py's SERIES_COLUMNS is not engine/triaxial/series_columns.hpp's list";
    EXPECT_EQ(table.front(), "time_s") << "results.py takes the first column for the time";
}
