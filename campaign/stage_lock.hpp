// One process per stage of a job directory at a time.
//
// The stages write their files by writing beside the name and renaming, and
// continue from checkpoints, so a stage killed at any point leaves nothing
// half written. Two processes running the *same* stage of one directory at
// once (a user starting `wiredem run DIR` twice, a cluster job submitted
// twice, the server and the command line on one folder) would both write its
// checkpoints and its result. Each stage therefore holds an exclusive lock
// on its own lock file while it runs: DIR/specimen.lock (prepare),
// DIR/tests/test_K.lock (test K), DIR/analyse.lock (analyse). Different
// tests of one directory still run at once, in one process or in many (the
// cluster's fan-out, docs/studies.md).
//
// The lock is flock(2) on the file: the kernel drops it when the holder
// exits, however it ends (SIGKILL included), so a killed stage never leaves a
// stale lock, and the lock files themselves stay (empty but for the
// holder's pid and host, for the message). A stage that finds its lock held
// waits a while for it (StageControl::lock_wait_s, default 30 s) before it
// gives up: a runner stopped with SIGTERM (the server's death sends it one)
// saves a checkpoint on its way out, and the runner started in its place
// must not fail, and lose the job, for arriving a second early. On a file system without locks
// (flock fails with ENOLCK, ENOSYS or EOPNOTSUPP) the stage runs unlocked:
// the guard is lost, not the run.
#pragma once

#include "core/result.hpp"

#include <atomic>
#include <filesystem>
#include <string>

namespace wiredem::campaign {

class StageLock {
public:
    /// Takes the lock on `file` (created if missing), waiting up to
    /// `wait_s` seconds for another holder to let it go (0: not at all), or
    /// until `cancel` is set. The error names `what` (e.g. "test 2/4 at
    /// sigma3 = 40000 Pa"), the file and, when it can be read, the holder's
    /// pid and host.
    [[nodiscard]] static engine::Result<StageLock, std::string> acquire(const std::filesystem::path& file,
        const std::string& what, double wait_s, const std::atomic<bool>* cancel = nullptr);

    StageLock(StageLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
    StageLock& operator=(StageLock&& other) noexcept;
    StageLock(const StageLock&) = delete;
    StageLock& operator=(const StageLock&) = delete;
    ~StageLock();

    /// Whether a lock is held (false on a file system without locks).
    [[nodiscard]] bool held() const { return fd_ >= 0; }

private:
    explicit StageLock(int fd) : fd_(fd) {}
    int fd_ = -1;
};

} // namespace wiredem::campaign
