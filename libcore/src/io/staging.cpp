#include "ecoterra/io/staging.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"

#include <fstream>
#include <system_error>
#include <unistd.h>

namespace ecoterra::io {

namespace fs = std::filesystem;

fs::path staging_path(const fs::path& dir, const std::string& name, const std::string& marker,
                      const std::string& suffix) {
    // (Built by append: GCC 12 warns falsely (-Wrestrict) on "." + std::string.)
    std::string n(".");
    n.append(name).append(".").append(marker).append("-").append(process_tag()).append(suffix);
    return dir / n;
}

void replace_folder(const fs::path& stage, const fs::path& target) {
    std::error_code ec;
    if (!fs::exists(target, ec)) {
        fs::rename(stage, target, ec);
        if (ec) throw IoError(target.string() + ": cannot move into place (" + ec.message() + ")");
        return;
    }
    const fs::path old = staging_path(target.parent_path(), target.filename().string(), "old");
    fs::remove_all(old, ec);
    fs::rename(target, old, ec);
    if (ec) throw IoError(target.string() + ": cannot move aside (" + ec.message() + ")");
    fs::rename(stage, target, ec);
    if (ec) {
        std::error_code back;
        fs::rename(old, target, back);
        throw IoError(target.string() + ": cannot move into place (" + ec.message() + ")");
    }
    fs::remove_all(old, ec);
}

OutputFolder::OutputFolder(fs::path dir, bool force) : m_dir(std::move(dir)) {
    if (m_dir.empty()) throw InputError("-o: give an output folder");
    std::error_code ec;
    if (fs::exists(m_dir, ec)) {
        if (!fs::is_directory(m_dir, ec))
            throw InputError("-o " + m_dir.string() + ": exists and is not a folder");
        if (!fs::is_empty(m_dir, ec) && !force)
            throw InputError("-o " + m_dir.string() +
                             ": the folder exists with files in it; give --force to write into "
                             "it (files of the same name are replaced, no other file is touched)");
    }
    const fs::path abs = fs::absolute(m_dir).lexically_normal();
    const fs::path parent =
        abs.has_filename() ? abs.parent_path() : abs.parent_path().parent_path();
    fs::create_directories(parent, ec);
    const std::string name =
        (abs.has_filename() ? abs.filename() : abs.parent_path().filename()).string();
    // Staging folders of exports into the same place whose processes were killed: removed.
    sweep_dead_staging(parent, name, ".partial-");
    m_stage = staging_path(parent, name, "partial");
    fs::remove_all(m_stage, ec);
    if (!fs::create_directories(m_stage, ec))
        throw IoError(m_stage.string() + ": cannot create the staging folder (" + ec.message() +
                      ")");
}

OutputFolder::~OutputFolder() {
    if (!m_committed) {
        std::error_code ec;
        fs::remove_all(m_stage, ec);
    }
}

fs::path OutputFolder::staged_path(const std::string& relative) {
    const fs::path rel(relative);
    if (rel.is_absolute() || rel.empty() || *rel.begin() == "..")
        throw Error("output folder: '" + relative + "' is not a relative path inside it");
    const fs::path p = m_stage / rel;
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    if (ec) throw IoError(p.parent_path().string() + ": cannot create (" + ec.message() + ")");
    m_files.push_back(relative);
    return p;
}

void OutputFolder::write(const std::string& relative, const std::string& bytes) {
    const fs::path p = staged_path(relative);
    std::ofstream out(p, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw IoError(p.string() + ": write failed");
}

std::uint64_t OutputFolder::bytes() const {
    std::uint64_t n = 0;
    std::error_code ec;
    for (const auto& f : m_files) {
        const auto s = fs::file_size((m_committed ? m_dir : m_stage) / f, ec);
        if (!ec) n += s;
    }
    return n;
}

void OutputFolder::commit() {
    std::error_code ec;
    if (!fs::exists(m_dir, ec)) {
        fs::rename(m_stage, m_dir, ec);
        if (ec)
            throw IoError(m_dir.string() + ": cannot move the export into place (" + ec.message() +
                          ")");
    } else {
        for (const auto& f : m_files) {
            const fs::path to = m_dir / f;
            fs::create_directories(to.parent_path(), ec);
            fs::rename(m_stage / f, to, ec);
            if (ec) throw IoError(to.string() + ": cannot replace (" + ec.message() + ")");
        }
        fs::remove_all(m_stage, ec);
    }
    m_committed = true;
}

} // namespace ecoterra::io
