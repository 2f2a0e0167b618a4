#pragma once
// Gathering an ensemble's members into tables and pictures (OUT/summary/):
//   members.csv     one row per member: index, combination, replicate, seed, status, the axis
//                   values, every metric (units in the column names), seconds, error
//   aggregate.csv   one row per combination of axis values: members, ok, failed, and per metric
//                   mean, sd, p10, p50, p90 over the members that succeeded
//   histograms.csv  (run bases) the mean diameter histogram of each combination
//   summary.h5      the same three tables, a dataset per column with its units
//   NAME.png        the manifest's pictures
#include "ecoterra/ensemble/manifest.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace ecoterra::ensemble {

struct SummaryReport {
    std::size_t members = 0, ok = 0, failed = 0, missing = 0;
    std::vector<std::size_t> failed_members, missing_members;
    std::vector<std::string> failures; ///< "member N: message" of each failed member
    std::vector<std::filesystem::path> files;
};

/// Reads every finished member's record and writes the summary (each file atomically). Members
/// not finished are counted as missing; failed members appear with their message.
SummaryReport write_summary(const std::filesystem::path& out, const Manifest& m);

/// "0-4,7,9-11": a list of member indices as ranges (for Slurm's --array).
std::string index_ranges(const std::vector<std::size_t>& indices);

/// The unit of a metric or column from the suffix of its name ("m/s" for *_m_per_s).
std::string unit_of(const std::string& column);

} // namespace ecoterra::ensemble
