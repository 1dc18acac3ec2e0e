#pragma once
/// \file spectrum.hpp
/// Power spectral density of a uniformly sampled signal (Welch's method, FFTW), peaks labelled
/// as harmonics or subharmonics of the forcing, and a broadband indicator.

#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

/// Tapering window of each Welch segment.
enum class Window { hann, rectangular };
/// Parses "hann" or "rectangular"; throws std::invalid_argument otherwise.
Window parse_window(std::string_view name);

/// Welch options.
struct PsdOptions {
    double sample_rate = 1.0;  ///< samples per unit reduced time, > 0
    int segment_length = 4096; ///< samples per segment, 8 .. 2^24 (any size; powers of 2 fastest)
    double overlap = 0.5;      ///< fraction of a segment shared with the next, [0, 0.95]
    Window window = Window::hann; ///< taper applied to each segment
    bool remove_mean = true;      ///< subtract the signal's mean first
};

/// One-sided PSD: sum(density) * df equals the mean square of the (mean-removed) signal for a
/// rectangular window and one segment (Parseval), and estimates it otherwise.
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
    double power = 0.0;     ///< power in the peak's bins (density * df summed)
    int numerator = 0;      ///< the peak is at numerator / denominator * f_r, if labelled
    int denominator = 0;    ///< 1: harmonic; > 1: subharmonic order; 0: unlabelled (no
                            ///< m/n within the peak's bins, or more than one)
    [[nodiscard]] std::string label() const; ///< "2 f_r", "1/2 f_r", "3/4 f_r", or "-"
};

/// Spectral reading of a PSD against the forcing frequency.
struct SpectralContent {
    std::vector<SpectralPeak> peaks; ///< local maxima above 1e-6 of the largest, by power
    double broadband_share = 0.0;    ///< power away from every m/n f_r (n <= max_order), [0, 1]
};

/// Finds the peaks of psd and measures its broadband share: power more than `width` bins away
/// from every frequency m/n f_r with 1 <= n <= max_order (f_r > 0, max_order >= 1).
SpectralContent spectral_content(const Psd& psd, double f_r, int max_order = 4, int width = 1,
                                 int max_peaks = 20);

} // namespace gapchain
