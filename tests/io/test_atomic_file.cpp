// Files replaced whole (engine/io/atomic_file): a reader finds the old file
// or the new one, never part of either, and a failed write leaves the old
// one as it was.
#include "io/atomic_file.hpp"
#include "source_tree.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

using namespace wiredem::engine::io;
using wiredem::engine::io::test::TempDir;
using wiredem::test_support::read_text;
namespace fs = std::filesystem;

namespace {

} // namespace

TEST(AtomicFile, ReplacesTheFileWholeAndLeavesNoPartialFile)
{
    const TempDir dir;
    const fs::path file = dir.path() / "summary.json";
    write_text_file_atomically(file, "old\n");
    write_text_file_atomically(file, std::string(100000, 'x'));
    EXPECT_EQ(read_text(file), std::string(100000, 'x'));
    EXPECT_FALSE(fs::exists(dir.path() / "summary.json.partial"));
}

TEST(AtomicFile, AWriteThatFailsHalfWayLeavesTheOldFileAndNoPartialFile)
{
    const TempDir dir;
    const fs::path file = dir.path() / "result.h5";
    write_text_file_atomically(file, "old\n");
    EXPECT_THROW(replace_file_atomically(file,
                     [](const fs::path& partial) {
                         std::ofstream(partial) << "half of the new";
                         throw std::runtime_error("disk full");
                     }),
        std::runtime_error);
    EXPECT_EQ(read_text(file), "old\n");
    EXPECT_FALSE(fs::exists(dir.path() / "result.h5.partial"));
}

TEST(AtomicFile, AFileThatCannotBeWrittenIsAnErrorNamingIt)
{
    const TempDir dir;
    const fs::path file = dir.path() / "no such directory" / "summary.json";
    try {
        write_text_file_atomically(file, "x");
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("summary.json"), std::string::npos) << e.what();
    }
}

// A full disk, injected: the partial file is a symbolic link to /dev/full,
// whose every write fails with ENOSPC. The error is one line naming the
// reason and the file (not its ".partial"); the old file stays, the link goes.
TEST(AtomicFile, AFullDiskIsOneLineNamingTheFile)
{
    const TempDir dir;
    const fs::path file = dir.path() / "summary.json";
    write_text_file_atomically(file, "old\n");
    fs::create_symlink("/dev/full", dir.path() / "summary.json.partial");
    try {
        write_text_file_atomically(file, std::string(100000, 'x'));
        FAIL() << "no error";
    } catch (const WriteError& e) {
        EXPECT_EQ(std::string(e.what()), "no space left on device writing " + file.string());
        EXPECT_TRUE(e.no_space());
    }
    EXPECT_EQ(read_text(file), "old\n");
    EXPECT_FALSE(fs::exists(fs::symlink_status(dir.path() / "summary.json.partial")));
}
