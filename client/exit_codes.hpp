// Exit codes of the `wiredem` command (docs/client.md has the same table).
// Scripts depend on these numbers: never renumber, only add.
#pragma once

#include <stdexcept>
#include <string>

namespace wiredem::client {

namespace exit_code {
inline constexpr int ok = 0;              ///< done; for wait/submit --wait: the job succeeded
inline constexpr int job_failed = 1;      ///< the job ended failed
inline constexpr int usage = 2;           ///< bad command line or server URL
inline constexpr int invalid_job = 3;     ///< the job or study file is not valid (local check or server 400)
inline constexpr int not_found = 4;       ///< no such job (404)
inline constexpr int unauthorized = 5;    ///< token missing or wrong (401/403)
inline constexpr int server_refused = 6;  ///< other 4xx/5xx: queue full (429), not finished yet (409), server error
inline constexpr int network = 7;         ///< cannot connect, timeout, connection lost, not HTTP
inline constexpr int job_cancelled = 8;   ///< the job ended cancelled
inline constexpr int local_io = 9;        ///< a local file cannot be read or written
inline constexpr int wait_timeout = 10;   ///< wait --timeout passed before the job ended
} // namespace exit_code

/// An error that ends the command: printed as one line, then exit with `code`.
struct CommandError : std::runtime_error {
    CommandError(int exit_code, const std::string& message) : std::runtime_error(message), code(exit_code) {}
    int code;
};

} // namespace wiredem::client
