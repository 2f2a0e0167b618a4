#pragma once
// A minimal binary archive for checkpoints: trivially copyable values, vectors, strings and
// rasters, stored bit-exact in native byte order. The checkpoint blob of a run starts with a magic
// tag and a format version; reading past the end, or a wrong tag, throws ecoterra::Error.
#include "ecoterra/error.hpp"
#include "ecoterra/hash.hpp"
#include "ecoterra/raster.hpp"

#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace ecoterra {

class ArchiveWriter {
public:
    template <class T>
    void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
        m_buf.insert(m_buf.end(), p, p + sizeof(T));
    }
    template <class T>
    void put_vector(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        put<std::uint64_t>(v.size());
        const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
        m_buf.insert(m_buf.end(), p, p + v.size() * sizeof(T));
    }
    void put_string(const std::string& s) {
        put<std::uint64_t>(s.size());
        m_buf.insert(m_buf.end(), s.begin(), s.end());
    }
    template <class T>
    void put_raster(const Raster<T>& r) {
        const auto& g = r.grid();
        put(g.nx);
        put(g.ny);
        put(g.cell_size_m);
        put(g.origin_x_m);
        put(g.origin_y_m);
        const auto* p = reinterpret_cast<const std::uint8_t*>(r.data());
        m_buf.insert(m_buf.end(), p, p + static_cast<std::size_t>(r.size()) * sizeof(T));
    }
    const std::vector<std::uint8_t>& bytes() const { return m_buf; }

private:
    std::vector<std::uint8_t> m_buf;
};

class ArchiveReader {
public:
    ArchiveReader(const std::uint8_t* data, std::size_t size, std::string source)
        : m_p(data), m_end(data + size), m_source(std::move(source)) {}
    template <class T>
    T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        need(sizeof(T));
        T v;
        std::memcpy(&v, m_p, sizeof(T));
        m_p += sizeof(T);
        return v;
    }
    template <class T>
    std::vector<T> get_vector() {
        const auto n = get<std::uint64_t>();
        need(n * sizeof(T));
        std::vector<T> v(n);
        if (n) std::memcpy(v.data(), m_p, n * sizeof(T));
        m_p += n * sizeof(T);
        return v;
    }
    std::string get_string() {
        const auto n = get<std::uint64_t>();
        need(n);
        std::string s(reinterpret_cast<const char*>(m_p), n);
        m_p += n;
        return s;
    }
    template <class T>
    Raster<T> get_raster() {
        GridSpec g;
        g.nx = get<decltype(g.nx)>();
        g.ny = get<decltype(g.ny)>();
        g.cell_size_m = get<double>();
        g.origin_x_m = get<double>();
        g.origin_y_m = get<double>();
        Raster<T> r(g);
        const std::size_t bytes = static_cast<std::size_t>(r.size()) * sizeof(T);
        need(bytes);
        std::memcpy(r.data(), m_p, bytes);
        m_p += bytes;
        return r;
    }
    bool at_end() const { return m_p == m_end; }

private:
    void need(std::size_t n) const {
        if (static_cast<std::size_t>(m_end - m_p) < n)
            throw CheckpointError(m_source + ": the checkpoint is truncated or of another format");
    }
    const std::uint8_t* m_p;
    const std::uint8_t* m_end;
    std::string m_source;
};

/// Checkpoint sections: a checkpoint as named parts, each with a version of its own, so that a new
/// column in one process's state changes that section's version only. A section is stored as its
/// name, its version and its bytes.
class SectionWriter {
public:
    explicit SectionWriter(ArchiveWriter& out) : m_out(out) {}
    /// Writes section `name` at `version`: what `body(ArchiveWriter&)` puts.
    template <class F>
    void section(const std::string& name, std::uint32_t version, F&& body) {
        ArchiveWriter part;
        body(part);
        m_out.put_string(name);
        m_out.put(version);
        m_out.put_vector(part.bytes());
    }

private:
    ArchiveWriter& m_out;
};

class SectionReader {
public:
    /// Reads the sections that fill the rest of `in`; `source` names the checkpoint in messages.
    SectionReader(ArchiveReader& in, std::string source);
    /// The version of section `name` in the checkpoint, 0 when it has none.
    std::uint32_t version(const std::string& name) const;
    /// Reads section `name` with `body(ArchiveReader&, version)`, accepting versions `oldest` to
    /// `newest` (older ones the body converts). CheckpointError naming the section when it is
    /// absent, of another version, or when `body` leaves bytes unread.
    template <class F>
    void read(const std::string& name, std::uint32_t oldest, std::uint32_t newest, F&& body) {
        const auto it = m_parts.find(name);
        if (it == m_parts.end())
            throw CheckpointError(m_source + ": the checkpoint has no section '" + name + "'");
        const std::uint32_t v = it->second.version;
        if (v < oldest || v > newest)
            throw CheckpointError(m_source + ": checkpoint section '" + name + "' has version " +
                                  std::to_string(v) + ", this ecoterra reads versions " +
                                  std::to_string(oldest) + " to " + std::to_string(newest));
        ArchiveReader r(it->second.bytes.data(), it->second.bytes.size(),
                        m_source + " (section " + name + ")");
        body(r, v);
        if (!r.at_end())
            throw CheckpointError(m_source + ": checkpoint section '" + name +
                                  "' holds more than this ecoterra reads from its version " +
                                  std::to_string(v));
        it->second.read = true;
    }
    /// CheckpointError naming the first section no read() took (a newer ecoterra's).
    void finish() const;

private:
    struct Part {
        std::uint32_t version = 0;
        std::vector<std::uint8_t> bytes;
        bool read = false;
    };
    std::map<std::string, Part> m_parts;
    std::string m_source;
};

} // namespace ecoterra
