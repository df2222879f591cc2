// Process, socket and file helpers of the server tests.
#include "harness.hpp"

#include <boost/json.hpp>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace wiredem::test {
namespace fs = std::filesystem;
using clock_type = std::chrono::steady_clock;

TempDir::TempDir()
{
    const char* base = std::getenv("TMPDIR");
    std::string tmpl = std::string(base && *base ? base : "/tmp") + "/wiredem-server-test-XXXXXX";
    if (!::mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
}

TempDir::~TempDir()
{
    std::error_code ec;
    fs::remove_all(path_, ec);
}

std::string read_file(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void write_file(const fs::path& p, const std::string& text)
{
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << text;
}

ServerProcess::ServerProcess(const fs::path& data_dir, std::vector<std::string> extra_args, double step_s)
{
    fs::create_directories(data_dir);
    const fs::path port_file = data_dir.parent_path() / (data_dir.filename().string() + ".port");
    fs::remove(port_file);
    log_file_ = data_dir.parent_path() / (data_dir.filename().string() + ".log");

    std::vector<std::string> args{WIREDEM_SERVER_BIN, "--listen", "127.0.0.1:0", "--port-file", port_file.string(),
        "--data-dir", data_dir.string(), "--log-level", "debug"};
    // The fake runner unless the test names another (the real one).
    if (std::find(extra_args.begin(), extra_args.end(), "--runner") == extra_args.end())
        args.insert(args.end(), {"--runner", WIREDEM_FAKE_RUNNER});
    // The fake runner does no physics, so the tests' jobs (often the default,
    // paper-literal spec: ~10⁹ steps) pass the work limit unless a test sets it.
    if (std::find(extra_args.begin(), extra_args.end(), "--max-steps-per-job") == extra_args.end())
        args.insert(args.end(), {"--max-steps-per-job", "1e15"});
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);

    std::vector<std::string> env_strings;
    for (char** e = environ; *e; ++e)
        if (std::string_view(*e).rfind("WIREDEM_FAKE_STEP_S=", 0) != 0) env_strings.emplace_back(*e);
    env_strings.push_back("WIREDEM_FAKE_STEP_S=" + std::to_string(step_s));
    std::vector<char*> envp;
    for (auto& e : env_strings) envp.push_back(e.data());
    envp.push_back(nullptr);

    // fork + exec rather than posix_spawn: the server must die with the test
    // process even when a test crashes (PR_SET_PDEATHSIG), or it would linger.
    const int log_fd = ::open(log_file_.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (log_fd < 0) throw std::runtime_error("cannot open " + log_file_.string());
    const pid_t parent = ::getpid();
    pid_ = ::fork();
    if (pid_ == 0) {
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(127);
        ::dup2(log_fd, 1);
        ::dup2(log_fd, 2);
        ::execve(argv[0], argv.data(), envp.data());
        ::_exit(127);
    }
    ::close(log_fd);
    if (pid_ < 0) throw std::runtime_error("cannot start " + args[0]);

    const auto deadline = clock_type::now() + std::chrono::seconds(20);
    while (clock_type::now() < deadline) {
        std::ifstream in(port_file);
        int port = 0;
        if (in >> port && port > 0) {
            port_ = static_cast<std::uint16_t>(port);
            return;
        }
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            throw std::runtime_error("wiredem-server exited at start:\n" + log());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    throw std::runtime_error("wiredem-server did not start listening:\n" + log());
}

ServerProcess::~ServerProcess()
{
    if (pid_ > 0) kill_hard();
}

void ServerProcess::kill_hard()
{
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
}

int ServerProcess::terminate(std::chrono::milliseconds limit)
{
    if (pid_ <= 0) return -1;
    ::kill(pid_, SIGTERM);
    const auto deadline = clock_type::now() + limit;
    int status = 0;
    while (clock_type::now() < deadline) {
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            return status;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    kill_hard();
    return -1;
}

std::string ServerProcess::log() const { return read_file(log_file_); }

boost::json::value RawReply::json() const
{
    boost::system::error_code ec;
    auto v = boost::json::parse(body, ec);
    return ec ? boost::json::value(nullptr) : v;
}

std::string RawReply::error_code() const
{
    const auto v = json();
    if (const auto* o = v.if_object())
        if (const auto* e = o->if_contains("error"); e && e->is_object())
            if (const auto* c = e->get_object().if_contains("code"); c && c->is_string()) return std::string(c->get_string());
    return {};
}

RawReply raw_exchange(std::uint16_t port, const std::string& bytes, std::chrono::milliseconds timeout, bool half_close)
{
    RawReply reply;
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return reply;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        ::close(fd);
        return reply;
    }
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) break;  // the server may answer (413) and stop reading early
        sent += static_cast<std::size_t>(n);
    }
    if (half_close) ::shutdown(fd, SHUT_WR);
    std::string in;
    const auto deadline = clock_type::now() + timeout;
    char buf[65536];
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock_type::now()).count();
        if (left <= 0) break;
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left)) <= 0) break;
        const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
        if (n <= 0) break;
        in.append(buf, static_cast<std::size_t>(n));
    }
    ::close(fd);

    const auto head_end = in.find("\r\n\r\n");
    if (in.rfind("HTTP/1.", 0) != 0 || head_end == std::string::npos) return reply;
    reply.status = std::atoi(in.c_str() + 9);
    std::istringstream head(in.substr(0, head_end));
    std::string line;
    std::getline(head, line);
    while (std::getline(head, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto colon = line.find(':');
        if (colon == std::string::npos) continue;
        std::string name = line.substr(0, colon);
        for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        std::string value = line.substr(colon + 1);
        while (!value.empty() && value.front() == ' ') value.erase(0, 1);
        reply.headers[name] = value;
    }
    reply.body = in.substr(head_end + 4);
    if (auto it = reply.headers.find("content-length"); it != reply.headers.end()) {
        const auto n = std::stoull(it->second);
        if (reply.body.size() > n) reply.body.resize(n);
    }
    return reply;
}

RawReply http(std::uint16_t port, const std::string& method, const std::string& target, const std::string& body,
    const std::vector<std::pair<std::string, std::string>>& headers)
{
    std::string req = method + " " + target + " HTTP/1.1\r\nConnection: close\r\n";
    bool has_type = false, has_host = false;
    for (const auto& [k, v] : headers) {
        req += k + ": " + v + "\r\n";
        has_type = has_type || k == "Content-Type";
        has_host = has_host || k == "Host";
    }
    if (!has_host) req += "Host: 127.0.0.1\r\n";
    if (!body.empty() && !has_type) req += "Content-Type: application/json\r\n";
    if (!body.empty() || method == "POST") req += "Content-Length: " + std::to_string(body.size()) + "\r\n";
    req += "\r\n" + body;
    return raw_exchange(port, req);
}

int server_exit_code(const fs::path& data_dir, const std::vector<std::string>& extra_args, std::string& log)
{
    const fs::path log_file = data_dir.parent_path() / "start.log";
    std::string command = std::string("/usr/bin/timeout 10 '") + WIREDEM_SERVER_BIN + "' --listen 127.0.0.1:0 --data-dir '"
                        + data_dir.string() + "' --runner /bin/true";
    for (const auto& a : extra_args) command += " '" + a + "'";
    command += " > '" + log_file.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    log = read_file(log_file);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

ClientRun run_client(const std::vector<std::string>& args)
{
    static int counter = 0;
    const fs::path dir = fs::temp_directory_path();
    const std::string stem = "wiredem-client-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    const fs::path out = dir / (stem + ".out");
    const fs::path err = dir / (stem + ".err");
    std::string cmd = std::string("'") + WIREDEM_CLIENT_BIN + "'";
    for (const auto& a : args) cmd += " '" + a + "'";
    cmd += " > '" + out.string() + "' 2> '" + err.string() + "' < /dev/null";
    const int status = std::system(cmd.c_str());
    ClientRun run;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = read_file(out);
    run.err = read_file(err);
    fs::remove(out);
    fs::remove(err);
    return run;
}

std::string state_of(const boost::json::value& job)
{
    if (const auto* o = job.if_object())
        if (const auto* s = o->if_contains("state"); s && s->is_string()) return std::string(s->get_string());
    return {};
}

boost::json::value poll_job(std::uint16_t port, const std::string& id, bool (*pred)(const boost::json::value&),
    std::chrono::milliseconds limit, const std::string& token)
{
    const auto deadline = clock_type::now() + limit;
    boost::json::value job;
    std::vector<std::pair<std::string, std::string>> headers;
    if (!token.empty()) headers.emplace_back("Authorization", "Bearer " + token);
    while (clock_type::now() < deadline) {
        const auto r = http(port, "GET", "/v1/jobs/" + id, {}, headers);
        if (r.status == 200) {
            job = r.json();
            if (pred(job)) return job;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return job;
}

} // namespace wiredem::test
