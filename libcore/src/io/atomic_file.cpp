#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/io/staging.hpp"

#include "ecoterra/error.hpp"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace ecoterra::io {

namespace fs = std::filesystem;

AtomicOutput::AtomicOutput(fs::path target) : m_target(std::move(target)) {
    static std::atomic<unsigned> counter{0};
    fs::path dir = m_target.parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw IoError(m_target.string() + ": the output folder " + dir.string() +
                      " does not exist");
    if (fs::is_directory(m_target, ec))
        throw IoError(m_target.string() + ": is a folder, not a file");
    std::string suffix("-"); // (appended: GCC 12 warns falsely (-Wrestrict) on "-" + string)
    suffix.append(std::to_string(counter++));
    m_temp = staging_path(dir, m_target.filename().string(), "tmp", suffix);
}

AtomicOutput::~AtomicOutput() {
    if (!m_committed) {
        std::error_code ec;
        fs::remove(m_temp, ec);
    }
}

namespace {
/// Flushes `path` (a file or a folder) to the disk; returns the errno of a failure, 0 on success.
int sync_path(const fs::path& path, int flags) {
    const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
    if (fd < 0) return errno;
    const int rc = ::fsync(fd) == 0 ? 0 : errno;
    ::close(fd);
    return rc;
}
} // namespace

void AtomicOutput::commit() {
    // The data reach the disk before the rename makes them visible, so a crash of the machine
    // leaves either the old file or the complete new one, never an empty file under the name.
    if (const int err = sync_path(m_temp, O_RDONLY))
        throw IoError(m_target.string() +
                      ": cannot flush the finished file to disk: " + std::strerror(err));
    std::error_code ec;
    fs::rename(m_temp, m_target, ec);
    if (ec)
        throw IoError(m_target.string() +
                      ": cannot move the finished file into place: " + ec.message());
    m_committed = true;
    fs::path dir = m_target.parent_path();
    if (dir.empty()) dir = ".";
    sync_path(dir, O_RDONLY | O_DIRECTORY); // the rename itself; some file systems refuse, harmless
}

void write_text_atomic(const fs::path& target, const std::string& text) {
    AtomicOutput out(target);
    {
        std::ofstream f(out.temp_path(), std::ios::binary);
        if (!f)
            throw IoError(target.string() + ": cannot open for writing: " + std::strerror(errno));
        f << text;
        f.flush();
        if (!f) throw IoError(target.string() + ": write failed (disk full?)");
    }
    out.commit();
}

void create_folder(const fs::path& dir, const std::string& what) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw IoError(dir.string() + ": cannot create " + what + ": " + ec.message());
}

std::string read_text(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path.string() + ": cannot open for reading: " + std::strerror(errno));
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

std::string host_name() {
    char b[256] = {0};
    if (::gethostname(b, sizeof b - 1) != 0 || b[0] == 0) return "unknown";
    return b;
}

bool process_alive(long pid) {
    if (pid <= 0) return false;
    if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) return false;
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string text;
    if (!std::getline(stat, text)) return true; // no /proc: trust kill()
    const auto close = text.rfind(')');
    return close == std::string::npos || close + 2 >= text.size() || text[close + 2] != 'Z';
}

std::string process_tag() {
    return host_name() + "-" + std::to_string(::getpid());
}

std::size_t sweep_dead_staging(const fs::path& dir, const std::string& head,
                               const std::string& marker) {
    const std::string host = host_name() + "-";
    std::size_t removed = 0;
    std::error_code ec;
    std::vector<fs::path> gone;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string n = e.path().filename().string();
        if (n.size() <= head.size() + 1 || n[0] != '.' || n.compare(1, head.size(), head) != 0)
            continue;
        const auto at = n.find(marker, 1 + head.size());
        if (at == std::string::npos || n.compare(at + marker.size(), host.size(), host) != 0)
            continue;
        const char* digits = n.c_str() + at + marker.size() + host.size();
        char* end = nullptr;
        const long pid = std::strtol(digits, &end, 10);
        if (end == digits || process_alive(pid)) continue;
        gone.push_back(e.path());
    }
    for (const auto& p : gone) removed += fs::remove_all(p, ec) > 0;
    return removed;
}

} // namespace ecoterra::io
