// A runner child process with its stdout and stderr on pipes (Linux).
//
// The child runs in its own process group, so signal() reaches the runner and
// anything it started; it gets SIGTERM if the server dies (PR_SET_PDEATHSIG),
// so a kill -9 of the server leaves no runner writing into a job directory.
// Every descriptor but 0, 1, 2 is closed in the child.
//
// What leaves the group (setsid, a daemon's double fork) is found by a tag in
// its environment, WIREDEM_RUNNER_TAG, which the child gets and its
// descendants inherit: once the runner has ended, every process of the
// server's children that carries the runner's tag is killed and reaped. They
// are the server's children because the server is their subreaper
// (become_subreaper: an orphan goes to the nearest subreaper, not to init).
// A descendant that clears its environment still escapes; only a cgroup
// would hold it.
//
// Thread safety: one ChildProcess belongs to one worker thread, except
// signal(), which any thread may call.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace wiredem::server {

/// One runner process and the read ends of its stdout and stderr.
class ChildProcess {
public:
    /// Starts `argv[0]` with arguments `argv` in directory `cwd`.
    /// @throws std::system_error if the pipes or fork fail. A missing or
    /// non-executable program shows as exit status 127 with a stderr line.
    ChildProcess(const std::vector<std::string>& argv, const std::filesystem::path& cwd);
    ~ChildProcess();  ///< kills (SIGKILL) and reaps a child still running
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    /// Sends `sig` to the child's process group; no effect once reaped.
    void signal(int sig) noexcept;

    /// Reads both pipes until they close, calling `on_stdout_line` for every
    /// complete stdout line (without '\n'), and `on_tick` at least every
    /// `tick` (to check for cancellation). Lines longer than max_line_bytes are
    /// cut. Keeps the last stderr bytes (see stderr_tail). Then reaps the child.
    /// @return the wait status (as from waitpid)
    int run_to_exit(const std::function<void(const std::string&)>& on_stdout_line,
        const std::function<void()>& on_tick, std::chrono::milliseconds tick);

    /// The last few KiB the child wrote to stderr.
    [[nodiscard]] const std::string& stderr_tail() const { return stderr_tail_; }

    /// The child's pid (also its process group id).
    [[nodiscard]] pid_t pid() const { return pid_; }

    /// The value of WIREDEM_RUNNER_TAG in the child's environment.
    [[nodiscard]] const std::string& tag() const { return tag_; }

    static constexpr std::size_t max_line_bytes = 64 * 1024;
    static constexpr std::size_t stderr_tail_bytes = 4096;

private:
    /// Reaps the runner (reap_with_group), then what left its group.
    bool reap(int& status, bool block);

    std::string tag_;
    std::atomic<pid_t> pid_{-1};
    int out_fd_ = -1;
    int err_fd_ = -1;
    std::string stderr_tail_;
};

/// Makes this process the subreaper of its descendants (PR_SET_CHILD_SUBREAPER):
/// a runner's orphan becomes the server's child, which ChildProcess kills
/// and reaps once that runner has ended (see the file comment). Call once,
/// before the first ChildProcess. Returns false when the kernel refuses.
bool become_subreaper();

/// "exited with status 3" / "killed by signal 9 (Killed)".
[[nodiscard]] std::string describe_wait_status(int status);

/// The last non-empty line of `text`, trimmed.
[[nodiscard]] std::string last_line(const std::string& text);

} // namespace wiredem::server
