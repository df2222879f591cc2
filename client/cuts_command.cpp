// Cuts where a reference test's wire strain was lowest; see cuts_command.hpp.
#include "cuts_command.hpp"

#include "exit_codes.hpp"

#include "analysis/cut_selection.hpp"
#include "api/job_spec.hpp"
#include "api/result_data.hpp"
#include "io/hdf5.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <vector>

namespace wiredem::client {
namespace io = engine::io;
namespace json = boost::json;

namespace {

/// The segments removed in `g`'s wire_breaks (if any) marked in `removed`.
void mark_removed(const io::Group& g, std::vector<std::uint8_t>& removed)
{
    if (!g.exists("wire_breaks")) return;
    for (std::int64_t s : g.open_group("wire_breaks").open_dataset("segment").read_int64s())
        if (s >= 0 && static_cast<std::size_t>(s) < removed.size()) removed[static_cast<std::size_t>(s)] = 1;
}

} // namespace

int cmd_cuts(const CutsRequest& r)
{
    const std::filesystem::path path = std::filesystem::is_directory(r.result) ? r.result / "result.h5" : r.result;
    const std::string file_name = path.string();
    if (r.count < 1) throw CommandError(exit_code::usage, "--count " + std::to_string(r.count) + ": at least 1 cut");
    if (r.min_spacing_m && !(std::isfinite(*r.min_spacing_m) && *r.min_spacing_m >= 0.0))
        throw CommandError(exit_code::usage, "--min-spacing-m: must be a finite length ≥ 0");
    if (r.at_strain && !std::isfinite(*r.at_strain)) throw CommandError(exit_code::usage, "--at-strain: must be finite");
    if (!std::filesystem::is_regular_file(path)) throw CommandError(exit_code::local_io, "cannot read result file " + file_name);
    try {
        const io::File file = io::File::open_read_only(path);
        const io::Group root = file.root();
        const auto spec = api::parse_written_job_spec(root.open_dataset("job_spec").read_string());
        if (!spec) throw CommandError(exit_code::local_io, file_name + ": /job_spec is not a valid job: "
                                                              + spec.error().front().message);
        const double l_w = spec.value().specimen.wire.segment_length_m;
        // The reference test and its snapshot: the one nearest --at-strain,
        // else the test's peak (the largest q; the free-standing test's
        // snapshot at its largest σ₁).
        const std::vector<std::string> tests = api::test_names(root);
        const std::string test = !r.test.empty() ? r.test : tests.empty() ? std::string() : tests.back();
        std::string snapshot_name;
        std::vector<std::uint8_t> removed;
        double axial_strain = 0.0;
        const bool free_standing = test == api::free_standing_group;
        if (!free_standing && std::find(tests.begin(), tests.end(), test) == tests.end())
            throw CommandError(exit_code::local_io, file_name + " has no test \"" + test + "\"");
        if (free_standing && !root.exists(std::string(api::free_standing_group)))
            throw CommandError(exit_code::local_io, file_name + " has no free-standing test");
        const io::Group group = root.open_group(free_standing ? std::string(api::free_standing_group) : "tests/" + test);
        if (free_standing && !r.at_strain) {
            if (!group.exists(std::string(api::free_standing_peak_snapshot)))
                throw CommandError(exit_code::local_io, "the free-standing test of " + file_name + " has no peak snapshot; give --at-strain");
            snapshot_name = std::string(api::free_standing_peak_snapshot);
        } else {
            const double target = r.at_strain ? *r.at_strain : group.read_double_attribute("peak_axial_strain");
            double best = INFINITY;
            for (std::size_t k : api::snapshot_indices(group)) {
                const double e = group.open_group(api::snapshot_path(k)).read_double_attribute("axial_strain");
                if (std::abs(e - target) < best) {
                    best = std::abs(e - target);
                    snapshot_name = api::snapshot_path(k);
                }
            }
            if (snapshot_name.empty()) throw CommandError(exit_code::local_io, test + " of " + file_name + " has no snapshot");
        }
        const io::Group snap = group.open_group(snapshot_name);
        axial_strain = snap.read_double_attribute("axial_strain");
        if (!snap.exists("wire_segment_strain"))
            throw CommandError(exit_code::local_io, test + " of " + file_name + " has no wire");
        const std::vector<double> strain = snap.open_dataset("wire_segment_strain").read_doubles();
        if (strain.empty()) throw CommandError(exit_code::local_io, test + " of " + file_name + " has no wire");
        // Segments removed before (the specimen's cuts and breaks) or in the
        // test report strain 0: never a place to cut.
        removed.assign(strain.size(), 0);
        if (root.exists("specimen")) mark_removed(root.open_group("specimen"), removed);
        mark_removed(group, removed);
        // The default spacing: one loop of the wire about the axis, from the
        // prepared wire's nodes.
        double loop_m = 0.0;
        if (root.exists("specimen/wire_node_position_m")) {
            const io::Dataset d = root.open_dataset("specimen/wire_node_position_m");
            const std::vector<double> flat = d.read_doubles();
            std::vector<engine::Vec3> x;
            for (std::size_t i = 0; i + 2 < flat.size(); i += 3) x.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
            loop_m = engine::analysis::length_per_loop_m(x, l_w);
        }
        if (!r.min_spacing_m && !(loop_m > 0.0))
            throw CommandError(exit_code::usage, "the wire of " + file_name
                                                     + " winds less than one loop about the axis: give --min-spacing-m");
        const double spacing_m = r.min_spacing_m ? *r.min_spacing_m : loop_m;
        const auto places = engine::analysis::lowest_strain_cuts(strain, l_w, r.count, spacing_m, removed);
        json::array at, strains, segments;
        for (const auto& p : places) {
            at.push_back(p.position_m);
            strains.push_back(p.strain);
            segments.push_back(p.segment);
        }
        json::object out{{"cuts_at_m", std::move(at)}, {"segment", std::move(segments)}, {"strain", std::move(strains)},
            {"test", test}, {"snapshot", snapshot_name}, {"axial_strain", axial_strain}, {"min_spacing_m", spacing_m},
            {"loop_length_m", loop_m > 0.0 ? json::value(loop_m) : json::value(nullptr)}};
        std::cout << json::serialize(out) << std::endl;
        if (places.size() < r.count)
            std::cerr << "wiredem: only " << places.size() << " of the " << r.count << " cuts fit "
                      << spacing_m << " m apart and from the wire's ends" << std::endl;
    } catch (const CommandError&) {
        throw;
    } catch (const std::exception& e) {
        throw CommandError(exit_code::local_io, file_name + ": " + e.what());
    }
    return exit_code::ok;
}

} // namespace wiredem::client
