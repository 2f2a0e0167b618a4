#include "ecoterra/progress.hpp"

#include <algorithm>

namespace ecoterra {

namespace {
thread_local const std::function<void(double)>* t_sink = nullptr;
thread_local double t_offset = 0, t_scale = 1;
} // namespace

ProgressScope::ProgressScope(std::function<void(double)> sink)
    : m_sink(std::move(sink)), m_previous(t_sink) {
    t_sink = &m_sink;
}

ProgressScope::~ProgressScope() {
    t_sink = m_previous;
}

ProgressStage::ProgressStage(double begin, double end) : m_offset(t_offset), m_scale(t_scale) {
    t_offset = m_offset + m_scale * begin;
    t_scale = m_scale * (end - begin);
}

ProgressStage::~ProgressStage() {
    t_offset = m_offset;
    t_scale = m_scale;
}

void report_progress(double fraction) {
    if (t_sink && *t_sink) (*t_sink)(t_offset + t_scale * std::clamp(fraction, 0.0, 1.0));
}

} // namespace ecoterra
