// The parsers of request parts, each on its own and faster than through the
// router: the Range header (handlers/jobs.hpp parse_range), job ids, job
// state names, the Host and Origin checks (origin.hpp) and the request
// target with its query (Boost.URL, as the router reads it). The first byte
// picks the parser, the rest is its input.
#include "fuzz_check.hpp"

#include "config.hpp"
#include "handlers/jobs.hpp"
#include "job.hpp"
#include "origin.hpp"

#include <boost/url/parse.hpp>
#include <boost/url/url_view.hpp>
#include <fuzzer/FuzzedDataProvider.h>

#include <filesystem>
#include <string>

using namespace wiredem;

namespace {

/// A resolved range lies inside the file, and reads back as itself when
/// written as `bytes=first-last`; unsatisfiable only when no byte can be sent.
void check_range(std::string_view header, std::uint64_t size)
{
    const std::string what = "Range '" + std::string(header) + "' on " + std::to_string(size) + " bytes";
    const server::RangeRequest r = server::parse_range(header, size);
    if (r.kind == server::RangeRequest::Kind::unsatisfiable) return;
    if (r.kind == server::RangeRequest::Kind::none) return;
    FUZZ_CHECK(r.range.length >= 1 && r.range.first < size && r.range.length <= size - r.range.first, what);
    const std::string again = "bytes=" + std::to_string(r.range.first) + "-" + std::to_string(r.range.first + r.range.length - 1);
    const server::RangeRequest r2 = server::parse_range(again, size);
    FUZZ_CHECK(r2.kind == server::RangeRequest::Kind::range && r2.range.first == r.range.first
            && r2.range.length == r.range.length, what + " then " + again);
}

/// A valid id names a folder directly under jobs/: no separator, no dot-dot.
void check_job_id(std::string_view id)
{
    if (!server::is_valid_job_id(id)) return;
    const std::filesystem::path jobs = "/data/jobs";
    const auto p = (jobs / std::string(id)).lexically_normal();
    FUZZ_CHECK(p.parent_path() == jobs && p.filename() == std::string(id), "id '" + std::string(id) + "'");
}

void check_state_name(std::string_view name)
{
    if (const auto s = server::job_state_from_string(name))
        FUZZ_CHECK(server::to_string(*s) == name, "state '" + std::string(name) + "'");
}

/// A Host the server accepts makes the server's own origin acceptable; an
/// accepted Origin is exactly that origin (up to case).
void check_host_and_origin(std::string_view host, std::string_view origin, const server::ServerConfig& config)
{
    if (server::host_problem(host, config)) return;
    FUZZ_CHECK(!server::origin_problem("http://" + std::string(host), host), "Host '" + std::string(host) + "'");
    if (!server::origin_problem(origin, host))
        FUZZ_CHECK(origin.size() == host.size() + 7, "Origin '" + std::string(origin) + "' for Host '" + std::string(host) + "'");
}

/// The router splits the target into segments and decoded parameters.
void check_target(std::string_view target)
{
    const auto parsed = boost::urls::parse_origin_form(target);
    if (!parsed) return;
    const boost::urls::url_view url = *parsed;
    std::size_t n = 0;
    for (auto s : url.segments()) n += std::string(s).size();
    for (auto p : url.params()) n += p.key.size() + (p.has_value ? p.value.size() : 0);
    FUZZ_CHECK(n <= 3 * target.size(), "target '" + std::string(target) + "'");  // decoding never grows text
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    FuzzedDataProvider in(data, size);
    switch (in.ConsumeIntegralInRange<int>(0, 4)) {
    case 0: {
        // Sizes near the edges of the integer as often as ordinary ones.
        const std::uint64_t file_size = in.ConsumeBool() ? in.ConsumeIntegralInRange<std::uint64_t>(0, 2000)
                                                         : in.ConsumeIntegral<std::uint64_t>();
        check_range(in.ConsumeRemainingBytesAsString(), file_size);
        break;
    }
    case 1: check_job_id(in.ConsumeRemainingBytesAsString()); break;
    case 2: check_state_name(in.ConsumeRemainingBytesAsString()); break;
    case 3: {
        server::ServerConfig config;
        config.listen_host = in.ConsumeBool() ? "127.0.0.1" : in.ConsumeBool() ? "0.0.0.0" : "::1";
        config.listen_port = in.ConsumeIntegral<std::uint16_t>();
        if (in.ConsumeBool()) config.allowed_hosts.push_back(in.ConsumeRandomLengthString(64));
        const std::string host = in.ConsumeRandomLengthString(128);
        check_host_and_origin(host, in.ConsumeRemainingBytesAsString(), config);
        break;
    }
    default: check_target(in.ConsumeRemainingBytesAsString()); break;
    }
    return 0;
}
