// /v1/jobs handlers. Validation happens here, once, through api/ (the same
// parser the client runs before sending); the store only ever sees a
// normalised spec (api::to_json), so equal jobs compare equal as text.
#include "jobs.hpp"

#include "api/derived.hpp"
#include "api/job_spec.hpp"
#include "api/json_text.hpp"
#include "core/format.hpp"
#include "../job_files.hpp"

#include <boost/json.hpp>
#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <charconv>
#include <cstdio>

namespace wiredem::server {
namespace json = boost::json;
using engine::format_number;

namespace {

constexpr std::size_t max_idempotency_key_bytes = 255;

std::string job_url(const std::string& id) { return "/v1/jobs/" + id; }

json::value optional_time(const std::optional<std::int64_t>& ms)
{
    return ms ? json::value(format_rfc3339(*ms)) : json::value(nullptr);
}

/// The job as the API shows it; `live` overrides the stored progress of a
/// running job, `with_spec` adds the full spec and `slurm` the Slurm jobs
/// that run it (--executor slurm).
json::object job_json(const JobRecord& r, const std::optional<LiveProgress>& live, bool with_spec,
    const std::optional<SlurmIds>& slurm = std::nullopt)
{
    JobState state = r.state;
    std::string stage = r.stage;
    double progress = r.progress;
    std::optional<double> eta = r.eta_s;
    std::string message = r.message;
    if (live && (state == JobState::preparing || state == JobState::running)) {
        state = live->state;
        stage = live->stage;
        progress = live->progress;
        eta = live->eta_s;
        message = live->message;
    }
    json::object o;
    o["id"] = r.id;
    o["url"] = job_url(r.id);
    o["name"] = r.name;
    o["state"] = to_string(state);
    o["stage"] = stage.empty() ? json::value(nullptr) : json::value(stage);
    o["progress"] = progress;
    o["eta_s"] = eta ? json::value(*eta) : json::value(nullptr);
    o["message"] = message;
    o["error"] = r.error.empty() ? json::value(nullptr) : json::value(r.error);
    o["attempts"] = r.attempts;
    o["created_at"] = format_rfc3339(r.created_ms);
    o["started_at"] = optional_time(r.started_ms);
    o["finished_at"] = optional_time(r.finished_ms);
    json::object links{{"self", job_url(r.id)}};
    if (state == JobState::succeeded) {
        links["summary"] = job_url(r.id) + "/summary";
        links["result"] = job_url(r.id) + "/result.h5";
    }
    o["links"] = std::move(links);
    if (slurm)
        o["slurm"] = json::object{{"prepare_job_id", slurm->prepare}, {"test_array_job_id", slurm->tests},
            {"analyse_job_id", slurm->analyse}, {"submitted_at", format_rfc3339(slurm->submitted_ms)}};
    if (with_spec) {
        // The spec the job runs with (stored_spec: complete as today's
        // wiredem writes it); what the store holds if that does not parse.
        try {
            o["spec"] = api::to_json(stored_spec(r.spec_json));
        } catch (const std::exception&) {
            boost::system::error_code ec;
            o["spec"] = json::parse(r.spec_json, ec);
        }
    }
    return o;
}

std::optional<LiveProgress> live_of(const JobRecord& r, Services& svc)
{
    if (r.state != JobState::preparing && r.state != JobState::running) return std::nullopt;
    return svc.queue.live(r.id);
}

std::string_view header_value(const Request& req, http::field f)
{
    auto it = req.find(f);
    return it == req.end() ? std::string_view() : std::string_view(it->value().data(), it->value().size());
}

std::string_view header_value(const Request& req, std::string_view name)
{
    auto it = req.find(name);
    return it == req.end() ? std::string_view() : std::string_view(it->value().data(), it->value().size());
}

bool is_json_media_type(std::string_view ct)
{
    const auto semi = ct.find(';');
    std::string_view type = ct.substr(0, semi);
    while (!type.empty() && type.back() == ' ') type.remove_suffix(1);
    std::string lower(type);
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return lower == "application/json";
}

Response job_not_found(const Request& req, const std::string& id)
{
    return error_response(req, http::status::not_found, "not_found", "no job " + id, "id");
}

Response not_succeeded(const Request& req, const JobRecord& r)
{
    return error_response(req, http::status::conflict, "not_succeeded",
        "job " + r.id + " is " + std::string(to_string(r.state)) + "; results exist only once it has succeeded",
        "id");
}

} // namespace

std::optional<std::int64_t> parse_positive(std::string_view s)
{
    std::int64_t v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || v <= 0) return std::nullopt;
    return v;
}

std::optional<FieldProblem> job_limit_problem(const api::JobSpec& spec, const ServerConfig& config)
{
    const api::BodyCounts bodies = api::estimated_body_counts(spec);
    if (bodies.total() > config.max_bodies_per_job)
        return FieldProblem{"specimen.grain_count",
            "the job needs about " + std::to_string(bodies.total()) + " bodies ("
                + std::to_string(bodies.grains) + " grains, " + std::to_string(bodies.wire_nodes) + " wire nodes, "
                + std::to_string(bodies.membrane_nodes) + " membrane nodes); this server runs at most "
                + std::to_string(config.max_bodies_per_job)};
    // Work: a valid-looking spec can ask for a job that never ends (δt =
    // 5e-324 s, a plate at 1e-12 m/s, rows every 1e-300 s). The field named
    // is the one that drives the estimate.
    const api::WorkEstimate work = api::estimated_work(spec);
    if (!(work.total_steps() <= config.max_steps_per_job)) {
        const double prep = work.preparation_steps;
        return FieldProblem{api::work_field(spec, work),
            "the job needs about " + format_number(work.total_steps()) + " time steps of "
                + format_number(work.time_step_s) + " s (preparation up to " + format_number(prep) + ", "
                + std::to_string(work.test_steps.size()) + " tests " + format_number(work.tests_total_steps())
                + "); this server runs at most " + format_number(config.max_steps_per_job) + " (--max-steps-per-job)"};
    }
    if (!(work.samples_per_test <= config.max_samples_per_test))
        return FieldProblem{"triaxial.sample_interval_s",
            "a test would record about " + format_number(work.samples_per_test) + " rows; this server keeps at most "
                + format_number(config.max_samples_per_test) + " per test (--max-samples-per-test)"};
    return std::nullopt;
}

bool is_json_content_type(const Request& req) { return is_json_media_type(header_value(req, http::field::content_type)); }

json::object job_resource(const JobRecord& r, Services& svc) { return job_json(r, live_of(r, svc), false); }

Response handle_submit_job(const Request& req, Services& svc)
{
    // A missing Content-Type is refused too: it is what a browser sends for a
    // Blob body, the one cross-site POST that needs no preflight.
    if (auto ct = header_value(req, http::field::content_type); !is_json_media_type(ct))
        return error_response(req, http::status::unsupported_media_type, "unsupported_media_type",
            ct.empty() ? std::string("the job must be sent with Content-Type: application/json")
                       : "the job must be sent as application/json, not " + std::string(ct),
            "Content-Type");

    const std::string_view key = header_value(req, "Idempotency-Key");
    if (req.find("Idempotency-Key") != req.end()) {
        bool ok = !key.empty() && key.size() <= max_idempotency_key_bytes;
        for (char c : key) ok = ok && c > 0x20 && c < 0x7f;
        if (!ok)
            return error_response(req, http::status::bad_request, "bad_header",
                "Idempotency-Key must be 1 to 255 visible ASCII characters", "Idempotency-Key");
    }

    auto doc = api::parse_json_text(req.body());
    if (!doc)
        return error_response(req, http::status::bad_request, "invalid_json",
            "request body is not valid JSON: " + doc.error());
    auto spec = api::parse_job_spec(doc.value());
    if (!spec) {
        std::vector<FieldProblem> details;
        for (const auto& e : spec.error()) details.push_back({e.path, e.message});
        const auto& first = spec.error().front();
        std::string msg = (first.path.empty() ? "" : first.path + ": ") + first.message;
        if (details.size() > 1) msg += " (and " + std::to_string(details.size() - 1) + " more)";
        return error_response(req, http::status::bad_request, "invalid_job", msg, first.path, details);
    }
    if (auto problem = job_limit_problem(spec.value(), svc.config))
        return error_response(
            req, http::status::bad_request, "invalid_job", problem->field + ": " + problem->message, problem->field);

    JobRecord job;
    job.id = make_job_id();
    job.created_ms = now_ms();
    job.name = spec.value().name;
    job.spec_json = json::serialize(api::to_json(spec.value()));
    job.idempotency_key = std::string(key);
    JobRecord stored;
    switch (svc.store.insert(job, svc.config.max_queued, stored)) {
    case InsertOutcome::created: {
        apply_retention(svc);
        svc.metrics.jobs_submitted.fetch_add(1, std::memory_order_relaxed);
        svc.queue.notify();
        auto res = json_response(req, http::status::created, job_json(stored, std::nullopt, false));
        res.set(http::field::location, job_url(stored.id));
        return res;
    }
    case InsertOutcome::replayed: {
        // The same reply as the first time, so a client retrying a lost 201 gets it.
        auto res = json_response(req, http::status::created, job_json(stored, live_of(stored, svc), false));
        res.set(http::field::location, job_url(stored.id));
        res.set("Idempotent-Replayed", "true");
        return res;
    }
    case InsertOutcome::idempotency_conflict:
        return error_response(req, http::status::conflict, "idempotency_conflict",
            "Idempotency-Key was already used for job " + stored.id + " with a different spec",
            "Idempotency-Key");
    case InsertOutcome::queue_full: {
        auto res = error_response(req, http::status::too_many_requests, "queue_full",
            "the queue holds " + std::to_string(svc.config.max_queued) + " jobs already; retry later");
        res.set(http::field::retry_after, std::to_string(svc.config.retry_after.count()));
        return res;
    }
    }
    return error_response(req, http::status::internal_server_error, "internal", "unexpected insert outcome");
}

Response handle_list_jobs(const Request& req, const QueryParams& params, Services& svc)
{
    std::optional<JobState> state;
    int limit = default_page_size;
    std::int64_t cursor = 0;
    std::vector<std::string> seen;
    for (const auto& [key, value] : params) {
        if (std::find(seen.begin(), seen.end(), key) != seen.end())
            return error_response(req, http::status::bad_request, "bad_parameter", "parameter given twice", key);
        seen.push_back(key);
        if (key == "state") {
            state = job_state_from_string(value);
            if (!state)
                return error_response(req, http::status::bad_request, "bad_parameter",
                    "state must be one of queued, preparing, running, succeeded, failed, cancelled", "state");
        } else if (key == "limit") {
            auto v = parse_positive(value);
            if (!v || *v > max_page_size)
                return error_response(req, http::status::bad_request, "bad_parameter",
                    "limit must be an integer in [1, " + std::to_string(max_page_size) + "]", "limit");
            limit = static_cast<int>(*v);
        } else if (key == "cursor") {
            auto v = parse_positive(value);
            if (!v)
                return error_response(req, http::status::bad_request, "bad_parameter",
                    "cursor must be a next_cursor value from an earlier page", "cursor");
            cursor = *v;
        } else {
            return error_response(req, http::status::bad_request, "bad_parameter",
                "unknown parameter (known: state, limit, cursor)", key);
        }
    }
    const auto rows = svc.store.list(state, cursor, limit);
    json::array jobs;
    for (const auto& r : rows) jobs.push_back(job_json(r, live_of(r, svc), false));
    json::object body;
    body["jobs"] = std::move(jobs);
    body["next_cursor"] = static_cast<int>(rows.size()) == limit && !rows.empty()
        ? json::value(std::to_string(rows.back().seq))
        : json::value(nullptr);
    return json_response(req, http::status::ok, body);
}

Response handle_get_job(const Request& req, const std::string& id, Services& svc)
{
    const auto r = svc.store.get(id);
    if (!r) return job_not_found(req, id);
    return json_response(req, http::status::ok, job_json(*r, live_of(*r, svc), true, svc.store.slurm_ids(id)));
}

void apply_retention(Services& svc)
{
    if (svc.config.max_finished_jobs == 0) return;
    for (const auto& id : svc.store.remove_finished_beyond(svc.config.max_finished_jobs))
        if (!remove_job_dir(svc.config.data_dir, id))
            spdlog::warn("job {}: removed by the retention bound, but its folder could not be removed", id);
}

Response handle_delete_job(const Request& req, const std::string& id, const QueryParams& params, Services& svc)
{
    // Removing is asked for in so many words (?remove=true): a cancel that
    // crosses the job's success must not delete its results.
    bool remove = false;
    for (const auto& [key, value] : params) {
        if (key != "remove" || value != "true" || remove)
            return error_response(req, http::status::bad_request, "bad_parameter",
                "the only parameter here is remove=true (delete an ended job with its files)", key);
        remove = true;
    }
    if (!remove) {
        switch (svc.store.cancel(id)) {
        case CancelOutcome::not_found: return job_not_found(req, id);
        case CancelOutcome::already_final: {
            const auto r = svc.store.get(id);
            return error_response(req, http::status::conflict, "already_finished",
                "job " + id + " already " + std::string(to_string(r ? r->state : JobState::failed))
                    + " (DELETE ?remove=true deletes it with its files)",
                "id");
        }
        case CancelOutcome::cancelled: svc.queue.cancel(id); break;
        case CancelOutcome::already_cancelled: break;  // cancelling twice is harmless
        }
        const auto r = svc.store.get(id);
        if (!r) return job_not_found(req, id);
        return json_response(req, http::status::ok, job_json(*r, std::nullopt, false));
    }
    // The row first: a crash between the two leaves a folder no job names,
    // never a job without its files.
    switch (svc.store.remove(id)) {
    case RemoveOutcome::not_found: return job_not_found(req, id);
    case RemoveOutcome::not_final:
        return error_response(req, http::status::conflict, "not_finished",
            "job " + id + " has not ended; cancel it first (DELETE without ?remove)", "id");
    case RemoveOutcome::in_study:
        return error_response(req, http::status::conflict, "in_study",
            "job " + id + " is a point of a study and stays with it", "id");
    case RemoveOutcome::removed: break;
    }
    if (!remove_job_dir(svc.config.data_dir, id))
        spdlog::warn("job {}: deleted, but its folder could not be removed", id);
    return no_content_response(req);
}

Response handle_get_summary(const Request& req, const std::string& id, Services& svc)
{
    const auto r = svc.store.get(id);
    if (!r) return job_not_found(req, id);
    if (r->state != JobState::succeeded) return not_succeeded(req, *r);
    const auto text = read_job_file(svc.config.data_dir, id, "summary.json", max_summary_bytes);
    if (!text)
        return error_response(req, http::status::internal_server_error, "internal",
            "summary of job " + id + " cannot be read");
    return text_response(req, http::status::ok, *text, "application/json");
}

RangeRequest parse_range(std::string_view header, std::uint64_t size)
{
    RangeRequest out;
    constexpr std::string_view unit = "bytes=";
    if (header.substr(0, unit.size()) != unit) return out;
    std::string_view spec = header.substr(unit.size());
    while (!spec.empty() && spec.front() == ' ') spec.remove_prefix(1);
    while (!spec.empty() && spec.back() == ' ') spec.remove_suffix(1);
    if (spec.find(',') != std::string_view::npos) return out;  // several ranges: send everything
    const auto dash = spec.find('-');
    if (dash == std::string_view::npos) return out;
    const std::string_view a = spec.substr(0, dash);
    const std::string_view b = spec.substr(dash + 1);
    auto number = [](std::string_view s, std::uint64_t& v) {
        if (s.empty()) return false;
        auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        return ec == std::errc() && p == s.data() + s.size();
    };
    std::uint64_t first = 0;
    std::uint64_t last = 0;
    if (a.empty()) {  // suffix: the last n bytes
        std::uint64_t n = 0;
        if (!number(b, n)) return out;
        if (n == 0 || size == 0) {
            out.kind = RangeRequest::Kind::unsatisfiable;
            return out;
        }
        first = n >= size ? 0 : size - n;
        last = size - 1;
    } else {
        if (!number(a, first)) return out;
        if (b.empty()) last = size == 0 ? 0 : size - 1;
        else if (!number(b, last) || last < first) return out;
        if (first >= size) {
            out.kind = RangeRequest::Kind::unsatisfiable;
            return out;
        }
        last = std::min(last, size - 1);
    }
    out.kind = RangeRequest::Kind::range;
    out.range = {first, last - first + 1};
    return out;
}

Response handle_get_result(const Request& req, const std::string& id, Services& svc)
{
    const auto r = svc.store.get(id);
    if (!r) return job_not_found(req, id);
    if (r->state != JobState::succeeded) return not_succeeded(req, *r);

    // `id` is 24 hex digits, so this path stays inside the data directory;
    // no symlink on the way is followed (job_files.hpp).
    UniqueFd file = open_job_file(svc.config.data_dir, id, "result.h5");
    if (!file)
        return error_response(req, http::status::internal_server_error, "internal",
            "result of job " + id + " cannot be opened");
    const int fd = file.release();
    auto owned = std::shared_ptr<int>(new int(fd), [](int* p) {
        ::close(*p);
        delete p;
    });
    struct stat st{};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
        return error_response(req, http::status::internal_server_error, "internal",
            "result of job " + id + " is not a regular file");
    const auto size = static_cast<std::uint64_t>(st.st_size);
    char etag_buf[64];
    std::snprintf(etag_buf, sizeof etag_buf, "\"%llx-%llx\"", static_cast<unsigned long long>(size),
        static_cast<unsigned long long>(st.st_mtim.tv_sec) * 1000000000ull
            + static_cast<unsigned long long>(st.st_mtim.tv_nsec));
    const std::string etag = etag_buf;

    RangeRequest range;
    if (auto h = header_value(req, http::field::range); !h.empty()) {
        const auto if_range = header_value(req, http::field::if_range);
        if (if_range.empty() || if_range == etag) range = parse_range(h, size);
    }
    if (range.kind == RangeRequest::Kind::unsatisfiable) {
        auto res = error_response(req, http::status::range_not_satisfiable, "range_not_satisfiable",
            "the file has " + std::to_string(size) + " bytes", "Range");
        res.set(http::field::content_range, "bytes */" + std::to_string(size));
        return res;
    }
    FileResponse res{range.kind == RangeRequest::Kind::range ? http::status::partial_content : http::status::ok,
        req.version()};
    res.set(http::field::server, server_name);
    res.set(http::field::content_type, "application/x-hdf5");
    res.set(http::field::content_disposition, "attachment; filename=\"" + id + ".h5\"");
    res.set(http::field::accept_ranges, "bytes");
    res.set(http::field::etag, etag);
    res.keep_alive(req.keep_alive());
    res.body().fd = std::move(owned);
    res.body().offset = 0;
    res.body().length = size;
    if (range.kind == RangeRequest::Kind::range) {
        res.body().offset = range.range.first;
        res.body().length = range.range.length;
        res.set(http::field::content_range, "bytes " + std::to_string(range.range.first) + "-"
                + std::to_string(range.range.first + range.range.length - 1) + "/" + std::to_string(size));
    }
    res.content_length(res.body().length);
    return res;
}

} // namespace wiredem::server
