// Job states, ids and timestamps.
#include "job.hpp"

#include <array>
#include <chrono>
#include <ctime>
#include <random>
#include <stdexcept>
#include <utility>

namespace wiredem::server {

std::string_view to_string(JobState s) noexcept
{
    switch (s) {
    case JobState::queued: return "queued";
    case JobState::preparing: return "preparing";
    case JobState::running: return "running";
    case JobState::succeeded: return "succeeded";
    case JobState::failed: return "failed";
    case JobState::cancelled: return "cancelled";
    }
    return "unknown";
}

std::optional<JobState> job_state_from_string(std::string_view name) noexcept
{
    for (JobState s : all_job_states)
        if (to_string(s) == name) return s;
    return std::nullopt;
}

bool is_valid_job_id(std::string_view id) noexcept
{
    if (id.size() != job_id_length) return false;
    for (char c : id)
        if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
    return true;
}

std::string make_job_id()
{
    static constexpr char hex[] = "0123456789abcdef";
    std::random_device rd;  // /dev/urandom: ids must not be guessable from each other
    std::string id;
    id.reserve(job_id_length);
    while (id.size() < job_id_length) {
        std::uint32_t r = rd();
        for (int k = 0; k < 8 && id.size() < job_id_length; ++k, r >>= 4) id.push_back(hex[r & 0xf]);
    }
    return id;
}

std::int64_t now_ms() noexcept
{
    using namespace std::chrono;
    return duration_cast<milliseconds>(system_clock::now().time_since_epoch()).count();
}

std::string format_rfc3339(std::int64_t unix_ms)
{
    const std::time_t secs = static_cast<std::time_t>(unix_ms / 1000);
    std::tm tm{};
    gmtime_r(&secs, &tm);
    std::array<char, 32> date{};
    std::strftime(date.data(), date.size(), "%Y-%m-%dT%H:%M:%S", &tm);
    const int ms = static_cast<int>(unix_ms % 1000);
    std::string out = date.data();
    out += '.';
    out += static_cast<char>('0' + ms / 100);
    out += static_cast<char>('0' + ms / 10 % 10);
    out += static_cast<char>('0' + ms % 10);
    out += 'Z';
    return out;
}

api::JobSpec stored_spec(const std::string& spec_json)
{
    auto spec = api::parse_written_job_spec(spec_json);
    if (!spec.ok()) {
        const api::FieldError& e = spec.error().front();
        throw std::runtime_error("the stored spec does not parse: " + (e.path.empty() ? e.message : e.path + ": " + e.message));
    }
    return std::move(spec.value());
}

} // namespace wiredem::server
