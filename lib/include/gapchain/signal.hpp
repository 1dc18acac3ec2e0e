#pragma once
/// \file signal.hpp
/// Uniformly sampled time series of one variable of a run (for spectra and time-series
/// Lyapunov estimates). Samples fall exactly on step ends: the step is refined so that every
/// sampling time is one.

#include "gapchain/poincare.hpp"
#include "gapchain/run.hpp"
#include "gapchain/spectrum.hpp"

#include <limits>
#include <string>
#include <vector>

namespace gapchain {

/// A sampled signal.
struct Signal {
    std::vector<double> values; ///< samples, the first at the end of the transient
    double sample_rate = 0.0;   ///< samples per unit reduced time
    double t0 = 0.0;            ///< reduced time of the first sample
    /// The variable's least and largest value at every step end of the recorded window (the
    /// samples among them): what the run saw between the samples
    double step_min = std::numeric_limits<double>::infinity();
    double step_max = -std::numeric_limits<double>::infinity();
};

/// The record at half fine's rate: its samples 0, 2, 4, ... (the same t0).
Signal every_other(const Signal& fine);

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

/// The spectrum of one variable of a run, as gapchain-spectrum and Python's spectrum() ask for
/// it (one set of rules and limits for both).
struct RowSpectrumOptions {
    std::string variable = "u1"; ///< a state variable: u1..uNm, v1..vNm, g0..gNm or F0..FNm
    /// Samples per forcing period, 2 .. 100000. The run records twice as many (four times for
    /// a contact force F_j, whose kinks fold harmonics from far above), to measure the aliasing
    /// (RowSpectrum::aliased_share); the spectrum is that of every other (every fourth) sample
    int samples_per_period = 32;
    /// Welch segment [samples], 16 .. 2^24 and at most those recorded; 0:
    /// whole_period_segment() (a shipped scene's 100 periods at 32 samples a period: 60
    /// periods, 1920 samples, 2 segments)
    int segment = 0;
    Window window = Window::hann; ///< segment taper
    int order = 4;                ///< largest subharmonic order n labelled (m/n f_r), 1 .. 64
};

/// The recorded signal's size, its PSD and its reading against f_r.
struct RowSpectrum {
    RunOutcome outcome; ///< the run (psd and content are empty unless it completed)
    long samples = 0;   ///< samples recorded
    int segment = 0;    ///< Welch segment used [samples]
    double segment_periods =
        0.0; ///< forcing periods a segment holds (segment / samples_per_period)
    /// The segment holds a whole multiple of whole_period_unit(order) periods: every m/n f_r
    /// falls on a bin. Otherwise the lines leak; the broadband share's and the peaks' errors
    /// add how much they move on the longest whole segment the asked one holds (NaN where
    /// none of 16 samples fits)
    bool whole_periods = true;
    double sample_rate = 0; ///< [samples per unit reduced time]
    Psd psd;                ///< Welch PSD of the variable
    /// Peaks and broadband share (its error: the segments' spread, broadband_share_error(),
    /// plus aliased_share; NaN with a single segment); each peak's power_error is the larger of its
    /// standard error over the segments (band_power_errors()) and 2 run.tolerance x power, plus its
    /// aliasing error (what folds onto it from above the Nyquist frequency, or how much its
    /// power moves when the rate is doubled, the larger; for a contact force plus what folds
    /// onto it at twice the rate); NaN with a single segment
    SpectralContent content;
    /// Share of the variable's power between the Nyquist frequency (samples_per_period / 2
    /// forcing harmonics) and twice it, measured on the record taken at twice the rate, [0, 1]:
    /// power the asked rate folds onto lower frequencies (aliasing). Above 1e-3 the spectrum's
    /// shape is the sampling's as much as the row's: raise samples_per_period. A lower bound:
    /// power above twice the Nyquist frequency folds in the record at twice the rate too and
    /// is not seen (at 2 samples per period, most of it)
    double aliased_share = 0.0;
    /// The samples' range (largest less least) over the variable's range at every step end of
    /// the recorded window, [0, 1] (1 for a variable that never moves). Well below 1 the
    /// samples miss its peaks, which aliasing alone need not show: at 7 samples per period the
    /// contact force of Fig 5's row was sampled between its impacts, all zeros
    double sampled_range_share = 1.0;
    double wall_time_s = 0.0; ///< the run and the PSD [s]
};

/// Throws std::invalid_argument naming variable, samples_per_period, segment (also when longer
/// than the samples run records: (periods - transient) x samples_per_period + 1) or order; dyn
/// must have harmonic forcing.
void validate(const RowSpectrumOptions& options, const Dynamics& dyn, const RunOptions& run);

/// Records options.variable over run (validate() first) and takes its spectrum.
RowSpectrum row_spectrum(const Dynamics& dyn, const RunOptions& run,
                         const RowSpectrumOptions& options, const std::vector<double>& initial = {},
                         const ProgressCallback& progress = {});

} // namespace gapchain
