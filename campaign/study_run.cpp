#include "study_run.hpp"

#include "api/json_text.hpp"
#include "io/atomic_file.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <iterator>
#include <mutex>
#include <thread>

namespace wiredem::campaign {

namespace json = boost::json;

std::filesystem::path point_dir(const std::filesystem::path& study_dir, std::size_t k)
{
    return study_dir / "points" / std::to_string(k);
}

namespace {

std::optional<json::value> read_summary(const std::filesystem::path& file)
{
    std::ifstream in(file, std::ios::binary);
    if (!in) return std::nullopt;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Correctly rounded (Boost.JSON's parser may miss the last bit).
    auto v = api::parse_json_text(text);
    if (!v) return std::nullopt;
    return std::move(v).value();
}

} // namespace

std::vector<api::PointOutcome> run_study(const api::Study& study, const std::filesystem::path& dir, std::size_t at_once,
    const StageControl& control, const StudyEvent& event)
{
    const std::size_t n = study.points.size();
    std::vector<api::PointOutcome> outcomes(n);
    std::mutex mutex; // events and outcomes, from the workers
    const auto tell = [&](std::size_t k, const std::string& what, const std::string& detail) {
        if (event) event(k, what, detail);
    };
    const unsigned threads = control.threads ? control.threads : std::max(1u, std::thread::hardware_concurrency());
    at_once = std::clamp<std::size_t>(at_once, 1, std::max<std::size_t>(1, n));
    std::atomic<std::size_t> next{0};
    const auto worker = [&](unsigned worker_threads) {
        for (std::size_t k = next.fetch_add(1); k < n; k = next.fetch_add(1)) {
            if (control.cancel && control.cancel->load()) return;
            const JobDir job_dir{point_dir(dir, k)};
            api::PointOutcome o;
            // A point done already counts only if it is this point's job (a
            // changed study document must not reuse another job's results).
            const auto held = read_job(job_dir);
            const bool same_job = held.ok() && held.value() == study.points[k].spec;
            if (auto done = same_job ? read_summary(job_dir.summary()) : std::nullopt) {
                o.state = "succeeded";
                o.summary = std::move(done);
                std::lock_guard lock(mutex);
                tell(k, "done already", "");
                outcomes[k] = std::move(o);
                continue;
            }
            {
                std::lock_guard lock(mutex);
                tell(k, "started", std::to_string(worker_threads) + " threads");
            }
            StageControl c = control;
            c.threads = worker_threads;
            c.progress = nullptr; // the display follows points, not steps
            std::error_code ec;
            std::filesystem::create_directories(job_dir.root, ec);
            StageError e = ec ? StageError("cannot create " + job_dir.root.string() + ": " + ec.message())
                              : run(study.points[k].spec, job_dir, c);
            if (!e) {
                o.summary = read_summary(job_dir.summary());
                if (!o.summary) e = job_dir.summary().string() + " is missing or not JSON";
            }
            o.state = e ? (control.cancel && control.cancel->load() ? "cancelled" : "failed") : "succeeded";
            if (e) o.error = *e;
            std::lock_guard lock(mutex);
            tell(k, o.state, o.error);
            outcomes[k] = std::move(o);
        }
    };
    std::vector<std::thread> workers;
    for (std::size_t t = 1; t < at_once; ++t)
        workers.emplace_back(worker, std::max(1u, static_cast<unsigned>(threads / at_once + (t < threads % at_once ? 1 : 0))));
    worker(std::max(1u, static_cast<unsigned>(threads / at_once + (threads % at_once > 0 ? 1 : 0))));
    for (auto& t : workers) t.join();
    for (auto& o : outcomes)
        if (o.state.empty()) o.state = "cancelled"; // never started

    const json::object summary = api::study_summary(study, outcomes);
    engine::io::write_text_file_atomically(dir / "summary.json", api::json_document_text(summary) + "\n");
    engine::io::write_text_file_atomically(dir / "summary.csv", api::study_summary_csv(summary));
    return outcomes;
}

} // namespace wiredem::campaign
