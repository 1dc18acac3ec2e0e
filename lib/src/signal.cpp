#include "gapchain/signal.hpp"

#include "detail/check.hpp"

#include <cmath>

namespace gapchain {

SignalRecorder::SignalRecorder(const Dynamics& dyn, SectionVariable variable,
                               double sample_interval, Signal& out)
    : m_dyn(dyn), m_variable(variable), m_interval(sample_interval), m_out(out) {
    detail::require_range("sample interval", sample_interval, 0.0, 1e12, detail::Bound::open_low);
    m_out.sample_rate = 1.0 / sample_interval;
}

void SignalRecorder::on_step(const StepView& step) {
    if (!step.recording) return;
    if (m_out.values.empty()) {
        m_out.t0 = step.t0;
        m_out.values.push_back(m_variable.value(m_dyn, step.t0, step.y0));
    }
    // Only step ends on the sampling grid count; split pieces end elsewhere.
    const double k = (step.t1 - m_out.t0) / m_interval;
    if (std::abs(k - std::round(k)) < 1e-6 &&
        std::lround(k) == static_cast<long>(m_out.values.size()))
        m_out.values.push_back(m_variable.value(m_dyn, step.t1, step.y1));
}

Signal record_signal(const Dynamics& dyn, const RunOptions& options,
                     const SectionVariable& variable, int samples_per_period, RunOutcome& outcome,
                     const std::vector<double>& initial, const ProgressCallback& progress) {
    validate(options);
    require_harmonic(dyn, "spectrum");
    PlannedRun planned(dyn, options, initial, samples_per_period);
    Signal signal;
    SignalRecorder recorder(dyn, variable, dyn.period() / samples_per_period, signal);
    Observer* observers[] = {&recorder};
    outcome = planned.run(observers, progress);
    return signal;
}

} // namespace gapchain
