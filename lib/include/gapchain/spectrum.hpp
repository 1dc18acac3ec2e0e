#pragma once
/// \file spectrum.hpp
/// Power spectral density of a uniformly sampled signal (Welch's method, FFTW), peaks labelled
/// as harmonics or subharmonics of the forcing, and a broadband indicator.

#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gapchain {

/// Tapering window of each Welch segment.
enum class Window { hann, rectangular };
/// Parses "hann" or "rectangular"; throws std::invalid_argument otherwise.
Window parse_window(std::string_view name);

/// Welch options.
struct PsdOptions {
    double sample_rate = 1.0;  ///< samples per unit reduced time, > 0
    int segment_length = 4096; ///< samples per segment, 8 .. 2^25 (any size; powers of 2 fastest)
    double overlap = 0.5;      ///< fraction of a segment shared with the next, [0, 0.95]
    Window window = Window::hann; ///< taper applied to each segment
    /// subtract each segment's mean before the window (Welch's constant detrend)
    bool remove_mean = true;
};

/// One-sided PSD: sum(density) * df equals the mean square of the (mean-removed) segment for a
/// rectangular window and one segment (Parseval), and estimates the signal's otherwise.
struct Psd {
    std::vector<double> frequency; ///< [cycles per unit reduced time], 0 .. sample_rate / 2
    std::vector<double> density;   ///< [signal^2 per unit frequency]
    double df = 0.0;               ///< frequency resolution
    int segments = 0;              ///< segments averaged
};

/// Welch PSD of signal (at least segment_length samples, all finite). FFTW plans are made once
/// per segment length and reused (thread-safe).
Psd welch_psd(const std::vector<double>& signal, const PsdOptions& options);

/// A spectral peak and what it is relative to the forcing frequency f_r.
struct SpectralPeak {
    double frequency = 0.0; ///< [1 / reduced time]
    /// Half the frequency resolution, df / 2 [1 / reduced time]: the line lies within it
    double frequency_error = 0.0;
    double power = 0.0; ///< power in the peak's bins (density * df summed)
    /// Estimated error of power [signal^2, >= 0]: band_power_errors() where the caller sets it;
    /// NaN where not estimated (spectral_content() alone, or fewer than 2 segments)
    double power_error = std::numeric_limits<double>::quiet_NaN();
    int first_bin = 0; ///< the peak's bins, first_bin .. last_bin of the PSD
    int last_bin = 0;
    int numerator = 0;   ///< the peak is at numerator / denominator * f_r, if labelled
    int denominator = 0; ///< 1: harmonic; > 1: subharmonic order; 0: unlabelled (no
                         ///< m/n within the peak's bins, or more than one)
    [[nodiscard]] std::string label() const; ///< "2 f_r", "1/2 f_r", "3/4 f_r", or "-"
};

/// Spectral reading of a PSD against the forcing frequency.
struct SpectralContent {
    std::vector<SpectralPeak> peaks; ///< local maxima above 1e-6 of the largest, by power
    double broadband_share = 0.0;    ///< power away from every m/n f_r (n <= max_order), [0, 1]
    /// Share of the bins (1 and up) within `width` bins of some m/n f_r, [0, 1]: the part of
    /// the spectrum the broadband share does not read. Above 1/2 the segment holds too few
    /// forcing periods to tell a line from broadband power (a chaotic row read 0 at 2 periods)
    double fraction_bin_share = 0.0;
    /// Its estimated error, >= 0: broadband_share_error() where the caller sets it; NaN where
    /// not estimated (spectral_content() alone, or fewer than 2 segments)
    double broadband_share_error = std::numeric_limits<double>::quiet_NaN();
};

/// The sampling error of each band's power in welch_psd(signal, options): the band (bins
/// first .. last, 0 <= first <= last <= segment_length / 2) is summed in every segment, and the
/// standard error of the mean of those sums follows from their spread over the segments with
/// Welch's (1967) correction for overlapping segments (the window's own correlation between
/// segments k hops apart). NaN for every band where the record holds fewer than 2 segments. A
/// signal that repeats segment to segment (a periodic motion sampled over whole periods) has an
/// error at round-off: what remains is the integration's.
std::vector<double> band_power_errors(const std::vector<double>& signal, const PsdOptions& options,
                                      const std::vector<std::pair<int, int>>& bands);

/// The sampling error of the broadband share that spectral_content() reads off
/// welch_psd(signal, options) with the same f_r, max_order and width: the share is a ratio of
/// mean powers over the segments, and its standard error follows from each segment's power
/// away from the fractions and in all (first order in their spread, with Welch's correction
/// for overlapping segments as in band_power_errors()). NaN with fewer than 2 segments or no
/// power.
double broadband_share_error(const std::vector<double>& signal, const PsdOptions& options,
                             double f_r, int max_order = 4, int width = 1);

/// Forcing periods a Welch segment holds whole so that every m/n f_r with n <= max_order falls
/// on a bin (and a line leaks no power beyond its neighbours under the Hann window):
/// lcm(1, ..., n) for the largest n <= max_order where that is at most 128; 12 for max_order
/// 4, 60 from 5 on (subharmonics of order 7 and up then fall between bins). max_order >= 1.
int whole_period_unit(int max_order);

/// The longest segment [samples] of at most `length` that holds a multiple of
/// whole_period_unit(max_order) periods, else of whole periods, of samples_per_period samples
/// each (>= 1); 0 where that is under 16 samples.
int whole_segment_within(int length, int samples_per_period, int max_order);

/// The default Welch segment [samples] for a record of `samples` samples taken
/// samples_per_period times a forcing period (>= 1): a multiple of whole_period_unit(max_order)
/// periods, the most up to 128 periods (or one unit, if longer) that leaves min_segments
/// segments at half overlap; one unit if the record holds fewer; the record's whole periods if
/// it holds less than a unit; at least 16 samples and at most `samples`.
int whole_period_segment(long samples, int samples_per_period, int max_order, int min_segments = 2);

/// How much `share`, the broadband share of welch_psd(signal, options) (spectral_content() with
/// f_r, max_order and width 1), moves on segments of half as many forcing periods
/// (whole_segment_within() half of options' segment, which holds samples_per_period samples a
/// period). The share counts the power more than a bin away from every m/n f_r, a band of
/// f_r / (the segment's periods) that narrows as segments lengthen, so the share rises towards
/// that of the spectrum's continuous part; if it falls as one over the segment's periods, the
/// move is what this segment misses (Fig 13's row at f_r = 3.3: 0.039 at 60 periods, 0.0445 at
/// 120, 0.0475 at 480). NaN where no whole half segment of 16 samples fits.
double broadband_share_resolution_error(const std::vector<double>& signal,
                                        const PsdOptions& options, double share, double f_r,
                                        int max_order, int samples_per_period);

/// Welch options for the same signal sampled at twice options' rate: twice the samples per
/// segment and exactly twice the hop, so that its segments cover the same stretches of time
/// and its bins up to options' Nyquist frequency are options' bins.
PsdOptions doubled_rate_options(const PsdOptions& options);

/// Share of psd's power (bins 1 and up) in the bins above `bin`, [0, 1]; 0 with no power. On
/// the PSD of a record at twice the asked rate (doubled_rate_options()) with bin the asked
/// Nyquist bin (asked segment_length / 2), it is the power the asked rate folds onto lower
/// frequencies: the aliased share.
double power_share_above(const Psd& psd, int bin);

/// The aliased share of the record `asked` takes every other sample of: power_share_above() of
/// welch_psd(fine, doubled_rate_options(asked)) at the asked Nyquist bin. fine holds at least
/// 2 asked.segment_length samples.
double aliased_share(const std::vector<double>& fine, const PsdOptions& asked);

/// Finds the peaks of psd and measures its broadband share: power more than `width` bins away
/// from every frequency m/n f_r with 1 <= n <= max_order (f_r > 0, max_order >= 1).
SpectralContent spectral_content(const Psd& psd, double f_r, int max_order = 4, int width = 1,
                                 int max_peaks = 20);

} // namespace gapchain
