// What the fuzz targets share: a property check that stops the run with the
// offending input's description (libFuzzer then saves the input as
// crash-<sha1>), the seed documents (examples/*.json), and CPU time.
#pragma once

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace wiredem::fuzz {

[[noreturn]] inline void property_violated(const char* expr, const char* file, int line, const std::string& detail)
{
    std::fprintf(stderr, "\n%s:%d: property violated: %s\n%s\n", file, line, expr, detail.c_str());
    std::abort();
}

/// Aborts (a libFuzzer crash) with `detail` when `cond` is false.
#define FUZZ_CHECK(cond, detail)                                                              \
    do {                                                                                      \
        if (!(cond)) ::wiredem::fuzz::property_violated(#cond, __FILE__, __LINE__, (detail)); \
    } while (0)

/// A file's bytes ("" when it cannot be read).
inline std::string read_file(const std::filesystem::path& p)
{
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// The text of every examples/*.json, in name order: valid jobs to start from.
inline std::vector<std::string> example_documents()
{
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(WIREDEM_SOURCE_DIR) / "examples"))
        if (e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    std::vector<std::string> docs;
    for (const auto& f : files) docs.push_back(read_file(f));
    if (docs.empty()) {
        std::fprintf(stderr, "no examples/*.json under %s\n", WIREDEM_SOURCE_DIR);
        std::abort();
    }
    return docs;
}

/// CPU time of the calling thread [s]: unlike wall-clock time, it does not
/// grow when other processes load the machine.
inline double thread_cpu_seconds()
{
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

} // namespace wiredem::fuzz
