#include "ecoterra/io/file_lock.hpp"

#include "ecoterra/error.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace ecoterra::io {

namespace fs = std::filesystem;

fs::path FileLock::path_for(const fs::path& target) {
    const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
    // (Built by append: GCC 12 warns falsely (-Wrestrict) on "." + std::string.)
    std::string name(".");
    name.append(target.filename().string()).append(".lock");
    return parent / name;
}

FileLock::FileLock(const fs::path& target) : m_path(path_for(target)) {
    // The lock file may be removed by its holder between our open and our flock: then the lock
    // we got is on a file nobody else will open, so check that the name still leads to it.
    for (int attempt = 0; attempt < 100; ++attempt) {
        const int fd = ::open(m_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0)
            throw IoError(m_path.string() + ": cannot create the lock file of " + target.string() +
                          " (" + std::strerror(errno) + ")");
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            const int err = errno;
            char pid[32] = {};
            const ssize_t n = ::pread(fd, pid, sizeof pid - 1, 0);
            ::close(fd);
            if (err == EWOULDBLOCK) {
                std::string who = n > 0 ? std::string(pid, static_cast<std::size_t>(n)) : "";
                while (!who.empty() && (who.back() == '\n' || who.back() == ' ')) who.pop_back();
                throw InputError(target.string() + ": another ecoterra process" +
                                 (who.empty() ? std::string() : " (pid " + who + ")") +
                                 " is writing it now (lock " + m_path.string() +
                                 "); wait for it to finish, or write elsewhere");
            }
            throw IoError(m_path.string() + ": cannot lock (" + std::strerror(err) + ")");
        }
        struct stat held {
        }, named{};
        if (::fstat(fd, &held) == 0 && ::stat(m_path.c_str(), &named) == 0 &&
            held.st_ino == named.st_ino && held.st_dev == named.st_dev) {
            m_fd = fd;
            const std::string me = std::to_string(::getpid()) + "\n";
            if (::ftruncate(fd, 0) == 0) {
                [[maybe_unused]] const ssize_t w = ::pwrite(fd, me.data(), me.size(), 0);
            }
            return;
        }
        ::close(fd); // removed or replaced under us: try again
    }
    throw IoError(m_path.string() + ": cannot take the lock (it keeps being replaced)");
}

FileLock::~FileLock() {
    if (m_fd < 0) return;
    // Remove the name while holding the lock, so that a waiter that opened the old file sees
    // (fstat against stat) that it no longer leads there and opens a new one.
    ::unlink(m_path.c_str());
    ::close(m_fd);
}

} // namespace ecoterra::io
