// fork + exec with pipes. Between fork and exec the child calls only
// async-signal-safe functions: the parent is multi-threaded.
#include "child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <string_view>
#include <system_error>
#include <vector>

extern char** environ;

namespace wiredem::server {
namespace {

[[noreturn]] void throw_errno(const char* what)
{
    throw std::system_error(errno, std::generic_category(), what);
}

void write_all(int fd, const char* s)
{
    std::size_t n = std::strlen(s);
    while (n > 0) {
        const ssize_t w = ::write(fd, s, n);
        if (w <= 0) return;
        s += w;
        n -= static_cast<std::size_t>(w);
    }
}

/// The server's children by ChildProcess, until reaped: the sweep
/// (kill_escaped) leaves them to their own ChildProcess. Held across fork,
/// so that no sweep sees a new child before it is listed here.
std::mutex children_mutex;
std::set<pid_t> children;
std::atomic<unsigned> tag_counter{0};

constexpr std::string_view tag_variable = "WIREDEM_RUNNER_TAG=";

/// The parent pid and state of process `pid` from /proc/PID/stat.
bool read_stat(pid_t pid, pid_t& ppid, char& state)
{
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string text;
    std::getline(in, text);
    const auto paren = text.rfind(')');  // the name may hold spaces and ')'
    if (paren == std::string::npos) return false;
    std::istringstream rest(text.substr(paren + 1));
    long parent = 0;
    if (!(rest >> state >> parent)) return false;
    ppid = static_cast<pid_t>(parent);
    return true;
}

/// Whether process `pid`'s environment holds `entry` ("NAME=value").
bool environment_holds(pid_t pid, const std::string& entry)
{
    std::ifstream in("/proc/" + std::to_string(pid) + "/environ", std::ios::binary);
    for (std::string var; std::getline(in, var, '\0');)
        if (var == entry) return true;
    return false;
}

/// Kills and reaps the server's children that carry `tag` (a runner's
/// escaped descendants, reparented to the server, its subreaper), until none
/// is left (one killed may leave children of its own, reparented in turn);
/// reaps the other children that are not ChildProcesses' and have ended
/// (zombies of strays). A few passes at most.
void kill_escaped(const std::string& tag)
{
    const std::string entry = std::string(tag_variable) + tag;
    const pid_t self = ::getpid();
    for (int pass = 0; pass < 8; ++pass) {
        std::vector<pid_t> tagged;
        {
            std::lock_guard lock(children_mutex);
            std::error_code ec;
            for (std::filesystem::directory_iterator it("/proc", ec), end; !ec && it != end; it.increment(ec)) {
                const std::string name = it->path().filename().string();
                if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
                const pid_t pid = static_cast<pid_t>(std::stol(name));
                pid_t ppid = 0;
                char state = '?';
                if (!read_stat(pid, ppid, state) || ppid != self || children.count(pid)) continue;
                if (state == 'Z') {
                    int status = 0;
                    ::waitpid(pid, &status, WNOHANG);
                } else if (environment_holds(pid, entry)) {
                    tagged.push_back(pid);
                }
            }
        }
        if (tagged.empty()) return;
        for (const pid_t pid : tagged) {
            ::kill(pid, SIGKILL);
            int status = 0;
            while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
            }
        }
    }
}

/// Child side of fork(); never returns.
[[noreturn]] void exec_child(char* const* argv, char* const* envp, const char* cwd, int out_w, int err_w, pid_t parent)
{
    // Signals are blocked (see spawn): drop the server's handlers before they
    // can run here. Asio's handler writes to a pipe this process inherited, so
    // a SIGTERM for the new runner, delivered before exec, reached the server
    // as a second SIGTERM (it then exits 1 at once).
    for (int sig = 1; sig < NSIG; ++sig)
        if (sig != SIGKILL && sig != SIGSTOP) ::signal(sig, SIG_DFL);
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(143);  // the server died before prctl took effect
    const int null_fd = ::open("/dev/null", O_RDONLY);
    if (null_fd >= 0) ::dup2(null_fd, 0);
    ::dup2(out_w, 1);
    ::dup2(err_w, 2);
    // The server's listening socket and database must not leak into the runner
    // (Asio does not open sockets with O_CLOEXEC).
    if (::syscall(SYS_close_range, 3u, ~0u, 0u) != 0)
        for (int fd = 3; fd < 4096; ++fd) ::close(fd);
    sigset_t none;
    ::sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::signal(SIGPIPE, SIG_DFL);  // ignored in the server; ignored dispositions survive exec
    if (::chdir(cwd) != 0) {
        write_all(2, "cannot enter the job directory\n");
        ::_exit(127);
    }
    ::execve(argv[0], argv, envp);
    write_all(2, "cannot execute the runner ");
    write_all(2, argv[0]);
    write_all(2, ": ");
    write_all(2, ::strerror(errno));  // not strictly async-signal-safe, harmless right before _exit
    write_all(2, "\n");
    ::_exit(127);
}

} // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::filesystem::path& cwd)
{
    std::vector<std::string> args = argv;
    std::vector<char*> cargv;
    for (auto& a : args) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    const std::string cwd_str = cwd.string();
    // The environment, with this child's tag (built before fork: the child
    // may only make async-signal-safe calls).
    tag_ = std::to_string(::getpid()) + "-" + std::to_string(tag_counter.fetch_add(1));
    std::vector<std::string> env;
    for (char** e = environ; e && *e; ++e)
        if (std::string_view(*e).substr(0, tag_variable.size()) != tag_variable) env.emplace_back(*e);
    env.push_back(std::string(tag_variable) + tag_);
    std::vector<char*> cenv;
    for (auto& e : env) cenv.push_back(e.data());
    cenv.push_back(nullptr);

    int out[2];
    int err[2];
    if (::pipe2(out, O_CLOEXEC) != 0) throw_errno("pipe");
    if (::pipe2(err, O_CLOEXEC) != 0) {
        ::close(out[0]);
        ::close(out[1]);
        throw_errno("pipe");
    }
    const pid_t parent = ::getpid();
    // Every signal blocked across fork: the child resets the server's handlers
    // before it takes any (exec_child unblocks them).
    sigset_t all, previous;
    ::sigfillset(&all);
    ::pthread_sigmask(SIG_BLOCK, &all, &previous);
    std::unique_lock listed(children_mutex);
    const pid_t pid = ::fork();
    if (pid == 0) exec_child(cargv.data(), cenv.data(), cwd_str.c_str(), out[1], err[1], parent);
    if (pid > 0) children.insert(pid);
    listed.unlock();
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    if (pid < 0) {
        const int e = errno;
        for (int fd : {out[0], out[1], err[0], err[1]}) ::close(fd);
        errno = e;
        throw_errno("fork");
    }
    ::setpgid(pid, pid);  // also in the parent: no window in which signal() misses the group
    ::close(out[1]);
    ::close(err[1]);
    out_fd_ = out[0];
    err_fd_ = err[0];
    pid_ = pid;
}

ChildProcess::~ChildProcess()
{
    if (const pid_t pid = pid_.load(); pid > 0) {
        ::kill(-pid, SIGKILL);
        int status = 0;
        reap(status, true);
    }
    if (out_fd_ >= 0) ::close(out_fd_);
    if (err_fd_ >= 0) ::close(err_fd_);
}

void ChildProcess::signal(int sig) noexcept
{
    if (const pid_t pid = pid_.load(); pid > 0) ::kill(-pid, sig);
}

namespace {

/// Once the runner has ended: kills what is left of its process group (a
/// child it left running would otherwise outlive the job and hold the pipes),
/// then reaps it. Until it is reaped the runner's pid, which names the group,
/// cannot be taken by another process, so the kill reaches no stranger.
/// Returns false when `block` is false and the runner is still running.
bool reap_with_group(pid_t pid, int& status, bool block)
{
    siginfo_t info{};
    const int options = WEXITED | WNOWAIT | (block ? 0 : WNOHANG);
    while (::waitid(P_PID, static_cast<id_t>(pid), &info, options) != 0)
        if (errno != EINTR) return false;
    if (info.si_pid != pid) return false; // WNOHANG: still running
    ::kill(-pid, SIGKILL);
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return true;
}

} // namespace

bool ChildProcess::reap(int& status, bool block)
{
    const pid_t pid = pid_.load();
    if (!reap_with_group(pid, status, block)) return false;
    pid_ = -1;
    {
        std::lock_guard lock(children_mutex);
        children.erase(pid);
    }
    kill_escaped(tag_);
    return true;
}

bool become_subreaper() { return ::prctl(PR_SET_CHILD_SUBREAPER, 1) == 0; }

int ChildProcess::run_to_exit(const std::function<void(const std::string&)>& on_stdout_line,
    const std::function<void()>& on_tick, std::chrono::milliseconds tick)
{
    using clock = std::chrono::steady_clock;
    std::string line;
    char buf[8192];
    int status = 0;
    bool reaped = false;
    clock::time_point reaped_at{};
    auto next_tick = clock::now() + tick;

    while (out_fd_ >= 0 || err_fd_ >= 0) {
        pollfd fds[2];
        nfds_t n = 0;
        if (out_fd_ >= 0) fds[n++] = {out_fd_, POLLIN, 0};
        if (err_fd_ >= 0) fds[n++] = {err_fd_, POLLIN, 0};
        const auto wait_ms = std::chrono::duration_cast<std::chrono::milliseconds>(next_tick - clock::now());
        const int rc = ::poll(fds, n, static_cast<int>(std::max<std::int64_t>(0, wait_ms.count())));
        if (rc < 0 && errno != EINTR) throw_errno("poll");
        for (nfds_t k = 0; rc > 0 && k < n; ++k) {
            if (!(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            const ssize_t got = ::read(fds[k].fd, buf, sizeof buf);
            if (got <= 0) {
                if (got < 0 && errno == EINTR) continue;
                int& fd = fds[k].fd == out_fd_ ? out_fd_ : err_fd_;
                ::close(fd);
                fd = -1;
                continue;
            }
            if (fds[k].fd == out_fd_) {
                for (ssize_t i = 0; i < got; ++i) {
                    if (buf[i] == '\n') {
                        on_stdout_line(line);
                        line.clear();
                    } else if (line.size() < max_line_bytes) {
                        line.push_back(buf[i]);
                    }  // the rest of an over-long line is dropped
                }
            } else {
                stderr_tail_.append(buf, static_cast<std::size_t>(got));
                if (stderr_tail_.size() > 2 * stderr_tail_bytes)
                    stderr_tail_.erase(0, stderr_tail_.size() - stderr_tail_bytes);
            }
        }
        if (clock::now() >= next_tick) {
            on_tick();
            next_tick = clock::now() + tick;
            if (!reaped) {
                if (reap(status, false)) {
                    reaped = true;
                    reaped_at = clock::now();
                }
            } else if (clock::now() - reaped_at > std::chrono::seconds(2)) {
                break;  // the runner is gone but something it started still holds the pipes
            }
        }
    }
    if (!line.empty()) on_stdout_line(line);
    if (!reaped) reap(status, true);
    if (stderr_tail_.size() > stderr_tail_bytes) stderr_tail_.erase(0, stderr_tail_.size() - stderr_tail_bytes);
    return status;
}

std::string describe_wait_status(int status)
{
    if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        const char* name = ::strsignal(sig);
        return "killed by signal " + std::to_string(sig) + (name ? std::string(" (") + name + ")" : "");
    }
    return "ended with wait status " + std::to_string(status);
}

std::string last_line(const std::string& text)
{
    std::size_t end = text.size();
    while (end > 0) {
        while (end > 0 && (text[end - 1] == '\n' || text[end - 1] == '\r' || text[end - 1] == ' ')) --end;
        std::size_t begin = text.rfind('\n', end == 0 ? 0 : end - 1);
        begin = begin == std::string::npos ? 0 : begin + 1;
        std::string l = text.substr(begin, end - begin);
        while (!l.empty() && (l.front() == ' ' || l.front() == '\t')) l.erase(0, 1);
        if (!l.empty()) return l;
        end = begin;
    }
    return {};
}

} // namespace wiredem::server
