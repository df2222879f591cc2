// The subcommands. Every server reply goes through check_reply, which turns
// an error reply into one line and the exit code of its class.
#include "commands.hpp"

#include "display.hpp"
#include "local_file.hpp"
#include "run_command.hpp"

#include "api/job_spec.hpp"
#include "api/json_text.hpp"
#include "api/study.hpp"

#include <boost/json.hpp>

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <limits>
#include <iostream>
#include <random>
#include <sstream>
#include <thread>

namespace wiredem::client {
namespace json = boost::json;
namespace fs = std::filesystem;
using clock_type = std::chrono::steady_clock;

namespace {

constexpr const char* default_server = "http://127.0.0.1:8080";

std::string read_file(const fs::path& p, const char* what)
{
    std::ifstream in(p, std::ios::binary);
    if (!in) throw CommandError(exit_code::local_io, std::string("cannot read ") + what + " " + p.string());
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string read_token(const std::string& file)
{
    std::string t = read_file(file, "token file");
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.pop_back();
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front()))) t.erase(0, 1);
    if (t.empty()) throw CommandError(exit_code::usage, "token file " + file + " is empty");
    return t;
}

HttpClient make_client(const GlobalOptions& g)
{
    std::string url = g.server_url;
    if (url.empty())
        if (const char* env = std::getenv("WIREDEM_SERVER"); env && *env) url = env;
    if (url.empty()) url = default_server;
    std::string token_file = g.token_file;
    if (token_file.empty())
        if (const char* env = std::getenv("WIREDEM_TOKEN_FILE"); env && *env) token_file = env;
    return HttpClient(parse_server_url(url), token_file.empty() ? std::string() : read_token(token_file), g.timeout);
}

/// `what`: "job" or "study", as the command names its id.
void check_id(const std::string& id, std::string_view what = "job")
{
    bool ok = id.size() == 24;
    for (char c : id) ok = ok && ((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'));
    if (!ok)
        throw CommandError(exit_code::usage,
            "'" + printable(id) + "' is not a " + std::string(what) + " id (24 lower-case hex digits)");
}

/// Throws CommandError for any reply that is not 2xx, with the server's own
/// message and the exit code of its class.
void check_reply(const HttpReply& r, const std::string& what)
{
    if (r.status >= 200 && r.status < 300) return;
    boost::system::error_code ec;
    const json::value doc = json::parse(r.body, ec);
    std::string code;
    std::string message;
    std::string details;
    if (const auto* err = ec ? nullptr : doc.is_object() ? doc.as_object().if_contains("error") : nullptr;
        err && err->is_object()) {
        const auto& e = err->get_object();
        if (auto* c = e.if_contains("code"); c && c->is_string()) code = std::string(c->get_string());
        if (auto* m = e.if_contains("message"); m && m->is_string()) message = std::string(m->get_string());
        if (auto* d = e.if_contains("details"); d && d->is_array() && d->get_array().size() > 1)
            for (const auto& item : d->get_array())
                if (item.is_object()) {
                    const auto& o = item.get_object();
                    auto* f = o.if_contains("field");
                    auto* m = o.if_contains("message");
                    details += "\n  " + printable((f && f->is_string() ? std::string(f->get_string()) + ": " : std::string())
                        + (m && m->is_string() ? std::string(m->get_string()) : std::string()));
                }
    }
    if (message.empty()) message = "HTTP " + std::to_string(r.status);
    std::string line = what + ": " + printable(message) + " (HTTP " + std::to_string(r.status) + ")";
    if (r.status == 429 && !r.header("retry-after").empty()) line += "; retry after " + r.header("retry-after") + " s";
    int exit = exit_code::server_refused;
    // A study refused is a file that is not valid, as a job refused is (3).
    if (r.status == 400 && (code == "invalid_job" || code == "invalid_json" || code == "invalid_study"))
        exit = exit_code::invalid_job;
    else if (r.status == 401 || r.status == 403) exit = exit_code::unauthorized;
    else if (r.status == 404) exit = exit_code::not_found;
    throw CommandError(exit, line + details);
}

/// The reply's JSON, numbers read correctly rounded (api::parse_json_text;
/// Boost.JSON's own parser may miss the last bit, and a figure fetched must
/// equal the figure computed).
json::value parse_reply(const HttpReply& r, const std::string& what)
{
    auto v = api::parse_json_text(r.body);
    if (!v) throw CommandError(exit_code::network, what + ": the server's reply is not JSON");
    return std::move(v).value();
}

std::string str(const json::value& v, std::string_view key)
{
    if (const auto* o = v.if_object())
        if (const auto* s = o->if_contains(key); s && s->is_string()) return std::string(s->get_string());
    return {};
}

void print_json(const json::value& v) { std::cout << json::serialize(v) << std::endl; }

api::JobSpec load_job(const fs::path& file)
{
    const std::string text = read_file(file, "job file");
    auto spec = api::parse_job_spec(std::string_view(text));
    if (spec) return std::move(spec).value();
    std::string msg = "job file " + file.string() + " is not a valid job:";
    for (const auto& e : spec.error()) msg += "\n  " + (e.path.empty() ? std::string() : e.path + ": ") + e.message;
    throw CommandError(exit_code::invalid_job, msg);
}

std::string random_key()
{
    std::random_device rd;
    char buf[33];
    std::snprintf(buf, sizeof buf, "%08x%08x%08x%08x", rd(), rd(), rd(), rd());
    return buf;
}

int exit_for_state(const std::string& state)
{
    if (state == "succeeded") return exit_code::ok;
    if (state == "cancelled") return exit_code::job_cancelled;
    return exit_code::job_failed;
}

bool is_final(const std::string& state) { return state == "succeeded" || state == "failed" || state == "cancelled"; }

int wait_for(HttpClient& client, const GlobalOptions& g, const std::string& id, const WaitOptions& w)
{
    const bool tty = !g.json && ::isatty(STDOUT_FILENO);
    const auto started = clock_type::now();
    std::optional<clock_type::time_point> failing_since;
    std::string last_state;
    std::string last_stage;
    double last_progress = -1.0;
    const auto interval = std::chrono::duration<double>(std::max(0.05, w.interval_s));
    for (;;) {
        HttpReply reply;
        try {
            reply = client.request(Method::get, "/v1/jobs/" + id);
            failing_since.reset();
        } catch (const CommandError& e) {
            // A server restarting (crash, upgrade) is not the end of a job: keep
            // trying for a minute, the job is durable.
            if (e.code != exit_code::network) throw;
            if (!failing_since) failing_since = clock_type::now();
            if (clock_type::now() - *failing_since > std::chrono::seconds(60)) throw;
            std::this_thread::sleep_for(interval);
            continue;
        }
        check_reply(reply, "job " + id);
        const json::value job = parse_reply(reply, "job " + id);
        const std::string state = str(job, "state");
        const std::string stage = str(job, "stage");
        double progress = 0.0;
        if (const auto* p = job.as_object().if_contains("progress"); p && p->is_number()) progress = p->to_number<double>();
        if (tty) {
            std::cout << '\r' << format_progress_bar(job, 30) << "\x1b[K" << std::flush;
        } else if (!g.json && (state != last_state || stage != last_stage || progress >= last_progress + 0.1)) {
            std::cout << format_progress_line(job) << std::endl;
            last_progress = progress;
        }
        last_state = state;
        last_stage = stage;
        if (is_final(state)) {
            if (tty) std::cout << '\n';
            if (g.json) print_json(job);
            else if (state == "succeeded") std::cout << "job " << id << " succeeded" << std::endl;
            else if (state == "cancelled") std::cerr << "wiredem: job " << id << " was cancelled" << std::endl;
            else std::cerr << "wiredem: job " << id << " failed: " << printable(str(job, "error")) << std::endl;
            return exit_for_state(state);
        }
        if (w.timeout_s && std::chrono::duration<double>(clock_type::now() - started).count() > *w.timeout_s) {
            if (tty) std::cout << '\n';
            throw CommandError(exit_code::wait_timeout, "job " + id + " still " + state + " after " + format_duration(*w.timeout_s));
        }
        std::this_thread::sleep_for(interval);
    }
}

} // namespace

int cmd_submit(const GlobalOptions& g, const fs::path& job_file, bool wait, const WaitOptions& w)
{
    const api::JobSpec spec = load_job(job_file);  // the server's own validation, before sending
    auto client = make_client(g);
    const std::string body = json::serialize(api::to_json(spec));
    // The key makes a retry after a lost reply safe: the server answers with the first job.
    const std::string key = random_key();
    HttpReply reply;
    for (int attempt = 1;; ++attempt) {
        try {
            reply = client.request(Method::post, "/v1/jobs", body, {{"Idempotency-Key", key}});
            break;
        } catch (const CommandError& e) {
            if (e.code != exit_code::network || attempt == 3) throw;
            std::this_thread::sleep_for(std::chrono::seconds(1));
        }
    }
    check_reply(reply, "submit " + job_file.string());
    const json::value job = parse_reply(reply, "submit");
    const std::string id = str(job, "id");
    if (g.json && !wait) print_json(job);
    else if (!g.json) std::cout << id << std::endl;
    return wait ? wait_for(client, g, id, w) : exit_code::ok;
}

int cmd_status(const GlobalOptions& g, const std::string& id)
{
    check_id(id);
    auto client = make_client(g);
    const auto reply = client.request(Method::get, "/v1/jobs/" + id);
    check_reply(reply, "job " + id);
    const json::value job = parse_reply(reply, "job " + id);
    if (g.json) print_json(job);
    else std::cout << format_job(job);
    return exit_code::ok;
}

int cmd_wait(const GlobalOptions& g, const std::string& id, const WaitOptions& w)
{
    check_id(id);
    auto client = make_client(g);
    return wait_for(client, g, id, w);
}

int cmd_list(const GlobalOptions& g, const std::string& state, int limit, bool all)
{
    auto client = make_client(g);
    json::array jobs;
    std::string cursor;
    json::value next = nullptr;
    do {
        std::string target = "/v1/jobs?limit=" + std::to_string(limit);
        if (!state.empty()) target += "&state=" + state;
        if (!cursor.empty()) target += "&cursor=" + cursor;
        const auto reply = client.request(Method::get, target);
        check_reply(reply, "list");
        json::value page = parse_reply(reply, "list");
        if (auto* arr = page.as_object().if_contains("jobs"); arr && arr->is_array())
            for (auto& j : arr->as_array()) jobs.push_back(std::move(j));
        next = page.as_object().contains("next_cursor") ? page.as_object()["next_cursor"] : json::value(nullptr);
        cursor = next.is_string() ? std::string(next.get_string()) : std::string();
    } while (all && !cursor.empty());
    json::object out{{"jobs", std::move(jobs)}, {"next_cursor", all ? json::value(nullptr) : next}};
    if (g.json) print_json(out);
    else std::cout << format_job_list(out);
    return exit_code::ok;
}

int cmd_cancel(const GlobalOptions& g, const std::string& id)
{
    check_id(id);
    auto client = make_client(g);
    const auto reply = client.request(Method::del, "/v1/jobs/" + id);
    check_reply(reply, "cancel " + id);
    const json::value job = parse_reply(reply, "cancel " + id);
    if (g.json) print_json(job);
    else std::cout << "job " << id << " " << str(job, "state") << std::endl;
    return exit_code::ok;
}

int cmd_summary(const GlobalOptions& g, const std::string& id)
{
    check_id(id);
    auto client = make_client(g);
    const auto reply = client.request(Method::get, "/v1/jobs/" + id + "/summary");
    check_reply(reply, "summary of " + id);
    const json::value summary = parse_reply(reply, "summary of " + id);
    if (g.json) print_json(summary);
    else std::cout << format_summary(summary);
    return exit_code::ok;
}

int cmd_fetch(const GlobalOptions& g, const std::string& id, const fs::path& dir)
{
    check_id(id);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw CommandError(exit_code::local_io, "cannot create " + dir.string() + ": " + ec.message());
    auto client = make_client(g);
    const std::string base = "/v1/jobs/" + id;

    const auto summary = client.request(Method::get, base + "/summary");
    check_reply(summary, "summary of " + id);
    const fs::path summary_file = dir / "summary.json";
    write_local_file(summary_file, summary.body);

    const auto head = client.request(Method::head, base + "/result.h5");
    check_reply(head, "result of " + id);
    std::uint64_t total = 0;
    try {
        total = std::stoull(head.header("content-length"));
    } catch (const std::exception&) {
        throw CommandError(exit_code::server_refused, "result of " + id + ": the server sent no Content-Length");
    }
    // Which result this is: the server's ETag, kept beside the partial and
    // the finished file. A partial is resumed (Range + If-Range) only if it is
    // of this result, and a finished file is taken as complete only if it is:
    // a .part left by another job must not be spliced with these bytes.
    const std::string etag = head.header("etag");
    if (etag.empty()) throw CommandError(exit_code::server_refused, "result of " + id + ": the server sent no ETag");
    const fs::path final_file = dir / "result.h5", final_tag = dir / "result.h5.etag";
    const fs::path part = dir / "result.h5.part", part_tag = dir / "result.h5.part.etag";
    const auto tag_of = [&](const fs::path& f) {
        std::ifstream in(f, std::ios::binary);
        std::string t;
        std::getline(in, t);
        return t;
    };
    const auto write_tag = [&](const fs::path& f) {
        std::ofstream out(f, std::ios::binary | std::ios::trunc);
        out << etag << '\n';
        out.close();
        if (!out) throw CommandError(exit_code::local_io, "cannot write " + f.string());
    };
    std::uint64_t resumed_from = 0;
    const bool have_final = fs::is_regular_file(final_file, ec) && fs::file_size(final_file, ec) == total
                         && tag_of(final_tag) == etag;
    if (!have_final) {
        const bool same_result = fs::is_regular_file(part, ec) && tag_of(part_tag) == etag;
        std::uint64_t offset = same_result ? fs::file_size(part, ec) : 0;
        if (offset > total) offset = 0;
        if (offset == 0) fs::remove(part, ec);
        write_tag(part_tag);
        resumed_from = offset;
        if (offset < total || total == 0) {
            const bool tty = !g.json && ::isatty(STDERR_FILENO);
            auto show = [&](std::uint64_t bytes) {
                if (tty) std::cerr << "\rresult.h5  " << bytes / 1024 << " / " << total / 1024 << " KiB" << std::flush;
            };
            auto reply = client.download(base + "/result.h5", part, offset, etag, show);
            if (reply.status == 416) {  // the part file is not a prefix of this result: start again
                resumed_from = 0;
                reply = client.download(base + "/result.h5", part, 0, etag, show);
            }
            if (reply.status == 200) resumed_from = 0; // the server sent it whole (If-Range did not match)
            if (tty) std::cerr << '\n';
            check_reply(reply, "result of " + id);
            if (reply.header("etag") != etag)
                throw CommandError(exit_code::server_refused, "result of " + id
                        + " changed while it was downloaded (ETag " + reply.header("etag") + ", was " + etag
                        + "); run fetch again");
        }
        const std::uint64_t got = fs::file_size(part, ec);
        if (ec || got != total)
            throw CommandError(exit_code::network, "result of " + id + ": got " + std::to_string(got) + " of "
                    + std::to_string(total) + " bytes; run fetch again to resume");
        fs::rename(part, final_file, ec);
        if (ec) throw CommandError(exit_code::local_io, "cannot write " + final_file.string() + ": " + ec.message());
        fs::rename(part_tag, final_tag, ec);
        if (ec) throw CommandError(exit_code::local_io, "cannot write " + final_tag.string() + ": " + ec.message());
    }
    if (g.json) {
        print_json(json::object{{"summary", summary_file.string()}, {"result", final_file.string()},
            {"bytes", total}, {"resumed_from", resumed_from}});
    } else {
        std::cout << summary_file.string() << '\n'
                  << final_file.string() << "  (" << total << " bytes"
                  << (have_final ? ", already complete" : resumed_from > 0 ? ", resumed at byte " + std::to_string(resumed_from) : "")
                  << ")" << std::endl;
    }
    return exit_code::ok;
}

int cmd_health(const GlobalOptions& g)
{
    auto client = make_client(g);
    const auto reply = client.request(Method::get, "/v1/health");
    check_reply(reply, "health");
    const json::value h = parse_reply(reply, "health");
    if (g.json) print_json(h);
    else std::cout << str(h, "status") << "  " << json::serialize(h) << std::endl;
    return exit_code::ok;
}

namespace {

StageOptions stage_options(const LocalStage& s)
{
    StageOptions o;
    o.threads = s.threads ? s.threads : std::max(1u, std::thread::hardware_concurrency());
    o.json_progress = s.progress == "json";
    o.checkpoint_interval_s = s.checkpoint_interval_s;
    o.lock_wait_s = s.lock_wait_s;
    o.specimen_from = s.specimen_from;
    return o;
}

void make_job_directory(const fs::path& dir)
{
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw CommandError(exit_code::local_io, "cannot create " + dir.string() + ": " + ec.message());
}

} // namespace

int cmd_run(const LocalStage& s)
{
    const api::JobSpec spec = load_job(s.job_file);
    make_job_directory(s.dir);
    return run_campaign_main(spec, s.dir, stage_options(s));
}

int cmd_prepare(const LocalStage& s)
{
    const api::JobSpec spec = load_job(s.job_file);
    make_job_directory(s.dir);
    return prepare_main(spec, s.dir, stage_options(s));
}

int cmd_test(const LocalStage& s)
{
    if (s.free_standing) return free_standing_test_main(s.dir, stage_options(s));
    return test_main(s.dir, s.index, s.pressure_pa, stage_options(s));
}

int cmd_analyse(const LocalStage& s) { return analyse_main(s.dir, stage_options(s)); }

namespace {

/// The study in `text`, read from `file` (named in the error).
api::Study parse_study_file(const std::string& text, const fs::path& file, std::size_t max_points)
{
    auto study = api::parse_study(std::string_view(text), max_points);
    if (!study) {
        std::string msg = "study file " + file.string() + " is not a valid study:";
        for (const auto& e : study.error())
            msg += "\n  " + (e.path.empty() ? std::string() : printable(e.path) + ": ") + printable(e.message);
        throw CommandError(exit_code::invalid_job, msg);
    }
    return std::move(study).value();
}

api::Study load_study(const fs::path& file, std::size_t max_points)
{
    return parse_study_file(read_file(file, "study file"), file, max_points);
}

/// "3 succeeded, 1 running, 2 queued": the non-zero counts of a study.
std::string counts_text(const json::value& study)
{
    std::string out;
    const json::value* c = study.is_object() ? study.as_object().if_contains("jobs_by_state") : nullptr;
    if (!c || !c->is_object()) return "-";
    for (const auto& kv : c->as_object())
        if (kv.value().is_number() && kv.value().to_number<double>() > 0) {
            if (!out.empty()) out += ", ";
            out += std::to_string(kv.value().to_number<long long>()) + " " + printable(kv.key());
        }
    return out.empty() ? "no jobs" : out;
}

/// Whether every job of the study has ended, and whether all succeeded.
std::pair<bool, bool> study_ended(const json::value& study)
{
    const json::value* c = study.as_object().if_contains("jobs_by_state");
    if (!c || !c->is_object()) return {false, false};
    auto count = [&](const char* s) {
        const json::value* v = c->as_object().if_contains(s);
        return v && v->is_number() ? v->to_number<long long>() : 0;
    };
    const long long active = count("queued") + count("preparing") + count("running");
    const long long bad = count("failed") + count("cancelled");
    return {active == 0, active == 0 && bad == 0};
}

} // namespace

int cmd_study_check(const GlobalOptions& g, const fs::path& study_file, std::size_t max_points)
{
    const api::Study study = load_study(study_file, max_points);
    if (g.json) {
        json::array points;
        for (const auto& p : study.points) points.push_back(api::to_json(p.spec));
        print_json(json::object{{"name", study.name}, {"jobs", std::move(points)}});
        return exit_code::ok;
    }
    std::cout << "study " << printable(study.name) << ": " << study.points.size() << " points, every one a valid job\n";
    for (std::size_t k = 0; k < study.points.size(); ++k)
        std::cout << "  " << k << "  " << printable(study.points[k].label) << "\n";
    return exit_code::ok;
}

int cmd_study_submit(const GlobalOptions& g, const fs::path& study_file, bool wait, const WaitOptions& w)
{
    // The document as written goes to the server, after the same checks
    // (the server also applies its own limit on points).
    // Read once: a pipe or /dev/stdin gives its bytes only once.
    const std::string body = read_file(study_file, "study file");
    (void)parse_study_file(body, study_file, std::numeric_limits<std::size_t>::max());
    auto client = make_client(g);
    const auto reply = client.request(Method::post, "/v1/studies", body);
    check_reply(reply, "submit " + study_file.string());
    const json::value study = parse_reply(reply, "submit");
    const std::string id = str(study, "id");
    if (g.json && !wait) print_json(study);
    else if (!g.json) std::cout << id << std::endl;
    return wait ? cmd_study_wait(g, id, w) : exit_code::ok;
}

int cmd_study_status(const GlobalOptions& g, const std::string& id)
{
    check_id(id, "study");
    auto client = make_client(g);
    const auto reply = client.request(Method::get, "/v1/studies/" + id);
    check_reply(reply, "study " + id);
    const json::value study = parse_reply(reply, "study " + id);
    if (g.json) {
        print_json(study);
        return exit_code::ok;
    }
    std::cout << "study  " << printable(str(study, "name")) << " (" << id << ")\njobs   " << counts_text(study) << "\n";
    if (const auto* jobs = study.as_object().if_contains("jobs"); jobs && jobs->is_array())
        for (const auto& p : jobs->as_array()) {
            const json::value* job = p.as_object().if_contains("job");
            std::cout << "  " << printable(str(p, "label")) << "  ";
            if (job && job->is_object()) std::cout << str(*job, "id") << "  " << format_progress_line(*job);
            else std::cout << "(job missing)";
            std::cout << "\n";
        }
    return exit_code::ok;
}

int cmd_study_wait(const GlobalOptions& g, const std::string& id, const WaitOptions& w)
{
    check_id(id, "study");
    auto client = make_client(g);
    const auto started = clock_type::now();
    std::optional<clock_type::time_point> failing_since;
    std::string last;
    const auto interval = std::chrono::duration<double>(std::max(0.05, w.interval_s));
    for (;;) {
        HttpReply reply;
        try {
            reply = client.request(Method::get, "/v1/studies/" + id);
            failing_since.reset();
        } catch (const CommandError& e) {
            if (e.code != exit_code::network) throw;  // a restarting server: retried for a minute
            if (!failing_since) failing_since = clock_type::now();
            if (clock_type::now() - *failing_since > std::chrono::seconds(60)) throw;
            std::this_thread::sleep_for(interval);
            continue;
        }
        check_reply(reply, "study " + id);
        const json::value study = parse_reply(reply, "study " + id);
        const std::string now = counts_text(study);
        if (!g.json && now != last) std::cout << "study " << id << ": " << now << std::endl;
        last = now;
        if (const auto [ended, all_ok] = study_ended(study); ended) {
            if (g.json) print_json(study);
            if (!all_ok) std::cerr << "wiredem: study " << id << " ended with jobs that did not succeed: " << now << std::endl;
            return all_ok ? exit_code::ok : exit_code::job_failed;
        }
        if (w.timeout_s && std::chrono::duration<double>(clock_type::now() - started).count() > *w.timeout_s)
            throw CommandError(exit_code::wait_timeout, "study " + id + " still has jobs to run after "
                                                            + format_duration(*w.timeout_s) + ": " + now);
        std::this_thread::sleep_for(interval);
    }
}

int cmd_study_cancel(const GlobalOptions& g, const std::string& id)
{
    check_id(id, "study");
    auto client = make_client(g);
    const auto reply = client.request(Method::del, "/v1/studies/" + id);
    check_reply(reply, "cancel study " + id);
    const json::value study = parse_reply(reply, "cancel study " + id);
    if (g.json) print_json(study);
    else std::cout << "study " << id << ": " << counts_text(study) << std::endl;
    return exit_code::ok;
}

int cmd_study_delete(const GlobalOptions& g, const std::string& id)
{
    check_id(id, "study");
    auto client = make_client(g);
    const auto reply = client.request(Method::del, "/v1/studies/" + id + "?remove=true");
    check_reply(reply, "delete study " + id);
    if (g.json) print_json(json::object{{"id", id}, {"deleted", true}});
    else std::cout << "study " << id << " deleted with its jobs and their files" << std::endl;
    return exit_code::ok;
}

int cmd_study_summary(const GlobalOptions& g, const std::string& id, bool csv)
{
    check_id(id, "study");
    auto client = make_client(g);
    const auto reply = client.request(Method::get, "/v1/studies/" + id + "/summary");
    check_reply(reply, "summary of study " + id);
    const json::value summary = parse_reply(reply, "summary of study " + id);
    if (!summary.is_object()) throw CommandError(exit_code::network, "summary of study " + id + ": not a JSON object");
    if (g.json) print_json(summary);
    else if (csv) std::cout << api::study_summary_csv(summary.as_object());
    else std::cout << format_study_summary(summary);
    return exit_code::ok;
}

int cmd_study_fetch(const GlobalOptions& g, const std::string& id, const fs::path& dir)
{
    check_id(id, "study");
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw CommandError(exit_code::local_io, "cannot create " + dir.string() + ": " + ec.message());
    auto client = make_client(g);
    const auto reply = client.request(Method::get, "/v1/studies/" + id + "/summary");
    check_reply(reply, "summary of study " + id);
    const json::value summary = parse_reply(reply, "summary of study " + id);
    if (!summary.is_object()) throw CommandError(exit_code::network, "summary of study " + id + ": not a JSON object");
    write_local_file(dir / "summary.json", reply.body); // as the server sent it
    write_local_file(dir / "summary.csv", api::study_summary_csv(summary.as_object()));
    int fetched = 0, skipped = 0;
    for (const auto& p : summary.at("points").as_array()) {
        const std::string job_id = str(p, "job_id");
        if (str(p, "state") != "succeeded" || job_id.empty()) {
            ++skipped;
            continue;
        }
        const auto index = p.at("index").to_number<std::int64_t>();
        GlobalOptions quiet = g;
        quiet.json = true; // fetch prints nothing but its JSON line then; ours follows
        std::ostringstream sink;
        auto* old = std::cout.rdbuf(sink.rdbuf());
        try {
            cmd_fetch(quiet, job_id, dir / "points" / std::to_string(index));
        } catch (...) {
            std::cout.rdbuf(old);
            throw;
        }
        std::cout.rdbuf(old);
        ++fetched;
    }
    if (!g.json)
        std::cout << "study " << id << ": summary.json, summary.csv and " << fetched << " points' results in "
                  << dir.string() << (skipped ? " (" + std::to_string(skipped) + " points not succeeded)" : "") << std::endl;
    return exit_code::ok;
}

int cmd_study_run(const fs::path& study_file, const LocalStage& s, std::size_t jobs, std::size_t max_points)
{
    const api::Study study = load_study(study_file, max_points);
    make_job_directory(s.dir);
    return study_run_main(study, s.dir, jobs, stage_options(s));
}

} // namespace wiredem::client
