#pragma once
// An output folder that appears whole or not at all. Files are written into a hidden sibling
// staging folder; commit() renames it into place (a new folder), or, with --force into an
// existing folder, moves each file over its namesake (other files of the user are never touched
// or deleted). Without commit() (an error on the way) the staging folder is removed; a killed
// process's staging folder (".NAME.partial-HOST-PID") is removed by the next export to NAME.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ecoterra::exporter {

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

} // namespace ecoterra::exporter
