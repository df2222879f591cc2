#include "studies.hpp"

#include "../job_files.hpp"
#include "jobs.hpp"

#include "api/json_text.hpp"
#include "api/study.hpp"

#include <boost/json.hpp>
#include <spdlog/spdlog.h>

#include <charconv>
#include <fstream>
#include <sstream>

namespace wiredem::server {
namespace json = boost::json;

namespace {

/// A stored summary.json is read whole for the study summary; one larger than
/// this is not a runner's (they are a few kB).
constexpr std::uintmax_t max_summary_bytes = 16 * 1024 * 1024;

std::string study_url(const std::string& id) { return "/v1/studies/" + id; }

Response study_not_found(const Request& req, const std::string& id)
{
    return error_response(req, http::status::not_found, "not_found", "no study " + id, "id");
}

/// The stored document parsed again: it was valid when stored, and every
/// point's values come from it (the same expansion as at submit).
api::Study parse_stored(const StudyRecord& r)
{
    auto s = api::parse_study(std::string_view(r.document_json), r.job_ids.size());
    if (!s.ok() || s.value().points.size() != r.job_ids.size())
        throw std::runtime_error("study " + r.id + " has a stored document that no longer expands to its jobs");
    return std::move(s.value());
}

/// Jobs by state, as a list and the study itself show them.
json::object counts_json(const StateCounts& counts)
{
    json::object c;
    for (JobState s : all_job_states) c[to_string(s)] = counts[static_cast<std::size_t>(s)];
    return c;
}

StateCounts counts(const std::vector<std::optional<JobRecord>>& jobs)
{
    StateCounts c{};
    for (const auto& j : jobs)
        if (j) ++c[static_cast<std::size_t>(j->state)];
    return c;
}

std::vector<std::optional<JobRecord>> jobs_of(const StudyRecord& r, Services& svc)
{
    std::vector<std::optional<JobRecord>> jobs;
    for (const auto& id : r.job_ids) jobs.push_back(svc.store.get(id));
    return jobs;
}

/// A study's resource (StudyInfo); a list shows it for each study.
json::object study_json(const StudyListRow& r)
{
    json::object o;
    o["id"] = r.id;
    o["url"] = study_url(r.id);
    o["name"] = r.name;
    o["created_at"] = format_rfc3339(r.created_ms);
    o["points"] = r.points;
    o["jobs_by_state"] = counts_json(r.jobs_by_state);
    o["links"] = json::object{{"self", study_url(r.id)}, {"summary", study_url(r.id) + "/summary"}};
    return o;
}

json::object study_json(const StudyRecord& r, const std::vector<std::optional<JobRecord>>& jobs)
{
    return study_json(StudyListRow{r.seq, r.id, r.name, r.created_ms, r.job_ids.size(), counts(jobs)});
}

std::optional<json::value> read_summary(const std::filesystem::path& file)
{
    std::error_code ec;
    const auto size = std::filesystem::file_size(file, ec);
    if (ec || size > max_summary_bytes) return std::nullopt;
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    // Correctly rounded, so that the summary's figures are the runner's.
    auto v = api::parse_json_text(text.str());
    if (!v) return std::nullopt;
    return std::move(v).value();
}

} // namespace

Response handle_submit_study(const Request& req, Services& svc)
{
    if (!is_json_content_type(req))
        return error_response(req, http::status::unsupported_media_type, "unsupported_media_type",
            "the study must be sent with Content-Type: application/json", "Content-Type");
    auto doc = api::parse_json_text(req.body());
    if (!doc)
        return error_response(req, http::status::bad_request, "invalid_json",
            "request body is not valid JSON: " + doc.error());
    auto study = api::parse_study(doc.value(), svc.config.max_study_points);
    std::vector<FieldProblem> details;
    if (!study) {
        for (const auto& e : study.error()) details.push_back({e.path, e.message});
    } else {
        // Every point against this server's limits, named like the parser's errors.
        for (std::size_t k = 0; k < study.value().points.size(); ++k) {
            const api::StudyPoint& p = study.value().points[k];
            if (auto problem = job_limit_problem(p.spec, svc.config))
                details.push_back({"points[" + std::to_string(k) + "] (" + p.label + "): " + problem->field, problem->message});
        }
    }
    if (!details.empty()) {
        std::string msg = (details.front().field.empty() ? "" : details.front().field + ": ") + details.front().message;
        if (details.size() > 1) msg += " (and " + std::to_string(details.size() - 1) + " more)";
        return error_response(req, http::status::bad_request, "invalid_study", msg, details.front().field, details);
    }

    StudyRecord record;
    record.id = make_job_id();
    record.name = study.value().name;
    record.created_ms = now_ms();
    record.document_json = json::serialize(doc.value());
    std::vector<JobRecord> jobs;
    for (const api::StudyPoint& p : study.value().points) {
        JobRecord j;
        j.id = make_job_id();
        j.created_ms = record.created_ms;
        j.name = p.spec.name;
        j.spec_json = json::serialize(api::to_json(p.spec));
        jobs.push_back(std::move(j));
    }
    StudyRecord stored;
    if (svc.store.insert_study(record, jobs, svc.config.max_queued, stored) == InsertOutcome::queue_full) {
        auto res = error_response(req, http::status::too_many_requests, "queue_full",
            "the study's " + std::to_string(jobs.size()) + " jobs do not fit in the queue (at most "
                + std::to_string(svc.config.max_queued) + " queued jobs, --max-queued); retry later");
        res.set(http::field::retry_after, std::to_string(svc.config.retry_after.count()));
        return res;
    }
    svc.metrics.jobs_submitted.fetch_add(jobs.size(), std::memory_order_relaxed);
    svc.queue.notify();
    apply_retention(svc);
    auto res = json_response(req, http::status::created, study_json(stored, jobs_of(stored, svc)));
    res.set(http::field::location, study_url(stored.id));
    return res;
}

Response handle_list_studies(const Request& req, const QueryParams& params, Services& svc)
{
    int limit = default_page_size;
    std::int64_t cursor = 0;
    std::vector<std::string> seen;
    for (const auto& [key, value] : params) {
        if (std::find(seen.begin(), seen.end(), key) != seen.end())
            return error_response(req, http::status::bad_request, "bad_parameter", "parameter given twice", key);
        seen.push_back(key);
        if (key == "limit") {
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
                "unknown parameter (known: limit, cursor)", key);
        }
    }
    const auto rows = svc.store.list_studies(cursor, limit);
    json::array studies;
    for (const auto& r : rows) studies.push_back(study_json(r));
    json::object body;
    body["studies"] = std::move(studies);
    body["next_cursor"] = static_cast<int>(rows.size()) == limit && !rows.empty()
        ? json::value(std::to_string(rows.back().seq))
        : json::value(nullptr);
    return json_response(req, http::status::ok, body);
}

Response handle_get_study(const Request& req, const std::string& id, Services& svc)
{
    const auto r = svc.store.get_study(id);
    if (!r) return study_not_found(req, id);
    const api::Study study = parse_stored(*r);
    const auto jobs = jobs_of(*r, svc);
    json::object o = study_json(*r, jobs);
    json::array points;
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        json::object p;
        p["index"] = k;
        p["label"] = study.points[k].label;
        json::object values;
        for (const auto& [path, value] : study.points[k].values) values[path] = value;
        p["values"] = std::move(values);
        p["job"] = jobs[k] ? json::value(job_resource(*jobs[k], svc)) : json::value(nullptr);
        points.push_back(std::move(p));
    }
    o["jobs"] = std::move(points);
    if (auto doc = api::parse_json_text(r->document_json)) o["document"] = std::move(doc).value();
    return json_response(req, http::status::ok, o);
}

Response handle_delete_study(const Request& req, const std::string& id, const QueryParams& params, Services& svc)
{
    // As a job's DELETE (handlers/jobs.cpp): removing is asked for in so many
    // words (?remove=true), and only once every job of the study has ended.
    bool remove = false;
    for (const auto& [key, value] : params) {
        if (key != "remove" || value != "true" || remove)
            return error_response(req, http::status::bad_request, "bad_parameter",
                "the only parameter here is remove=true (delete an ended study with its jobs and their files)", key);
        remove = true;
    }
    if (remove) {
        std::vector<std::string> job_ids;
        switch (svc.store.remove_study(id, job_ids)) {
        case RemoveOutcome::not_found: return study_not_found(req, id);
        case RemoveOutcome::not_final:
        case RemoveOutcome::in_study:
            return error_response(req, http::status::conflict, "not_finished",
                "study " + id + " has jobs that have not ended; cancel it first (DELETE without ?remove)", "id");
        case RemoveOutcome::removed: break;
        }
        for (const auto& job : job_ids)
            if (!remove_job_dir(svc.config.data_dir, job))
                spdlog::warn("job {}: deleted with study {}, but its folder could not be removed", job, id);
        return no_content_response(req);
    }
    const auto r = svc.store.get_study(id);
    if (!r) return study_not_found(req, id);
    for (const auto& job : r->job_ids)
        if (svc.store.cancel(job) == CancelOutcome::cancelled) svc.queue.cancel(job);
    return json_response(req, http::status::ok, study_json(*r, jobs_of(*r, svc)));
}

Response handle_get_study_summary(const Request& req, const std::string& id, Services& svc)
{
    const auto r = svc.store.get_study(id);
    if (!r) return study_not_found(req, id);
    const api::Study study = parse_stored(*r);
    const auto jobs = jobs_of(*r, svc);
    std::vector<api::PointOutcome> outcomes;
    for (const auto& j : jobs) {
        api::PointOutcome o;
        if (!j) {
            o.state = "missing";
        } else {
            o.job_id = j->id;
            o.state = to_string(j->state);
            o.error = j->error;
            if (j->state == JobState::succeeded)
                o.summary = read_summary(svc.config.data_dir / "jobs" / j->id / "summary.json");
        }
        outcomes.push_back(std::move(o));
    }
    json::object summary = api::study_summary(study, outcomes);
    summary["id"] = r->id;
    return json_response(req, http::status::ok, summary);
}

} // namespace wiredem::server
