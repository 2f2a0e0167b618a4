#pragma once
// Reading comma-separated tables (RFC 4180 quoting) by their header: columns are found by name,
// rows one at a time, numbers parsed in full (no "12abc") with errors that name the file, the line,
// the column and the value.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace ecoterra {

class CsvReader {
public:
    /// Opens `path` and reads its header; InputError naming the file if it cannot.
    CsvReader(const std::filesystem::path& path, const std::string& what);
    const std::vector<std::string>& header() const { return m_header; }
    const std::string& header_line() const { return m_header_line; }
    /// Index of the column `name`, or -1.
    int column(const std::string& name) const;
    /// Index of the column `name`; InputError naming the file and the header if absent.
    int require(const std::string& name) const;
    /// Moves to the next non-empty row; false at the end.
    bool next();
    /// The value in column `col` of the row as a finite number; InputError naming the file, the
    /// line, `name` and the text otherwise (and when negative with `non_negative`).
    double number(int col, const std::string& name, bool non_negative = false) const;
    /// The text in column `col` of the row ("" past its end).
    std::string text(int col) const;
    /// The number of fields in the current row.
    int fields() const { return static_cast<int>(m_row.size()); }
    /// "FILE line N", for messages about the current row.
    std::string where() const;

private:
    std::filesystem::path m_path;
    std::ifstream m_in;
    std::string m_header_line;
    std::vector<std::string> m_header, m_row;
    int m_line = 1;
};

/// `text` as one CSV field: as it is, or in double quotes (with "" for a quote) when it holds a
/// comma, a quote or a line break (RFC 4180; CsvReader reads it back).
std::string csv_field(const std::string& text);

} // namespace ecoterra
