#pragma once
/// \file signal.hpp
/// Uniformly sampled time series of one variable of a run (for spectra and time-series
/// Lyapunov estimates). Samples fall exactly on step ends: the step is refined so that every
/// sampling time is one.

#include "gapchain/poincare.hpp"
#include "gapchain/run.hpp"

#include <vector>

namespace gapchain {

/// A sampled signal.
struct Signal {
    std::vector<double> values; ///< samples, the first at the end of the transient
    double sample_rate = 0.0;   ///< samples per unit reduced time
    double t0 = 0.0;            ///< reduced time of the first sample
};

/// Observer that appends `variable` every `every`-th step end of the grid (while recording).
class SignalRecorder final : public Observer {
public:
    /// dyn must outlive the recorder; sample_interval (reduced time, > 0) must be a multiple of
    /// the run's step.
    SignalRecorder(const Dynamics& dyn, SectionVariable variable, double sample_interval,
                   Signal& out);
    void on_step(const StepView& step) override;

private:
    const Dynamics& m_dyn;
    SectionVariable m_variable;
    double m_interval;
    Signal& m_out;
};

/// Runs dyn over options (full length) and records variable samples_per_period times per
/// forcing period after the transient. A failed run is reported in the outcome.
Signal record_signal(const Dynamics& dyn, const RunOptions& options,
                     const SectionVariable& variable, int samples_per_period, RunOutcome& outcome,
                     const std::vector<double>& initial = {},
                     const ProgressCallback& progress = {});

} // namespace gapchain
