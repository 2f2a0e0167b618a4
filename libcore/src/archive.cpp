#include "ecoterra/archive.hpp"

namespace ecoterra {

SectionReader::SectionReader(ArchiveReader& in, std::string source) : m_source(std::move(source)) {
    while (!in.at_end()) {
        const std::string name = in.get_string();
        Part p;
        p.version = in.get<std::uint32_t>();
        p.bytes = in.get_vector<std::uint8_t>();
        if (!m_parts.emplace(name, std::move(p)).second)
            throw CheckpointError(m_source + ": the checkpoint has section '" + name + "' twice");
    }
}

std::uint32_t SectionReader::version(const std::string& name) const {
    const auto it = m_parts.find(name);
    return it == m_parts.end() ? 0 : it->second.version;
}

void SectionReader::finish() const {
    for (const auto& [name, part] : m_parts)
        if (!part.read)
            throw CheckpointError(m_source + ": the checkpoint has a section '" + name +
                                  "' (version " + std::to_string(part.version) +
                                  ") this ecoterra does not know; was it made by a newer one?");
}

} // namespace ecoterra
