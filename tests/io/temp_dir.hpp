// Scratch files and directories for the io tests, named after the test and
// the process and removed afterwards.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

namespace wiredem::engine::io::test {

/// A path in the temporary directory unique to this test and process.
inline std::filesystem::path scratch_path(const std::string& suffix)
{
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    return std::filesystem::temp_directory_path()
         / ("wiredem_io_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + std::to_string(::getpid())
             + suffix);
}

/// A file name unique to this test and process, removed afterwards.
class TempFile {
public:
    explicit TempFile(const std::string& suffix = ".h5") : path_(scratch_path(suffix)) {}
    ~TempFile()
    {
        std::error_code ignored;
        std::filesystem::remove(path_, ignored);
    }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

/// A directory unique to this test and process, removed afterwards.
class TempDir {
public:
    TempDir() : path_(scratch_path(".d"))
    {
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir()
    {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

} // namespace wiredem::engine::io::test
