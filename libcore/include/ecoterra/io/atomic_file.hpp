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

/// This machine's host name ("unknown" if it has none): staging names carry it, so that a sweep
/// on a shared file system never takes another machine's live work for a dead process's.
std::string host_name();
/// True when process `pid` of this machine exists and is not a zombie (an orphan whose parent
/// died stays a zombie until someone reaps it, and in a container nobody may).
bool process_alive(long pid);
/// "HOST-PID" of this process: the tag of its staging names.
std::string process_tag();
/// Removes the entries of `dir` named "." + `head` + ... + `marker` + HOST-PID + ... whose
/// process, on this host, is gone (killed writers' staging folders and files); returns how
/// many. Others' and live processes' entries are left alone.
std::size_t sweep_dead_staging(const std::filesystem::path& dir, const std::string& head,
                               const std::string& marker);

/// Reads a whole file; throws IoError naming it.
std::string read_text(const std::filesystem::path& path);

} // namespace ecoterra::io
