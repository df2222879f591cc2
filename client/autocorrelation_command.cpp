// The wire autocorrelation of a result file's snapshot: api::wire_autocorrelation_json
// on its stored segment strains, with the segment length of the job it ran.
#include "autocorrelation_command.hpp"

#include "exit_codes.hpp"

#include "api/job_spec.hpp"
#include "api/json_text.hpp"
#include "api/result_data.hpp"
#include "io/hdf5.hpp"

#include <boost/json/serialize.hpp>

#include <algorithm>
#include <iostream>

namespace wiredem::client {
namespace io = engine::io;

int cmd_autocorrelation(const std::filesystem::path& result_h5, const std::string& test_in,
    std::optional<long long> snapshot)
{
    const std::string file_name = result_h5.string();
    if (!std::filesystem::is_regular_file(result_h5))
        throw CommandError(exit_code::local_io, "cannot read result file " + file_name);
    try {
        const io::File file = io::File::open_read_only(result_h5);
        const io::Group root = file.root();
        const auto spec = api::parse_written_job_spec(root.open_dataset("job_spec").read_string());
        if (!spec) throw CommandError(exit_code::local_io, file_name + ": /job_spec is not a valid job: "
                                                              + spec.error().front().message);
        const std::vector<std::string> tests = api::test_names(root);
        if (tests.empty()) throw CommandError(exit_code::local_io, file_name + " holds no test");
        const std::string test = test_in.empty() ? tests.back() : test_in;
        if (std::find(tests.begin(), tests.end(), test) == tests.end())
            throw CommandError(exit_code::local_io, file_name + " has no test " + test);
        const io::Group group = root.open_group("tests/" + test);
        const std::vector<std::size_t> ks = api::snapshot_indices(group);
        if (ks.empty()) throw CommandError(exit_code::local_io, test + " of " + file_name + " has no snapshot");
        if (snapshot && *snapshot < 0)
            throw CommandError(exit_code::usage, "--snapshot " + std::to_string(*snapshot) + ": a snapshot index is 0 or more");
        const std::size_t k = snapshot ? static_cast<std::size_t>(*snapshot) : ks.back();
        if (std::find(ks.begin(), ks.end(), k) == ks.end())
            throw CommandError(exit_code::local_io, test + " of " + file_name + " has no snapshot " + std::to_string(k));
        const io::Group snap = group.open_group(api::snapshot_path(k));
        if (!snap.exists("wire_segment_strain"))
            throw CommandError(exit_code::local_io, test + " snapshot " + std::to_string(k) + " of " + file_name + " has no wire");
        const std::vector<double> strain = snap.open_dataset("wire_segment_strain").read_doubles();
        std::cout << boost::json::serialize(api::wire_autocorrelation_json(strain, spec.value().specimen.wire.segment_length_m))
                  << std::endl;
    } catch (const CommandError&) {
        throw;
    } catch (const std::exception& e) {
        throw CommandError(exit_code::local_io, file_name + ": " + e.what());
    }
    return exit_code::ok;
}

} // namespace wiredem::client
