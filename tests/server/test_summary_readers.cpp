// One description of summary.json's keys: the Summary schemas of the OpenAPI
// document (server/handlers/meta.cpp), which the writer (campaign/stages.cpp)
// is held to by SummarySchemaRealRunner.* (every key it writes declared, every
// required key written). Here the readers that cannot include it are held to
// it: docs/results.md documents every key of the schemas and lists the
// top-level keys of Summary and no other, and the web page reads through
// `summary.…` only keys the schemas declare. A renamed key fails here,
// naming the file that still has the old name.
#include "handlers/meta.hpp"
#include "source_tree.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {
namespace fs = std::filesystem;
namespace json = boost::json;
using wiredem::test_support::read_text;
using wiredem::test_support::source;

const json::object& schemas() { return wiredem::server::openapi_document().at("components").at("schemas").as_object(); }

/// A schema with its references resolved ("#/components/schemas/X").
const json::object& resolved(const json::value& schema)
{
    const json::object* s = &schema.as_object();
    while (const json::value* ref = s->if_contains("$ref")) {
        const std::string name = std::string(ref->as_string()).substr(std::string("#/components/schemas/").size());
        s = &schemas().at(name).as_object();
    }
    return *s;
}

/// The property `key` of an object schema (through an array's items, a
/// nullable's alternatives), or null.
const json::object* property(const json::object& schema, const std::string& key)
{
    if (const json::value* items = schema.if_contains("items")) return property(resolved(*items), key);
    for (const char* alt : {"anyOf", "oneOf", "allOf"})
        if (const json::value* a = schema.if_contains(alt))
            for (const json::value& o : a->as_array())
                if (const json::object* p = property(resolved(o), key)) return p;
    if (const json::value* props = schema.if_contains("properties"))
        if (const json::value* p = props->as_object().if_contains(key)) return &resolved(*p);
    return nullptr;
}

/// Every property name of every Summary… schema.
std::set<std::string> every_summary_key()
{
    std::set<std::string> keys;
    for (const auto& [name, schema] : schemas()) {
        if (!name.starts_with("Summary")) continue;
        std::vector<const json::object*> todo{&schema.as_object()};
        while (!todo.empty()) {
            const json::object* s = todo.back();
            todo.pop_back();
            if (const json::value* props = s->if_contains("properties"))
                for (const auto& [key, sub] : props->as_object()) {
                    keys.emplace(key);
                    if (sub.is_object() && !sub.as_object().contains("$ref")) todo.push_back(&sub.as_object());
                }
            if (const json::value* items = s->if_contains("items"); items && items->is_object()
                && !items->as_object().contains("$ref"))
                todo.push_back(&items->as_object());
            for (const char* alt : {"anyOf", "oneOf", "allOf"})
                if (const json::value* a = s->if_contains(alt))
                    for (const json::value& o : a->as_array())
                        if (o.is_object() && !o.as_object().contains("$ref")) todo.push_back(&o.as_object());
        }
    }
    return keys;
}

std::string docs_summary_section()
{
    const std::string doc = read_text(source("docs/results.md"));
    const std::size_t from = doc.find("## `summary.json`");
    const std::size_t to = doc.find("## `result.h5`");
    EXPECT_NE(from, std::string::npos);
    EXPECT_NE(to, std::string::npos);
    return doc.substr(from, to - from);
}

} // namespace

TEST(SummaryKeys, TheSchemasDeclareTheKeysTheWriterIsHeldTo)
{
    const std::set<std::string> keys = every_summary_key();
    EXPECT_GE(keys.size(), 100u) << "the Summary schemas were not found whole";
    for (const char* k : {"tests", "mohr_coulomb", "yield", "consolidation", "wire_pieces", "pull_out", "caveats"})
        EXPECT_TRUE(keys.contains(k)) << k;
}

TEST(SummaryKeys, DocsResultsDocumentsEveryKeyAndListsTheTopLevelOnes)
{
    const std::string section = docs_summary_section();
    for (const std::string& k : every_summary_key())
        EXPECT_TRUE(section.find("`" + k + "`") != std::string::npos || section.find("`" + k + "[]`") != std::string::npos)
            << "docs/results.md's summary.json section does not name the key " << k << " of the Summary schemas";
    // The table's first column: "| `tests[]` | …" — Summary's own keys, each once, and no other.
    std::set<std::string> listed;
    const std::regex row(R"(\n\| `([a-z_0-9]+)(?:\[\])?` \|)");
    for (auto it = std::sregex_iterator(section.begin(), section.end(), row); it != std::sregex_iterator(); ++it)
        EXPECT_TRUE(listed.emplace((*it)[1].str()).second) << (*it)[1].str() << " listed twice";
    std::set<std::string> top;
    for (const auto& [key, sub] : schemas().at("Summary").at("properties").as_object()) top.emplace(key);
    EXPECT_EQ(listed, top) << "docs/results.md's table of summary.json lists other keys than Summary's";
}

TEST(SummaryKeys, TheWebPageReadsOnlyKeysOfTheSchemas)
{
    // summary.a.b… in the modules that read a job's summary.json (studies.js
    // reads a study's summary, another document); a chain ends at the first
    // name that is the JavaScript's own (summary.warnings.length).
    const std::set<std::string> javascript{"length", "map", "forEach", "filter", "some", "every", "find", "slice", "at"};
    const std::regex chain(R"((?:^|[^'"/\w.])summary((?:\.[A-Za-z_0-9]+)+))");
    const json::object& summary = schemas().at("Summary").as_object();
    std::size_t found = 0;
    for (const auto& entry : fs::directory_iterator(source("web/src/js"))) {
        if (entry.path().extension() != ".js" || entry.path().filename() == "studies.js") continue;
        const std::string js = read_text(entry.path());
        for (auto it = std::sregex_iterator(js.begin(), js.end(), chain); it != std::sregex_iterator(); ++it) {
            std::stringstream names((*it)[1].str().substr(1));
            const json::object* at = &summary;
            std::string path = "summary";
            for (std::string name; std::getline(names, name, '.');) {
                if (path == "summary" && name == "json") break;  // the file's name, in a comment
                if (javascript.contains(name)) break;
                path += "." + name;
                at = property(*at, name);
                ASSERT_NE(at, nullptr) << entry.path().filename().string() << " reads " << path
                                       << ", which the Summary schema (server/handlers/meta.cpp) does not declare";
                ++found;
            }
        }
    }
    EXPECT_GE(found, 30u) << "the page's reads of summary.json were not found: has the pattern of the JavaScript changed?";
}

TEST(SummaryKeys, ThePythonPackageReadsOnlyKeysOfTheSchemas)
{
    // summary["a"]["b"] and summary.get("a") in the package's job results
    // (study.py and client.py read a study's summary, another document).
    const std::set<std::string> keys = every_summary_key();
    const std::regex read(R"re(summary((?:\["[a-z_0-9]+"\])+|\.get\("[a-z_0-9]+"))re");
    const std::regex name(R"re("([a-z_0-9]+)")re");
    std::size_t found = 0;
    for (const char* file : {"python/wiredem/results.py", "python/wiredem/plots.py", "docs/python.md"}) {
        const std::string py = read_text(source(file));
        for (auto it = std::sregex_iterator(py.begin(), py.end(), read); it != std::sregex_iterator(); ++it) {
            const std::string names = (*it)[1].str();
            for (auto n = std::sregex_iterator(names.begin(), names.end(), name); n != std::sregex_iterator(); ++n) {
                EXPECT_TRUE(keys.contains((*n)[1].str()))
                    << file << " reads summary.json's " << (*n)[1].str() << ", which no Summary schema declares";
                ++found;
            }
        }
    }
    EXPECT_GE(found, 8u) << "the package's reads of summary.json were not found: has the pattern of the Python changed?";
}
