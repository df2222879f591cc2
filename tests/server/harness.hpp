// Test harness for the server suites: a real wiredem-server process on a
// random loopback port with its own data directory, raw HTTP over POSIX
// sockets (so hostile requests can be sent byte for byte), and runs of the
// real `wiredem` client binary. Nothing here links the server.
#pragma once

#include <boost/json/value.hpp>

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace wiredem::test {

/// A fresh directory under $TMPDIR (or /tmp), removed with everything in it.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

/// A wiredem-server child process listening on 127.0.0.1:<random port>,
/// running jobs with tests/server/fake_runner.sh.
class ServerProcess {
public:
    /// Starts the server on `data_dir` with `extra_args`; waits until it listens.
    /// @param step_s  pause between the fake runner's progress lines [s]
    ServerProcess(const std::filesystem::path& data_dir, std::vector<std::string> extra_args = {},
        double step_s = 0.05);
    ~ServerProcess();  ///< SIGKILL if still running
    ServerProcess(const ServerProcess&) = delete;
    ServerProcess& operator=(const ServerProcess&) = delete;

    [[nodiscard]] std::uint16_t port() const { return port_; }
    [[nodiscard]] std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
    [[nodiscard]] pid_t pid() const { return pid_; }

    /// kill -9, then reap.
    void kill_hard();
    /// SIGTERM, then wait up to `limit`; returns the exit status (or -1 on timeout, after SIGKILL).
    int terminate(std::chrono::milliseconds limit = std::chrono::milliseconds(10000));
    /// The server's log so far.
    [[nodiscard]] std::string log() const;

private:
    pid_t pid_ = -1;
    std::uint16_t port_ = 0;
    std::filesystem::path log_file_;
};

/// Starts the server on `data_dir` with `extra_args` (and --runner
/// /bin/true) and waits for it to exit (at most 10 s: one that is still
/// serving by then is stopped, exit code 124); returns the exit code, and
/// its log in `log`.
int server_exit_code(const std::filesystem::path& data_dir, const std::vector<std::string>& extra_args, std::string& log);

/// One HTTP reply read off a socket.
struct RawReply {
    int status = 0;                              ///< 0: no reply at all
    std::map<std::string, std::string> headers;  ///< lower-case names
    std::string body;
    [[nodiscard]] boost::json::value json() const;  ///< body parsed; null if not JSON
    [[nodiscard]] std::string error_code() const;   ///< error.code of an error body, else ""
};

/// Sends `bytes` to 127.0.0.1:port, half-closes (unless `half_close` is
/// false: then the connection stays open like a stalled client), reads until
/// the server closes or `timeout` passes, and parses the (first) reply.
RawReply raw_exchange(std::uint16_t port, const std::string& bytes,
    std::chrono::milliseconds timeout = std::chrono::milliseconds(10000), bool half_close = true);

/// A well-formed request (Connection: close) through raw_exchange.
RawReply http(std::uint16_t port, const std::string& method, const std::string& target, const std::string& body = {},
    const std::vector<std::pair<std::string, std::string>>& headers = {});

/// The result of running the client binary.
struct ClientRun {
    int exit_code = -1;
    std::string out;
    std::string err;
};

/// Runs `wiredem <args…>` (arguments are single-quoted for the shell).
ClientRun run_client(const std::vector<std::string>& args);

/// Polls GET /v1/jobs/{id} until `pred(job)` holds or `limit` passes; returns the last job.
boost::json::value poll_job(std::uint16_t port, const std::string& id, bool (*pred)(const boost::json::value&),
    std::chrono::milliseconds limit = std::chrono::milliseconds(20000), const std::string& token = {});

/// job["state"] as a string ("" if missing).
std::string state_of(const boost::json::value& job);

/// A file's bytes.
std::string read_file(const std::filesystem::path& p);

/// Writes `text` to `p`.
void write_file(const std::filesystem::path& p, const std::string& text);

} // namespace wiredem::test
