#include "ecoterra/terrain/fft.hpp"

#include <fftw3.h>

#include <memory>
#include <mutex>

namespace ecoterra::terrain {

namespace {
/// FFTW's planner is not thread-safe: every plan is made and destroyed under this lock.
std::mutex& planner_mutex() {
    static std::mutex m;
    return m;
}

struct PlanDeleter {
    void operator()(fftw_plan_s* p) const {
        std::lock_guard<std::mutex> lock(planner_mutex());
        fftw_destroy_plan(p);
    }
};
using Plan = std::unique_ptr<fftw_plan_s, PlanDeleter>;
} // namespace

HalfSpectrum forward_real_fft(const RasterD& field) {
    HalfSpectrum spec(field.nx(), field.ny());
    RasterD in = field; // FFTW may touch the input during planning
    Plan plan;
    {
        std::lock_guard<std::mutex> lock(planner_mutex());
        plan.reset(fftw_plan_dft_r2c_2d(field.ny(), field.nx(), in.data(),
                                        reinterpret_cast<fftw_complex*>(spec.data()),
                                        FFTW_ESTIMATE));
    }
    if (!plan) throw Error("FFTW could not plan a forward transform");
    fftw_execute(plan.get());
    return spec;
}

void inverse_real_fft(const HalfSpectrum& spec, RasterD& out) {
    HalfSpectrum work = spec; // c2r destroys its input
    Plan plan;
    {
        std::lock_guard<std::mutex> lock(planner_mutex());
        plan.reset(fftw_plan_dft_c2r_2d(out.ny(), out.nx(),
                                        reinterpret_cast<fftw_complex*>(work.data()), out.data(),
                                        FFTW_ESTIMATE));
    }
    if (!plan) throw Error("FFTW could not plan an inverse transform");
    fftw_execute(plan.get());
}

} // namespace ecoterra::terrain
