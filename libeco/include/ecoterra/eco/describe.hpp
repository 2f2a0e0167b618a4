#pragma once
// Every catalogue of ecoterra in one place: `ecoterra describe` prints them and
// docs/parameters.md is generated from them (a test fails when the two differ).
#include <string>
#include <vector>

namespace ecoterra::eco {

/// The topics: "scene", "species", "terrain", "vehicle", "outputs", or "all".
std::vector<std::string> describe_topics();

/// The catalogues of a topic as text (aligned columns) or as Markdown tables. InputError for an
/// unknown topic, naming the known ones.
std::string describe(const std::string& topic, bool markdown);

} // namespace ecoterra::eco
