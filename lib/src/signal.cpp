#include "gapchain/signal.hpp"

#include "detail/check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

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
        m_out.step_min = m_out.step_max = m_out.values.back();
    }
    const double value = m_variable.value(m_dyn, step.t1, step.y1);
    m_out.step_min = std::min(m_out.step_min, value);
    m_out.step_max = std::max(m_out.step_max, value);
    // Only step ends on the sampling grid count; split pieces end elsewhere.
    const double k = (step.t1 - m_out.t0) / m_interval;
    if (std::abs(k - std::round(k)) < 1e-6 &&
        std::lround(k) == static_cast<long>(m_out.values.size()))
        m_out.values.push_back(value);
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

namespace {

SectionVariable spectrum_variable(const std::string& name, const Dynamics& dyn) {
    return SectionVariable::parse_state(name, dyn.bodies(), "variable");
}

/// Samples per period the run records: twice the asked ones for the aliasing check, four times
/// for a contact force (add_second_folds()).
int held_rate(const RowSpectrumOptions& o, const Dynamics& dyn) {
    const bool force = spectrum_variable(o.variable, dyn).kind == SectionVariable::Kind::force;
    return (force ? 4 : 2) * o.samples_per_period;
}

} // namespace

void validate(const RowSpectrumOptions& o, const Dynamics& dyn, const RunOptions& run) {
    validate(run);
    require_harmonic(dyn, "spectrum"); // before the sample count, which needs a period
    (void)spectrum_variable(o.variable, dyn);
    detail::require_range("samples_per_period", o.samples_per_period, 2, 100000);
    if (o.segment != 0 && (o.segment < 16 || o.segment > (1 << 24)))
        throw std::invalid_argument("segment: must be 0 (whole forcing periods, up to 128, the "
                                    "record holds twice) or an integer in [16, 16777216], got " +
                                    std::to_string(o.segment));
    detail::require_range("order", o.order, 1, 64);
    // Both ends of the recorded window are samples.
    const long samples = (run.periods - with_transient_resolved(dyn, run).transient_periods) *
                             static_cast<long>(o.samples_per_period) +
                         1;
    if (o.segment == 0 && samples < 16)
        throw std::invalid_argument(
            "segment: the record holds " + std::to_string(samples) +
            " samples ((run.periods - run.transient_periods) x samples per period + 1), fewer "
            "than the shortest segment's 16; record more periods or more samples per period");
    if (samples < o.segment)
        throw std::invalid_argument("segment: must be at most the recorded samples " +
                                    std::to_string(samples) +
                                    " ((run.periods - run.transient_periods) x samples per "
                                    "period + 1), got " +
                                    std::to_string(o.segment));
    // The recorded samples are held in memory, twice as many for the aliasing check (four
    // times for a contact force, add_second_folds()) (a double
    // each, and the PSD's work as much): refuse up front what the machine cannot hold instead
    // of failing after the run.
    const int times = held_rate(o, dyn) / o.samples_per_period;
    // A force's segment is read at four times the rate too (add_second_folds()), within
    // welch_psd()'s 2^25: at 100000 samples a period it failed after the whole run (a reread,
    // helper-86).
    const long segment =
        o.segment != 0 ? o.segment : whole_period_segment(samples, o.samples_per_period, o.order);
    if (times == 4 && segment > (1L << 23))
        throw std::invalid_argument(
            "segment: a contact force's spectrum is also read at four times the rate, so its "
            "segment holds at most 8388608 samples (2^23), got " +
            std::to_string(segment) + "; fewer samples per period or a shorter segment");
    if (samples * times > 500'000'000L)
        throw std::invalid_argument(
            "samples_per_period: (run.periods - run.transient_periods) x samples per period = " +
            std::to_string(samples) + " samples, held at " + (times == 2 ? "twice" : "four times") +
            " the rate (about " + detail::format_number(std::ceil(samples * times * 20e-9)) +
            " GB); at most " + (times == 2 ? "2.5e8" : "1.25e8 for a contact force") +
            ": fewer samples per period or fewer periods");
}

Signal every_other(const Signal& fine) {
    Signal coarse;
    coarse.sample_rate = fine.sample_rate / 2.0;
    coarse.t0 = fine.t0;
    for (std::size_t i = 0; i < fine.values.size(); i += 2)
        coarse.values.push_back(fine.values[i]);
    return coarse;
}

namespace {

// How far power P moves when power P_m folds onto it with any phase: P_m + 2 sqrt(P P_m).
double folded_error(double power, double mirror) {
    return mirror + 2.0 * std::sqrt(power * mirror);
}

double band_power(const Psd& psd, int first, int last) {
    double power = 0.0;
    for (int k = first; k <= last; ++k)
        power += psd.density[static_cast<std::size_t>(k)] * psd.df;
    return power;
}

// The fine record cut into segments of twice the samples covers the same stretches of time as
// the asked one, so their bins share frequencies up to the asked Nyquist frequency: what lies
// above it in the fine PSD is folded back by the asked rate. Bin k of the asked PSD receives
// fine bin N - k (N the asked segment). The folded amplitude adds to the peak's with any phase,
// so the power moves by up to P_mirror + 2 sqrt(P P_mirror); the fine record's own folds, a
// step further up, show in how much the power moved between the two rates. On Fig 5's row at
// 32 samples per period the larger of the two covered the error against 2048 samples per
// period at every peak of u1, v1 and F1, by 1.1 to 4.6x on u1; at 64 a second reader found
// F1's (flagged aliased) up to 2.3x short and v1's 1.1x short at 11-12 f_r (docs/chaos.md).
void measure_aliasing(const Signal& fine, const std::vector<double>& coarse, const PsdOptions& po,
                      RowSpectrum& r, std::vector<double>& aliasing) {
    PsdOptions fo = doubled_rate_options(po);
    const auto held = static_cast<int>(fine.values.size());
    if (held < fo.segment_length) {
        // One segment as long as the record (2 S - 1 fine samples against 2 S): the share is
        // read on the whole fine record; the peaks' errors are unknown with one segment anyway.
        fo.segment_length = held - 1;
        const Psd whole = welch_psd(fine.values, fo);
        r.aliased_share =
            power_share_above(whole, (static_cast<int>(whole.density.size()) - 1) / 2);
        aliasing.assign(r.content.peaks.size(), std::numeric_limits<double>::quiet_NaN());
        return;
    }
    const Psd fine_psd = welch_psd(fine.values, fo);
    Psd compared = r.psd;
    // The fine record ends one sample short of the last segment the asked one may hold
    // (2 S - 1 samples against S): compare both without it.
    if (fine_psd.segments != compared.segments)
        compared = welch_psd(std::vector<double>(coarse.begin(), coarse.end() - 1), po);
    r.aliased_share = power_share_above(fine_psd, po.segment_length / 2);
    for (const SpectralPeak& p : r.content.peaks) {
        const double fine_power = band_power(fine_psd, p.first_bin, p.last_bin);
        const double mirror =
            band_power(fine_psd, po.segment_length - p.last_bin, po.segment_length - p.first_bin);
        aliasing.push_back(
            std::max(std::abs(band_power(compared, p.first_bin, p.last_bin) - fine_power),
                     folded_error(fine_power, mirror)));
    }
}

// A contact force has a kink where its contact closes and opens, so its harmonics decay as
// 1/h^2 only, and the harmonics near twice the Nyquist frequency fold onto the peaks as well:
// the fine record shares those folds with the asked one, and no move between the two rates
// shows them. Fig 5's F0 read 1 f_r at 1.334087e-3 +- 3.3e-7 at 256 samples a period where
// its Fourier power is 1.332812e-3, 3.9 bars off (an independent review, helper-84,
// 2026-11-29): the pair 2N +- h (N the samples per period) is the fold there, and
// measure_aliasing() at 2N reads it (+- 2e-6). So a force is recorded at four times the asked
// rate, and each peak's error adds the fold onto it at twice the rate as measure_aliasing()
// reads the first: the record at four times the rate holds the pair 2N +- h at its mirror bin.
void add_second_folds(const Signal& finest, const PsdOptions& po, const RowSpectrum& r,
                      std::vector<double>& aliasing) {
    const PsdOptions twice = doubled_rate_options(po);
    const PsdOptions four_times = doubled_rate_options(twice);
    if (static_cast<int>(finest.values.size()) < four_times.segment_length) return;
    const Psd finest_psd = welch_psd(finest.values, four_times);
    const int S = twice.segment_length;
    for (std::size_t i = 0; i < aliasing.size(); ++i) {
        const SpectralPeak& p = r.content.peaks[i];
        const double power = band_power(finest_psd, p.first_bin, p.last_bin);
        const double mirror = band_power(finest_psd, S - p.last_bin, S - p.first_bin);
        aliasing[i] += folded_error(power, mirror);
    }
}

// Power in psd's bins whose frequencies lie in [low, high], widened by half its bin.
double power_between(const Psd& psd, double low, double high) {
    double power = 0.0;
    for (std::size_t k = 1; k < psd.density.size(); ++k)
        if (psd.frequency[k] >= low - 0.5 * psd.df && psd.frequency[k] <= high + 0.5 * psd.df)
            power += psd.density[k] * psd.df;
    return power;
}

// A segment that is not a whole number of whole_period_unit() periods puts the lines m/n f_r
// between bins, where the Hann window spreads them beyond the bins next to them: power moves
// from the lines into the broadband share (a periodic row at 30 samples a period read
// 0.0152 +- 5.7e-6 against 0, its 1 f_r line 0.177 +- 4.2e-5 against 0.1796, a helper's probe
// of 2026-11-27). The same record cut into the longest whole segment that the asked one holds
// reads them without that spread: the difference is the leakage's error, of the share
// (returned) and of each peak (its power over the same frequencies). 0 for a whole segment;
// NaN where no shorter whole segment of 16 samples fits.
double measure_leakage(const std::vector<double>& signal, const PsdOptions& po,
                       const RowSpectrumOptions& o, double f_r, RowSpectrum& r,
                       std::vector<double>& leakage) {
    r.whole_periods = r.segment % (whole_period_unit(o.order) * o.samples_per_period) == 0;
    if (r.whole_periods) return 0.0;
    PsdOptions whole = po;
    whole.segment_length = whole_segment_within(r.segment, o.samples_per_period, o.order);
    // A segment of whole periods shorter than one unit is its own fallback: its leakage is
    // not measured, not 0.
    if (whole.segment_length == 0 || whole.segment_length == r.segment) {
        leakage.assign(leakage.size(), std::numeric_limits<double>::quiet_NaN());
        return std::numeric_limits<double>::quiet_NaN();
    }
    const Psd psd = welch_psd(signal, whole);
    const SpectralContent content = spectral_content(psd, f_r, o.order);
    for (std::size_t i = 0; i < leakage.size(); ++i) {
        const SpectralPeak& p = r.content.peaks[i];
        leakage[i] = std::abs(p.power - power_between(psd, r.psd.frequency[p.first_bin],
                                                      r.psd.frequency[p.last_bin]));
    }
    return std::abs(r.content.broadband_share - content.broadband_share);
}

} // namespace

RowSpectrum row_spectrum(const Dynamics& dyn, const RunOptions& run, const RowSpectrumOptions& o,
                         const std::vector<double>& initial, const ProgressCallback& progress) {
    validate(o, dyn, run);
    const auto start = std::chrono::steady_clock::now();
    RowSpectrum r;
    const auto finish = [&] {
        r.wall_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return r;
    };
    const SectionVariable variable = spectrum_variable(o.variable, dyn);
    const bool force = variable.kind == SectionVariable::Kind::force;
    const Signal finest =
        record_signal(dyn, run, variable, held_rate(o, dyn), r.outcome, initial, progress);
    const Signal fine = force ? every_other(finest) : finest;
    const Signal signal = every_other(fine);
    if (!signal.values.empty() && finest.step_max > finest.step_min) {
        const auto [least, largest] =
            std::minmax_element(signal.values.begin(), signal.values.end());
        r.sampled_range_share = (*largest - *least) / (finest.step_max - finest.step_min);
    }
    r.samples = static_cast<long>(signal.values.size());
    r.sample_rate = signal.sample_rate;
    if (r.outcome.status != RunStatus::completed) return finish();
    r.segment =
        o.segment != 0 ? o.segment : whole_period_segment(r.samples, o.samples_per_period, o.order);
    r.segment_periods = static_cast<double>(r.segment) / o.samples_per_period;
    PsdOptions po;
    po.sample_rate = signal.sample_rate;
    po.segment_length = r.segment;
    po.window = o.window;
    r.psd = welch_psd(signal.values, po);
    r.content = spectral_content(r.psd, dyn.ground_motion().f_r(), o.order);
    std::vector<std::pair<int, int>> bands;
    for (const SpectralPeak& p : r.content.peaks)
        bands.emplace_back(p.first_bin, p.last_bin);
    const std::vector<double> spread = band_power_errors(signal.values, po, bands);
    std::vector<double> aliasing;
    measure_aliasing(fine, signal.values, po, r, aliasing);
    if (force) add_second_folds(finest, po, r, aliasing);
    const double f_r = dyn.ground_motion().f_r();
    std::vector<double> leakage(bands.size(), 0.0);
    const double leaked_share = measure_leakage(signal.values, po, o, f_r, r, leakage);
    // Folded power lands anywhere, on the fractions or between them: the share moves by at
    // most the share folded.
    r.content.broadband_share_error =
        broadband_share_error(signal.values, po, f_r, o.order) + r.aliased_share + leaked_share +
        broadband_share_resolution_error(signal.values, po, r.content.broadband_share, f_r, o.order,
                                         o.samples_per_period);
    // A power is an amplitude squared: the samples' relative error run.tolerance moves it by
    // twice that. The segments' spread is the sampling error; a periodic record has none.
    for (std::size_t i = 0; i < bands.size(); ++i) {
        SpectralPeak& p = r.content.peaks[i];
        if (std::isfinite(spread[i]))
            p.power_error =
                std::max(spread[i], 2.0 * run.tolerance * p.power) + aliasing[i] + leakage[i];
    }
    return finish();
}

} // namespace gapchain
