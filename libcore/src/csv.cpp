#include "ecoterra/csv.hpp"

#include "ecoterra/error.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>

namespace ecoterra {

namespace {

/// The fields of one line (RFC 4180): a field in double quotes may hold commas, and "" inside
/// it stands for one quote; an unquoted field is taken as it is.
std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::string f;
    bool quoted = false, was_quoted = false;
    for (std::size_t k = 0; k < line.size(); ++k) {
        const char c = line[k];
        if (quoted) {
            if (c == '"' && k + 1 < line.size() && line[k + 1] == '"') {
                f += '"';
                ++k;
            } else if (c == '"') {
                quoted = false;
            } else {
                f += c;
            }
        } else if (c == '"' && f.empty() && !was_quoted) {
            quoted = was_quoted = true;
        } else if (c == ',') {
            out.push_back(std::move(f));
            f.clear();
            was_quoted = false;
        } else {
            f += c;
        }
    }
    if (!line.empty()) out.push_back(std::move(f));
    return out;
}

bool read_line(std::ifstream& in, std::string& line) {
    if (!std::getline(in, line)) return false;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
}

} // namespace

CsvReader::CsvReader(const std::filesystem::path& path, const std::string& what)
    : m_path(path), m_in(path) {
    if (!m_in)
        throw InputError(path.string() + ": cannot open the " + what + " (" + std::strerror(errno) +
                         ")");
    if (!read_line(m_in, m_header_line))
        throw InputError(path.string() + ": the " + what + " is empty");
    m_header = split(m_header_line);
    for (std::size_t a = 0; a < m_header.size(); ++a)
        for (std::size_t b = a + 1; b < m_header.size(); ++b)
            if (!m_header[a].empty() && m_header[a] == m_header[b])
                throw InputError(path.string() + ": the header names column " + m_header[a] +
                                 " twice (columns " + std::to_string(a + 1) + " and " +
                                 std::to_string(b + 1) + "); which one is meant is unclear");
}

int CsvReader::column(const std::string& name) const {
    const auto it = std::find(m_header.begin(), m_header.end(), name);
    return it == m_header.end() ? -1 : static_cast<int>(it - m_header.begin());
}

int CsvReader::require(const std::string& name) const {
    const int c = column(name);
    if (c < 0)
        throw InputError(m_path.string() + ": the header lacks column " + name + " (got '" +
                         m_header_line + "')");
    return c;
}

bool CsvReader::next() {
    std::string line;
    while (read_line(m_in, line)) {
        ++m_line;
        if (line.empty()) continue;
        m_row = split(line);
        return true;
    }
    return false;
}

double CsvReader::number(int col, const std::string& name, bool non_negative) const {
    const std::string t = col >= 0 && col < static_cast<int>(m_row.size())
                              ? m_row[static_cast<std::size_t>(col)]
                              : std::string();
    // Spaces around the number are allowed, anything else after it is not ("12abc").
    const std::size_t b = t.find_first_not_of(" \t"), e = t.find_last_not_of(" \t");
    const char* first = t.data() + (b == std::string::npos ? t.size() : b);
    const char* last = t.data() + (e == std::string::npos ? t.size() : e + 1);
    double v = 0;
    const auto [end, ec] = std::from_chars(first, last, v);
    if (ec != std::errc() || end != last || first == last || !std::isfinite(v))
        throw InputError(where() + ": " + name + " = '" + t + "' is not a finite number");
    if (non_negative && v < 0) throw InputError(where() + ": " + name + " = " + t + " is negative");
    return v;
}

std::string CsvReader::text(int col) const {
    return col >= 0 && col < static_cast<int>(m_row.size()) ? m_row[static_cast<std::size_t>(col)]
                                                            : std::string();
}

std::string CsvReader::where() const {
    return m_path.string() + " line " + std::to_string(m_line);
}

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string q = "\"";
    for (const char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

} // namespace ecoterra
