#pragma once
// An exclusive lock on an output, held while a command writes it, so that two processes never
// write the same run at once (flock on a hidden lock file beside it: ".NAME.lock"). The kernel
// drops the lock when the process ends, killed or not; the lock file is removed on release.
#include <filesystem>
#include <string>

namespace ecoterra::io {

class FileLock {
public:
    /// Takes the lock of `target` without waiting; InputError naming `target`, the other process
    /// (its pid, as written in the lock file) and the lock file if another process holds it.
    /// IoError if the lock file cannot be made.
    explicit FileLock(const std::filesystem::path& target);
    ~FileLock();
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;

    /// The lock file of `target`.
    static std::filesystem::path path_for(const std::filesystem::path& target);

private:
    std::filesystem::path m_path;
    int m_fd = -1;
};

} // namespace ecoterra::io
