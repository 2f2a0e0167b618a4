#pragma once
// Atomic replacement of output files: data goes to a temporary name in the same folder and is
// renamed over the target only when complete, so an existing file is never left half-written.
#include <filesystem>
#include <string>
#include <vector>

namespace ecoterra::io {

class AtomicOutput {
public:
    /// Prepares to replace `target`; throws IoError if its folder does not exist.
    explicit AtomicOutput(std::filesystem::path target);
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;
    /// Removes the temporary file unless commit() succeeded.
    ~AtomicOutput();
    /// Where to write.
    const std::filesystem::path& temp_path() const { return m_temp; }
    const std::filesystem::path& target() const { return m_target; }
    /// Renames the temporary file over the target.
    void commit();

private:
    std::filesystem::path m_target, m_temp;
    bool m_committed = false;
};

/// Writes `text` to `target` atomically.
void write_text_atomic(const std::filesystem::path& target, const std::string& text);

/// Creates the folder `dir` and its parents if needed; IoError "DIR: cannot create WHAT: reason".
void create_folder(const std::filesystem::path& dir, const std::string& what);

/// Reads a whole file; throws IoError naming it.
std::string read_text(const std::filesystem::path& path);

} // namespace ecoterra::io
