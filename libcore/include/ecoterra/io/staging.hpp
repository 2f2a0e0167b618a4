#pragma once
// Staging: every output of ecoterra is written under a hidden name beside its target and moved
// into place only when complete, so that a killed or failed writer never leaves a half-written
// output where a finished one was. The names are ".NAME.MARKER-HOST-PID[...]" (staging_path), so
// that sweep_dead_staging (atomic_file.hpp) removes what a dead process of this host left, and
// nothing of a live one or of another host. Files: AtomicOutput (atomic_file.hpp). Folders:
// OutputFolder, and replace_folder for a folder written whole.
//
// OutputFolder: an output folder that appears whole or not at all. Files are written into a hidden
// sibling staging folder; commit() renames it into place (a new folder), or, with --force into an
// existing folder, moves each file over its namesake (other files of the user are never touched
// or deleted). Without commit() (an error on the way) the staging folder is removed; a killed
// process's staging folder (".NAME.partial-HOST-PID") is removed by the next export to NAME.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ecoterra::io {

/// The staging name of `name` in `dir` for this process: dir / ".NAME.MARKER-HOST-PID" + suffix.
std::filesystem::path staging_path(const std::filesystem::path& dir, const std::string& name,
                                   const std::string& marker, const std::string& suffix = "");

/// Puts the complete folder `stage` in the place of `target`: an existing target is renamed
/// aside (".NAME.old-HOST-PID"), the stage renamed in and the old one removed; IoError naming the
/// folder when a rename fails (the earlier target is then put back).
void replace_folder(const std::filesystem::path& stage, const std::filesystem::path& target);

class OutputFolder {
public:
    /// InputError if `dir` exists with files in it and `force` is false, or exists as a file.
    OutputFolder(std::filesystem::path dir, bool force);
    ~OutputFolder();
    OutputFolder(const OutputFolder&) = delete;
    OutputFolder& operator=(const OutputFolder&) = delete;

    /// Writes `bytes` to `relative` (sub-folders created); relative paths only.
    void write(const std::string& relative, const std::string& bytes);
    /// The staging path of `relative`, for writers that need a file name (GDAL, libpng); the
    /// caller writes it and it is listed like any other.
    std::filesystem::path staged_path(const std::string& relative);
    /// A note for the README (resampling, warnings); also returned by notes().
    void note(const std::string& text) { m_notes.push_back(text); }

    void commit();

    const std::filesystem::path& dir() const { return m_dir; }
    const std::vector<std::string>& files() const { return m_files; }
    const std::vector<std::string>& notes() const { return m_notes; }
    /// Total bytes of the files written so far.
    std::uint64_t bytes() const;

private:
    std::filesystem::path m_dir, m_stage;
    std::vector<std::string> m_files, m_notes;
    bool m_committed = false;
};

} // namespace ecoterra::io
