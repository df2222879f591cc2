// A wiredem-server without sockets for the fuzz targets: the real Router
// over a real job store (SQLite, in memory) and a queue whose workers never
// start, configured with ServerConfig's defaults. The store holds one job in
// each final state and a queued one, and the succeeded job's files exist, so
// that requests reach every handler (summaries, byte ranges of result.h5).
#pragma once

#include "fuzz_check.hpp"

#include "framing.hpp"
#include "job_queue.hpp"
#include "job_store.hpp"
#include "router.hpp"
#include "services.hpp"

#include <spdlog/spdlog.h>

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace wiredem::fuzz {

/// Ids of the jobs the fixture's store holds (also in tests/fuzz/http.dict).
inline constexpr const char* succeeded_job_id = "0123456789abcdef01234567";
inline constexpr const char* failed_job_id = "00000000000000000000000f";
inline constexpr const char* queued_job_id = "aaaaaaaaaaaaaaaaaaaaaaaa";
/// Size of the succeeded job's result.h5 [bytes].
inline constexpr std::size_t result_bytes = 1000;

class ServerFixture {
public:
    ServerFixture()
    {
        spdlog::set_level(spdlog::level::off);  // a 500 is a failed check here, not a log line
        char dir[] = "/tmp/wiredem-fuzz-XXXXXX";
        if (!::mkdtemp(dir)) std::abort();
        data_dir_ = dir;
        config_.data_dir = data_dir_;
        config_.listen_port = 8080;
        config_.runner = "/bin/false";
        // The largest header limit the server allows, so fuzz_http_request
        // reaches fields of every size the parser can be given.
        config_.max_header_bytes = server::max_header_bytes_limit;
        store_ = std::make_unique<server::JobStore>(":memory:");
        restore();
        queue_ = std::make_unique<server::JobQueue>(*store_, server::QueueConfig{data_dir_, config_.runner});
        services_ = std::make_unique<server::Services>(server::Services{config_, *store_, *queue_, metrics_});
        router_ = std::make_unique<server::Router>(*services_);
    }
    ~ServerFixture()
    {
        router_.reset();
        services_.reset();
        queue_.reset();
        store_.reset();
        std::error_code ec;
        std::filesystem::remove_all(data_dir_, ec);
    }
    ServerFixture(const ServerFixture&) = delete;
    ServerFixture& operator=(const ServerFixture&) = delete;

    /// Puts back whichever of the three jobs is gone (DELETE removes the
    /// succeeded and failed ones, and so may the retention bound), files
    /// included, so that every input meets the same store.
    void restore()
    {
        if (!store_->get(succeeded_job_id)) {
            add_job(succeeded_job_id, server::JobState::succeeded);
            const auto job_dir = data_dir_ / "jobs" / succeeded_job_id;
            std::filesystem::create_directories(job_dir);
            std::ofstream(job_dir / "summary.json") << R"({"tests":[],"engine":{"body_steps_per_second":1e6}})" << '\n';
            std::ofstream(job_dir / "result.h5") << std::string(result_bytes, 'x');
        }
        if (!store_->get(failed_job_id)) add_job(failed_job_id, server::JobState::failed);
        if (!store_->get(queued_job_id)) add_job(queued_job_id, server::JobState::queued);
    }

    [[nodiscard]] server::Router& router() { return *router_; }
    [[nodiscard]] const server::ServerConfig& config() const { return config_; }
    [[nodiscard]] server::JobStore& store() { return *store_; }

private:
    void add_job(const std::string& id, server::JobState state)
    {
        server::JobRecord job;
        job.id = id;
        job.created_ms = 1;
        job.spec_json = "{}";
        server::JobRecord stored;
        if (store_->insert(job, 1'000'000, stored) != server::InsertOutcome::created) std::abort();
        if (state == server::JobState::queued) return;
        // Claimed (older queued jobs, submitted by earlier inputs, go back
        // to the queue in their order) and finished.
        std::vector<std::string> older;
        for (auto claimed = store_->claim_next(); claimed && claimed->id != id; claimed = store_->claim_next())
            older.push_back(claimed->id);
        for (const auto& other : older) store_->requeue(other);
        if (!store_->finish(id, state, state == server::JobState::failed ? "runner exited 1" : "", std::nullopt))
            std::abort();
    }

    std::filesystem::path data_dir_;
    server::ServerConfig config_;
    server::Metrics metrics_;
    std::unique_ptr<server::JobStore> store_;
    std::unique_ptr<server::JobQueue> queue_;
    std::unique_ptr<server::Services> services_;
    std::unique_ptr<server::Router> router_;
};

} // namespace wiredem::fuzz
