// Reading the runner's progress lines.
#include "progress_line.hpp"

#include "api/progress_line.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace wiredem::server {
namespace json = boost::json;

namespace {

/// The longest prefix of UTF-8 text `s` (Boost.JSON has validated it) of at
/// most `max_bytes` that ends at a character boundary: a cut inside a
/// character would leave invalid UTF-8 in the job's JSON.
std::string cut_utf8(std::string_view s, std::size_t max_bytes)
{
    if (s.size() <= max_bytes) return std::string(s);
    std::size_t n = max_bytes;
    while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;  // s[n] continues a character
    return std::string(s.substr(0, n));
}

/// A duration that can be shown and computed with: finite and not negative.
std::optional<double> duration(std::optional<double> x)
{
    return x && std::isfinite(*x) && *x >= 0.0 ? x : std::nullopt;
}

/// A rate that ETAs may divide by: finite and positive.
std::optional<double> rate(std::optional<double> x)
{
    return x && std::isfinite(*x) && *x > 0.0 ? x : std::nullopt;
}

} // namespace

std::optional<double> number_at(const json::value& v, std::initializer_list<const char*> path)
{
    const json::value* cur = &v;
    for (const char* key : path) {
        const auto* obj = cur->if_object();
        if (!obj) return std::nullopt;
        auto it = obj->find(key);
        if (it == obj->end()) return std::nullopt;
        cur = &it->value();
    }
    if (cur->is_double()) return cur->get_double();
    if (cur->is_int64()) return static_cast<double>(cur->get_int64());
    if (cur->is_uint64()) return static_cast<double>(cur->get_uint64());
    return std::nullopt;
}

std::optional<ProgressLine> parse_progress_line(std::string_view line)
{
    namespace key = api::progress_line;  // the runner contract's keys, one list
    boost::system::error_code ec;
    const json::value v = json::parse(line, ec);
    const auto* obj = ec ? nullptr : v.if_object();
    if (!obj) return std::nullopt;
    ProgressLine p;
    if (auto s = obj->find(key::stage); s != obj->end() && s->value().is_string())
        p.stage = cut_utf8(s->value().get_string(), max_stage_bytes);
    // A fraction: finite (Boost.JSON reads "0e3006" as NaN, which clamp would keep), then within [0, 1].
    if (auto f = number_at(v, {key::progress}); f && std::isfinite(*f)) p.progress = std::clamp(*f, 0.0, 1.0);
    if (auto e = obj->find(key::eta_s); e != obj->end()) {
        p.has_eta = true;
        p.eta_s = duration(number_at(v, {key::eta_s}));  // null: no estimate
    }
    if (auto m = obj->find(key::message); m != obj->end() && m->value().is_string())
        p.message = cut_utf8(m->value().get_string(), max_message_bytes);
    p.body_steps_per_second = rate(number_at(v, {key::body_steps_per_second}));
    return p;
}

void apply_progress_line(const ProgressLine& line, LiveProgress& live)
{
    if (line.stage) live.stage = *line.stage;
    if (line.progress) live.progress = *line.progress;
    if (line.has_eta) live.eta_s = line.eta_s;
    if (line.message) live.message = *line.message;
    // preparing until the runner reports a later stage; running from then on
    if (live.state == JobState::preparing && !live.stage.empty() && live.stage != api::progress_line::preparing)
        live.state = JobState::running;
}

} // namespace wiredem::server
