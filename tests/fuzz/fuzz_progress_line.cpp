// The runner's progress lines as the server reads them (server/progress_line.hpp):
// whatever a line holds, what the server keeps and later serves in every
// job's JSON is bounded, valid UTF-8, and numbers that make sense.
#include "fuzz_check.hpp"

#include "progress_line.hpp"

#include "api/json_text.hpp"

#include <boost/json.hpp>

#include <cmath>

using namespace wiredem;

namespace {

bool valid_utf8(const std::string& s)
{
    return api::parse_json_text(boost::json::serialize(boost::json::value(s))).ok();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string_view line(reinterpret_cast<const char*>(data), size);
    const auto p = server::parse_progress_line(line);
    if (!p) return 0;
    const std::string what(line);
    if (p->stage) FUZZ_CHECK(p->stage->size() <= server::max_stage_bytes && valid_utf8(*p->stage), what);
    if (p->message) FUZZ_CHECK(p->message->size() <= server::max_message_bytes && valid_utf8(*p->message), what);
    if (p->progress) FUZZ_CHECK(*p->progress >= 0.0 && *p->progress <= 1.0, what);
    if (p->eta_s) FUZZ_CHECK(std::isfinite(*p->eta_s) && *p->eta_s >= 0.0, what);
    if (p->body_steps_per_second)
        FUZZ_CHECK(std::isfinite(*p->body_steps_per_second) && *p->body_steps_per_second > 0.0, what);

    server::LiveProgress live;
    server::apply_progress_line(*p, live);
    FUZZ_CHECK(live.state == (live.stage.empty() || live.stage == "preparing" ? server::JobState::preparing
                                                                              : server::JobState::running), what);
    return 0;
}
