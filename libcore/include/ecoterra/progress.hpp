#pragma once
// Progress of long library calls, for the command line. A caller installs a sink for the length
// of a call (ProgressScope); the library reports the fraction done with report_progress(), which
// does nothing without a sink or on another thread (OpenMP workers: only the thread that
// installed the sink reports). ProgressStage maps the reports of a part of the work into its
// share of the whole (layer 2 of 3 reports 0..1, the sink sees 1/3..2/3).
#include <functional>

namespace ecoterra {

class ProgressScope {
public:
    explicit ProgressScope(std::function<void(double)> sink);
    ~ProgressScope();
    ProgressScope(const ProgressScope&) = delete;
    ProgressScope& operator=(const ProgressScope&) = delete;

private:
    std::function<void(double)> m_sink;
    const std::function<void(double)>* m_previous;
};

class ProgressStage {
public:
    /// The reports made while this stage lives cover [begin, end] of the enclosing range.
    ProgressStage(double begin, double end);
    ~ProgressStage();
    ProgressStage(const ProgressStage&) = delete;
    ProgressStage& operator=(const ProgressStage&) = delete;

private:
    double m_offset, m_scale;
};

/// Reports that `fraction` (0..1) of the current stage is done.
void report_progress(double fraction);

} // namespace ecoterra
