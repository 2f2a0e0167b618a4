#include "ecoterra/terrain/io/atomic_file.hpp"

#include "ecoterra/error.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace ecoterra::terrain::io {

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
    std::string name = m_target.filename().string();
    name.insert(0, 1, '.');
    name.append(".tmp-").append(std::to_string(::getpid())).append("-");
    name.append(std::to_string(counter++));
    m_temp = dir / name;
}

AtomicOutput::~AtomicOutput() {
    if (!m_committed) {
        std::error_code ec;
        fs::remove(m_temp, ec);
    }
}

void AtomicOutput::commit() {
    std::error_code ec;
    fs::rename(m_temp, m_target, ec);
    if (ec)
        throw IoError(m_target.string() +
                      ": cannot move the finished file into place: " + ec.message());
    m_committed = true;
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

std::string read_text(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw IoError(path.string() + ": cannot open for reading: " + std::strerror(errno));
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

} // namespace ecoterra::terrain::io
