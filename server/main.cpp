// wiredem-server: the HTTP front of the job queue. Wires the pieces together:
// options → data directory (locked) → job store → queue (workers) → listener
// on io_threads threads → wait for SIGINT/SIGTERM → stop accepting, stop the
// runners and requeue their jobs, let replies drain, exit 0.
#include "config.hpp"
#include "framing.hpp"
#include "job_queue.hpp"
#include "job_store.hpp"
#include "listener.hpp"
#include "router.hpp"
#include "services.hpp"

#include "api/derived.hpp"
#include "io/atomic_file.hpp"

#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/signal_set.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <future>
#include <thread>

namespace asio = boost::asio;
namespace fs = std::filesystem;
using namespace wiredem::server;

namespace {

/// Exit codes of wiredem-server.
constexpr int exit_ok = 0;
constexpr int exit_usage = 2;
constexpr int exit_setup = 3;  ///< data dir, database, runner, token or address unusable

fs::path default_runner()
{
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path("wiredem") : self.parent_path() / "wiredem";
}

/// The web page as installed beside the binary (BIN/../share/wiredem/web, the
/// build tree's layout too), or empty when it is not there.
fs::path default_web_dir()
{
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    const fs::path dir = self.parent_path().parent_path() / "share" / "wiredem" / "web";
    return fs::is_regular_file(dir / "index.html", ec) ? dir : fs::path();
}

bool parse_listen(const std::string& text, std::string& host, std::uint16_t& port)
{
    const auto colon = text.rfind(':');
    if (colon == std::string::npos) return false;
    host = text.substr(0, colon);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    const std::string p = text.substr(colon + 1);
    if (p.empty() || p.size() > 5 || p.find_first_not_of("0123456789") != std::string::npos) return false;
    const int v = std::stoi(p);
    if (v > 65535) return false;
    port = static_cast<std::uint16_t>(v);
    return !host.empty();
}

/// A data directory whose job folders outlived its database (a 0-byte or
/// missing jobs.sqlite3) would start as an empty store and forget every job
/// it holds: refuse, and say what to do.
void refuse_lost_store(const fs::path& data_dir)
{
    const fs::path db = data_dir / "jobs.sqlite3";
    std::error_code ec;
    const bool empty_db = !fs::exists(db, ec) || fs::file_size(db, ec) == 0;
    if (!empty_db) return;
    std::size_t folders = 0;
    for (const auto& entry : fs::directory_iterator(data_dir / "jobs", ec))
        if (entry.is_directory(ec)) ++folders;
    if (folders > 0)
        throw std::runtime_error(db.string() + (fs::exists(db, ec) ? " is empty" : " is missing") + " but "
                                 + (data_dir / "jobs").string() + " holds " + std::to_string(folders)
                                 + " job folder(s): the job store was lost. Restore jobs.sqlite3 from a backup, or "
                                   "move the job folders away to start an empty store");
}

/// "0640" for a st_mode.
std::string mode_text(mode_t mode)
{
    char buf[8];
    std::snprintf(buf, sizeof buf, "%04o", static_cast<unsigned>(mode & 07777));
    return buf;
}

std::string read_token(const fs::path& file)
{
    // A secret other users can read is no secret; said, not refused: a
    // container's secret is often mounted 0444 by its owner's choice.
    struct stat st{};
    if (::stat(file.c_str(), &st) == 0 && (st.st_mode & (S_IRWXG | S_IRWXO)) != 0)
        spdlog::warn("token file {} may be read by other users (mode {}): chmod 600 it", file.string(),
            mode_text(st.st_mode));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read token file " + file.string());
    std::string token((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back()))) token.pop_back();
    while (!token.empty() && std::isspace(static_cast<unsigned char>(token.front()))) token.erase(0, 1);
    if (token.empty()) throw std::runtime_error("token file " + file.string() + " is empty");
    for (char c : token)
        if (c <= 0x20 || c >= 0x7f) throw std::runtime_error("token in " + file.string() + " must be one word of visible ASCII");
    return token;
}

/// Files and folders the server creates are never readable by other users
/// (main() sets a umask of 027, 077 with a token: the token guards results
/// over HTTP, so the files must not be readable beside it); the data
/// directory's own mode covers what an earlier run left readable.
void keep_other_users_out(const fs::path& data_dir, bool with_token)
{
    const mode_t dir_mode = with_token ? 0700 : 0750;
    if (::chmod(data_dir.c_str(), dir_mode) != 0)
        throw std::runtime_error("cannot chmod " + data_dir.string() + ": " + std::strerror(errno));
}

/// Two servers on one data directory would run every job twice.
/// Locks the data directory for this process: an exclusive flock on the
/// directory itself, which (unlike a lock file, which anyone can delete from
/// under a running server, and a second server then locks a new file) exists
/// as long as the data does. Held until the process ends.
int lock_data_dir(const fs::path& dir)
{
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error("cannot open " + dir.string() + ": " + std::strerror(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        ::close(fd);
        throw std::runtime_error("another wiredem-server uses " + dir.string());
    }
    return fd;
}

/// The address to bind: a literal address as it is, a name (localhost) as the
/// resolver gives it, IPv4 first. @throws std::runtime_error when neither.
asio::ip::address listen_address(asio::io_context& ioc, const std::string& host)
{
    boost::system::error_code ec;
    const auto literal = asio::ip::make_address(host, ec);
    if (!ec) return literal;
    asio::ip::tcp::resolver resolver(ioc);
    const auto results = resolver.resolve(host, "", ec);
    if (ec || results.empty()) throw std::runtime_error("cannot resolve the --listen host '" + host + "'");
    for (const auto& r : results)
        if (r.endpoint().address().is_v4()) return r.endpoint().address();
    return results.begin()->endpoint().address();
}

void write_port_file(const fs::path& file, std::uint16_t port)
{
    wiredem::engine::io::write_text_file_atomically(file, std::to_string(port) + "\n"); // readers never see a half-written file
}

} // namespace

int main(int argc, char** argv)
{
    ServerConfig cfg;
    std::string listen = "127.0.0.1:8080";
    std::string token_file;
    std::string log_level = "info";
    std::string runner;
    std::string web_dir;
    unsigned threads_per_job = 0;
    unsigned read_timeout_s = 30;
    unsigned write_timeout_s = 60;
    unsigned retry_after_s = 30;
    std::string executor = "local";
    SlurmOptions slurm;
    std::string slurm_wiredem;
    double slurm_poll_s = std::chrono::duration<double>(slurm.poll_interval).count();

    CLI::App app{"wiredem-server: queues triaxial campaigns and serves their results over HTTP (docs/api.md)"};
    app.add_option("--listen", listen, "address:port to listen on")->capture_default_str();
    app.add_option("--allowed-host", cfg.allowed_hosts,
        "a name the Host header may give besides the listen address (and localhost on loopback); repeatable");
    app.add_option("--data-dir", cfg.data_dir, "directory for the job database and result files")->capture_default_str();
    app.add_option("--runner", runner, "executable that runs one job (default: wiredem next to this binary)");
    app.add_option("--jobs", cfg.concurrent_jobs, "jobs run at the same time")->capture_default_str()->check(CLI::Range(1u, 256u));
    app.add_option("--threads-per-job", threads_per_job, "engine threads per job (default: cores / jobs)")
        ->check(CLI::Range(1u, 1024u));
    app.add_option("--io-threads", cfg.io_threads, "threads serving HTTP")->capture_default_str()->check(CLI::Range(1u, 64u));
    app.add_option("--submit-threads", cfg.submit_threads, "threads validating submitted jobs, off the HTTP threads")
        ->capture_default_str()->check(CLI::Range(1u, 64u));
    app.add_option("--data-threads", cfg.data_threads, "threads reading result files for the data routes, off the HTTP threads")
        ->capture_default_str()->check(CLI::Range(1u, 64u));
    app.add_option("--max-pending-submits", cfg.max_pending_submits, "submits waiting for validation; more get 503")
        ->capture_default_str()->check(CLI::Range(1, 100000));
    app.add_option("--max-queued", cfg.max_queued, "queued jobs before submit answers 429")->capture_default_str()->check(CLI::Range(1, 1000000));
    app.add_option("--max-finished-jobs", cfg.max_finished_jobs,
        "ended jobs kept; past it the oldest are removed with their files (0: keep all)")
        ->capture_default_str()->check(CLI::Range(std::size_t{0}, std::size_t{100000000}));
    app.add_option("--max-study-points", cfg.max_study_points, "jobs one parameter study may create")
        ->capture_default_str()->check(CLI::Range(std::size_t{1}, std::size_t{100000}));
    app.add_option("--max-bodies-per-job", cfg.max_bodies_per_job, "estimated bodies a job may have")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--max-steps-per-job", cfg.max_steps_per_job, "estimated time steps a job may take (preparation and tests)")
        ->capture_default_str()->check(CLI::Range(1.0, wiredem::api::max_steps_of_any_job));
    std::uint64_t max_job_seconds = static_cast<std::uint64_t>(cfg.max_job_duration.count());
    app.add_option("--max-job-seconds", max_job_seconds, "wall-clock seconds one attempt of a job may run (0: no limit)")
        ->capture_default_str()->check(CLI::Range(std::uint64_t{0}, std::uint64_t{10'000'000'000}));
    app.add_option("--checkpoint-seconds", cfg.checkpoint_interval_s,
           "wall-clock seconds between a running test's checkpoints; a job interrupted by a crash, a restart or a "
           "SIGKILL continues from the last one")
        ->capture_default_str()->check(CLI::Range(0.001, 86400.0));
    app.add_option("--max-samples-per-test", cfg.max_samples_per_test, "estimated rows of a test's time series")
        ->capture_default_str()->check(CLI::Range(1.0, 1e12));
    app.add_option("--max-body-bytes", cfg.max_body_bytes, "request body limit")->capture_default_str()->check(CLI::Range(1024, 1 << 30));
    app.add_option("--max-header-bytes", cfg.max_header_bytes,
           "request header limit, and of a chunked body's trailer (up to 65535: Beast stores a field's length in 16 bits)")
        ->capture_default_str()->check(CLI::Range(std::uint32_t{1024}, max_header_bytes_limit));
    unsigned idle_timeout_s = static_cast<unsigned>(cfg.idle_timeout.count());
    app.add_option("--idle-timeout", idle_timeout_s, "seconds a connection may wait with nothing of a request sent")
        ->capture_default_str()->check(CLI::Range(1u, 3600u));
    app.add_option("--read-timeout", read_timeout_s, "seconds a request may take to arrive, from its first byte")->capture_default_str()->check(CLI::Range(1u, 3600u));
    app.add_option("--write-timeout", write_timeout_s, "seconds a client has to take each chunk of a reply")->capture_default_str()->check(CLI::Range(1u, 3600u));
    app.add_option("--max-connections", cfg.max_connections, "open connections (the longest idle is closed for a newcomer)")->capture_default_str()->check(CLI::Range(1, 100000));
    app.add_option("--retry-after", retry_after_s, "Retry-After seconds sent with 429")->capture_default_str()->check(CLI::Range(1u, 86400u));
    // Not checked by CLI11 (exit 2): an unreadable token file is a setup error (exit 3, read_token).
    app.add_option("--token-file", token_file, "file holding the bearer token every /v1 request must carry");
    app.add_option("--web-dir", web_dir,
        "folder of the web page served at / (default: share/wiredem/web beside the binary's folder; 'none': no page)");
    app.add_option("--port-file", cfg.port_file, "write the bound port here once listening (for --listen HOST:0)");
    app.add_option("--executor", executor,
           "how jobs run: local (a runner process per job on this machine) or slurm (each job as Slurm jobs: "
           "prepare, an array of tests, analyse; the data directory on a file system the nodes share; docs/studies.md)")
        ->capture_default_str()->check(CLI::IsMember({"local", "slurm"}));
    std::vector<CLI::Option*> slurm_only{
        app.add_option("--slurm-partition", slurm.partition, "Slurm partition of the jobs (default: the cluster's)"),
        app.add_option("--slurm-account", slurm.account, "Slurm account charged (default: the user's)"),
        app.add_option("--slurm-time-limit", slurm.time_limit,
            "time limit of each Slurm job, in sbatch --time's forms (default: the partition's)"),
        app.add_option("--slurm-cpus-per-task", slurm.cpus_per_task,
               "CPUs of each stage's Slurm job, its engine threads")
            ->capture_default_str()->check(CLI::Range(1u, 1024u)),
        app.add_option("--slurm-sbatch-option", slurm.sbatch_options,
            "one more sbatch option with its value, e.g. --slurm-sbatch-option=--qos=high; repeatable"),
        app.add_option("--slurm-wiredem", slurm_wiredem,
            "the wiredem binary the nodes run, the same path on each (default: the --runner)"),
        app.add_option("--slurm-poll-seconds", slurm_poll_s, "seconds between two looks at a job's Slurm jobs")
            ->capture_default_str()->check(CLI::Range(0.1, 3600.0))};
    app.add_option("--log-level", log_level, "trace, debug, info, warn, error")->capture_default_str()
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? exit_ok : exit_usage;
    }

    auto logger = spdlog::stderr_color_mt("wiredem-server");
    spdlog::set_default_logger(logger);
    spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
    spdlog::set_level(spdlog::level::from_str(log_level));

    if (!parse_listen(listen, cfg.listen_host, cfg.listen_port)) {
        spdlog::error("--listen must be HOST:PORT, got '{}'", listen);
        return exit_usage;
    }
    if (executor != "slurm")
        for (const CLI::Option* o : slurm_only)
            if (o->count() > 0) {
                spdlog::error("{} applies to --executor slurm only", o->get_name());
                return exit_usage;
            }
    cfg.max_job_duration = std::chrono::seconds(max_job_seconds);
    cfg.idle_timeout = std::chrono::seconds(idle_timeout_s);
    cfg.read_timeout = std::chrono::seconds(read_timeout_s);
    cfg.write_timeout = std::chrono::seconds(write_timeout_s);
    cfg.retry_after = std::chrono::seconds(retry_after_s);
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    cfg.threads_per_job = threads_per_job ? threads_per_job : std::max(1u, cores / cfg.concurrent_jobs);

    ::signal(SIGPIPE, SIG_IGN);
    ::umask(token_file.empty() ? 027 : 077);  // before the first file (keep_other_users_out)
    int lock_fd = -1;
    std::unique_ptr<JobStore> store;
    try {
        cfg.runner = fs::absolute(runner.empty() ? default_runner() : fs::path(runner));
        if (::access(cfg.runner.c_str(), X_OK) != 0)
            throw std::runtime_error("runner " + cfg.runner.string() + " is not an executable file (see --runner)");
        if (executor == "slurm") {
            slurm.wiredem = slurm_wiredem.empty() ? cfg.runner : fs::absolute(slurm_wiredem);
            slurm.poll_interval = std::chrono::milliseconds(static_cast<std::int64_t>(slurm_poll_s * 1000.0));
            if (const auto problem = slurm_options_problem(slurm)) throw std::runtime_error(*problem);
            cfg.slurm = slurm;
        }
        if (!token_file.empty()) cfg.token = read_token(token_file);
        if (web_dir.empty()) cfg.web_dir = default_web_dir();
        else if (web_dir != "none") {
            cfg.web_dir = fs::canonical(web_dir);
            if (!fs::is_regular_file(cfg.web_dir / "index.html"))
                throw std::runtime_error("--web-dir " + web_dir + " holds no index.html");
        }
        fs::create_directories(cfg.data_dir / "jobs");
        cfg.data_dir = fs::canonical(cfg.data_dir);
        lock_fd = lock_data_dir(cfg.data_dir);
        keep_other_users_out(cfg.data_dir, !cfg.token.empty());
        refuse_lost_store(cfg.data_dir);
        store = std::make_unique<JobStore>(cfg.data_dir / "jobs.sqlite3");
        // A job whose Slurm jobs may still run must not also run here: both
        // would write its folder.
        if (!cfg.slurm)
            if (const auto in_slurm = store->unfinished_with_slurm_ids(); !in_slurm.empty())
                throw std::runtime_error(std::to_string(in_slurm.size()) + " unfinished job(s) of this data directory ("
                                         + in_slurm.front() + (in_slurm.size() > 1 ? ", …" : "")
                                         + ") were submitted to Slurm: start the server with --executor slurm to "
                                           "follow them (or cancel them there first)");
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return exit_setup;
    }

    Metrics metrics;
    // The queue reads the store as it starts: a store error there is a setup
    // error too (exit 3 with the message), not an abort.
    std::unique_ptr<JobQueue> queue_owner;
    try {
        queue_owner = std::make_unique<JobQueue>(
            *store, [&] {
                QueueConfig q{cfg.data_dir, cfg.runner, cfg.concurrent_jobs, cfg.threads_per_job};
                q.max_job_duration = cfg.max_job_duration;
                q.checkpoint_interval_s = cfg.checkpoint_interval_s;
                q.slurm = cfg.slurm;
                return q;
            }());
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return exit_setup;
    }
    JobQueue& queue = *queue_owner;
    Services services{cfg, *store, queue, metrics};
    Router router(services);

    asio::io_context ioc(static_cast<int>(cfg.io_threads));
    std::shared_ptr<Listener> listener;
    try {
        const asio::ip::tcp::endpoint endpoint(listen_address(ioc, cfg.listen_host), cfg.listen_port);
        // Listening on a name (localhost): its address is one of the server's names too.
        if (endpoint.address().to_string() != cfg.listen_host) cfg.allowed_hosts.push_back(endpoint.address().to_string());
        listener = std::make_shared<Listener>(ioc, endpoint, router, cfg, metrics);
        queue.start();
        listener->run();
        const auto bound = listener->local_endpoint();
        cfg.listen_port = bound.port(); // the Host check compares with it; no I/O thread runs yet
        if (!cfg.port_file.empty()) write_port_file(cfg.port_file, bound.port());
        if (cfg.slurm)
            spdlog::info("listening on {}:{}; data {}; executor slurm: {} job(s) at once, wiredem {}, {} CPU(s) per "
                         "task{}{}", bound.address().to_string(), bound.port(), cfg.data_dir.string(), cfg.concurrent_jobs,
                cfg.slurm->wiredem.string(), cfg.slurm->cpus_per_task,
                cfg.slurm->partition.empty() ? "" : ", partition " + cfg.slurm->partition,
                cfg.token.empty() ? "" : "; bearer token required");
        else
            spdlog::info("listening on {}:{}; data {}; runner {}; {} job(s) x {} thread(s){}",
                bound.address().to_string(), bound.port(), cfg.data_dir.string(), cfg.runner.string(),
                cfg.concurrent_jobs, cfg.threads_per_job, cfg.token.empty() ? "" : "; bearer token required");
    } catch (const std::exception& e) {
        spdlog::error("cannot listen on {}: {}", listen, e.what());
        queue.stop();
        return exit_setup;
    }

    std::promise<int> stop_signal;
    asio::signal_set signals(ioc, SIGINT, SIGTERM);
    signals.async_wait([&](const boost::system::error_code& ec, int sig) {
        if (!ec) stop_signal.set_value(sig);
    });

    std::vector<std::thread> io_threads;
    for (unsigned i = 0; i < cfg.io_threads; ++i) io_threads.emplace_back([&ioc] { run_io_loop(ioc); });

    const int sig = stop_signal.get_future().get();
    spdlog::info("{}: stopping (running jobs go back to the queue)", sig == SIGINT ? "SIGINT" : "SIGTERM");
    // A second signal during the shutdown ends the process at once; accepted
    // jobs are safe in the store either way.
    signals.async_wait([](const boost::system::error_code& ec, int) {
        if (!ec) std::_Exit(1);
    });
    listener->stop();
    router.stop(); // its submit threads post replies to the I/O threads: stop them first
    queue.stop();
    const auto drain_until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (metrics.connections_open.load() > 0 && std::chrono::steady_clock::now() < drain_until)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ioc.stop();
    for (auto& t : io_threads) t.join();
    ::close(lock_fd);
    spdlog::info("stopped");
    return exit_ok;
}
