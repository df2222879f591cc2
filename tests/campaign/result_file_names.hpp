// Walks a result.h5 (or a file laid out like one) and holds every group,
// dataset and attribute name in it to the one table of result.h5's names
// (engine/triaxial/result_names.hpp; the series columns: series_columns.hpp),
// place by place, datasets' units too. Used on a file the writer's functions
// wrote (test_files.cpp) and on the real binary's result.h5 (test_stages.cpp).
#pragma once

#include "h5_compare.hpp"
#include "io/hdf5.hpp"
#include "triaxial/result_names.hpp"
#include "triaxial/series_columns.hpp"

#include <hdf5.h>

#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wiredem::test {

/// What a walk found.
struct ResultFileNames {
    std::vector<std::string> problems;  ///< each a name the table does not have there, or wrong units, with its path
    std::set<std::pair<engine::ResultPlace, std::string>> seen;  ///< (place, table name) of every name met
};

namespace result_file_names_detail {

using engine::ResultKind;
using engine::ResultNameSpec;
using engine::ResultPlace;

/// The table's entry for `name` of `kind` at `place` (a test's group and
/// /free_standing also hold the record's names).
inline const ResultNameSpec* find(ResultPlace place, ResultKind kind, const std::string& name)
{
    for (const ResultNameSpec& s : engine::result_name_specs) {
        const bool here = s.place == place
            || (s.place == ResultPlace::record && (place == ResultPlace::test || place == ResultPlace::free_standing));
        if (!here || s.kind != kind) continue;
        if (s.name == name) return &s;
        if (engine::result_name_is_prefix(s) && name.size() > s.name.size() && name.starts_with(s.name)) return &s;
    }
    return nullptr;
}

/// The place a group of the table opens: the layout of result.h5.
inline std::optional<ResultPlace> place_of_group(ResultPlace parent, std::string_view group)
{
    using P = ResultPlace;
    if (group == "wire_breaks") return P::wire_breaks;
    if (group == "snapshots") return P::snapshots;
    switch (parent) {
    case P::root:
        if (group == "specimen") return P::specimen;
        if (group == "tests") return P::tests;
        if (group == "free_standing") return P::free_standing;
        break;
    case P::specimen:
        if (group == "grain_sizes") return P::grain_sizes;
        if (group == "wire_pieces") return P::wire_pieces;
        break;
    case P::tests: return P::test;
    case P::snapshots: return P::snapshot;
    case P::free_standing:
        if (group == "pull_out") return P::pull_out;
        if (group == "peak_snapshot") return P::snapshot;
        if (group.starts_with("profile_")) return P::profile;
        break;
    default: break;
    }
    return std::nullopt;
}

/// The names of the attributes of `o` (h5_compare.hpp's walk of them).
inline std::vector<std::string> attribute_names(const engine::io::Object& o)
{
    return h5_compare_detail::attribute_names(static_cast<hid_t>(o.id()));
}

inline bool is_group(const engine::io::Group& g, const std::string& child)
{
    H5O_info_t info{};
    return H5Oget_info_by_name2(static_cast<hid_t>(g.id()), child.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0
        && info.type == H5O_TYPE_GROUP;
}

inline bool is_series_column(ResultPlace place, const std::string& name)
{
    if (place != ResultPlace::test && place != ResultPlace::free_standing) return false;
    for (const engine::SeriesColumnSpec& c : engine::series_column_specs)
        if (c.name == name) return true;
    return false;
}

inline void walk(const engine::io::Group& g, ResultPlace place, ResultFileNames& out)
{
    for (const std::string& a : attribute_names(g)) {
        if (const ResultNameSpec* s = find(place, ResultKind::attribute, a)) out.seen.emplace(s->place, std::string(s->name));
        else out.problems.push_back(g.path() + ": attribute " + a + " is not in engine/triaxial/result_names.hpp");
    }
    for (const std::string& child : g.child_names()) {
        const std::string path = g.path() + (g.path() == "/" ? "" : "/") + child;
        if (is_group(g, child)) {
            const ResultNameSpec* s = find(place, ResultKind::group, child);
            const std::optional<ResultPlace> inner = place_of_group(place, child);
            if (!s || !inner) {
                out.problems.push_back(path + ": group not in engine/triaxial/result_names.hpp");
                continue;
            }
            out.seen.emplace(s->place, std::string(s->name));
            walk(g.open_group(child), *inner, out);
            continue;
        }
        const engine::io::Dataset d = g.open_dataset(child);
        const bool column = is_series_column(place, child);
        const ResultNameSpec* s = column ? nullptr : find(place, ResultKind::dataset, child);
        if (!column && !s) {
            out.problems.push_back(path + ": dataset not in engine/triaxial/result_names.hpp");
            continue;
        }
        if (s) out.seen.emplace(s->place, std::string(s->name));
        for (const std::string& a : attribute_names(d)) {
            if (a != engine::result_name(ResultPlace::dataset, "units")) {
                out.problems.push_back(path + ": attribute " + a + " is not in engine/triaxial/result_names.hpp");
                continue;
            }
            out.seen.emplace(ResultPlace::dataset, a);
            if (s && !s->units.empty() && d.read_string_attribute(a) != s->units)
                out.problems.push_back(path + ": units \"" + d.read_string_attribute(a) + "\", the table's \""
                                       + std::string(s->units) + "\"");
        }
    }
}

} // namespace result_file_names_detail

/// Every name in `root` (a result.h5's root group, or a group laid out as
/// `place`) held to the table.
inline ResultFileNames result_file_names(const engine::io::Group& root, engine::ResultPlace place = engine::ResultPlace::root)
{
    ResultFileNames out;
    result_file_names_detail::walk(root, place, out);
    return out;
}

} // namespace wiredem::test
