#include "gapchain/spectrum.hpp"

#include "detail/check.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <numeric>
#include <stdexcept>

namespace gapchain {

Window parse_window(std::string_view name) {
    if (name == "hann") return Window::hann;
    if (name == "rectangular") return Window::rectangular;
    throw std::invalid_argument("window: must be hann or rectangular, got \"" + std::string(name) +
                                "\"");
}

namespace {

/// One FFTW r2c plan per length, made once (FFTW's planner is not thread-safe, so creation is
/// serialised) and then executed with the new-array interface on per-call buffers.
class PlanCache {
public:
    static PlanCache& instance() {
        static PlanCache cache;
        return cache;
    }
    fftw_plan plan(int n) {
        std::lock_guard<std::mutex> lock(m_mutex);
        auto it = m_plans.find(n);
        if (it != m_plans.end()) return it->second;
        double* in = fftw_alloc_real(n);
        fftw_complex* out = fftw_alloc_complex(n / 2 + 1);
        fftw_plan p = fftw_plan_dft_r2c_1d(n, in, out, FFTW_ESTIMATE);
        fftw_free(in);
        fftw_free(out);
        m_plans.emplace(n, p);
        return p;
    }

private:
    PlanCache() = default;
    ~PlanCache() {
        for (auto& [n, p] : m_plans)
            fftw_destroy_plan(p);
    }
    std::mutex m_mutex;
    std::map<int, fftw_plan> m_plans;
};

struct FftwBuffers {
    explicit FftwBuffers(int n) : in(fftw_alloc_real(n)), out(fftw_alloc_complex(n / 2 + 1)) {}
    ~FftwBuffers() {
        fftw_free(in);
        fftw_free(out);
    }
    FftwBuffers(const FftwBuffers&) = delete;
    FftwBuffers& operator=(const FftwBuffers&) = delete;
    double* in;
    fftw_complex* out;
};

} // namespace

namespace {

/// Welch's segments of a signal, each windowed and transformed in turn: the one loop behind
/// the PSD and its band errors.
class WelchSegments {
public:
    WelchSegments(const std::vector<double>& signal, const PsdOptions& o)
        : m_signal(signal), m_n(validated_length(signal, o)), m_w(o.segment_length, 1.0),
          m_hop(std::max(1, static_cast<int>(std::lround(m_n * (1.0 - o.overlap))))),
          m_plan(PlanCache::instance().plan(m_n)), m_buffers(m_n), m_remove_mean(o.remove_mean) {
        if (o.window == Window::hann)
            for (int i = 0; i < m_n; ++i)
                m_w[i] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * i / m_n);
        const double w2 = std::inner_product(m_w.begin(), m_w.end(), m_w.begin(), 0.0);
        // One-sided density: |X_k|^2 / (fs sum w^2), doubled except at DC and (even n) Nyquist.
        m_scale.resize(m_n / 2 + 1);
        for (int k = 0; k <= m_n / 2; ++k) {
            const bool edge = k == 0 || (m_n % 2 == 0 && k == m_n / 2);
            m_scale[k] = (edge ? 1.0 : 2.0) / (o.sample_rate * w2);
        }
    }

    /// Calls segment(density) for each segment in turn (bins 0 .. n / 2, one segment's
    /// one-sided density); returns the number of segments.
    template <class Segment>
    int each(Segment&& segment) {
        std::vector<double> density(m_scale.size());
        int count = 0;
        for (std::size_t start = 0; start + m_n <= m_signal.size(); start += m_hop, ++count) {
            // Each segment's own mean (Welch's constant detrend): the record's mean left an
            // offset in segments of whole periods when the record was not whole periods (the
            // sampled end point), and the window leaked it into bin 1 as broadband power (a pure
            // sine read 1e-9, growing as 1 / samples^2 of the record).
            const auto first = m_signal.begin() + static_cast<std::ptrdiff_t>(start);
            const double mean =
                m_remove_mean ? std::accumulate(first, first + m_n, 0.0) / m_n : 0.0;
            for (int i = 0; i < m_n; ++i)
                m_buffers.in[i] = (m_signal[start + i] - mean) * m_w[i];
            fftw_execute_dft_r2c(m_plan, m_buffers.in, m_buffers.out);
            for (std::size_t k = 0; k < density.size(); ++k)
                density[k] = m_scale[k] * (m_buffers.out[k][0] * m_buffers.out[k][0] +
                                           m_buffers.out[k][1] * m_buffers.out[k][1]);
            segment(density);
        }
        return count;
    }

    [[nodiscard]] int hop() const { return m_hop; }

    /// Correlation of two segments k hops apart for white noise, (sum w_i w_(i + k hop))^2 /
    /// (sum w_i^2)^2: Welch (1967), eq. (13); 0 once they no longer overlap.
    [[nodiscard]] double correlation(int k) const {
        const long shift = static_cast<long>(k) * m_hop;
        if (shift >= m_n) return 0.0;
        double cross = 0.0, norm = 0.0;
        for (int i = 0; i < m_n; ++i) {
            norm += m_w[i] * m_w[i];
            if (i + shift < m_n) cross += m_w[i] * m_w[static_cast<std::size_t>(i + shift)];
        }
        return cross * cross / (norm * norm);
    }

private:
    // Before any member is sized from it: -5 threw length_error, 2^31 - 1 ran FFTW's planner
    // out of memory.
    static int validated_length(const std::vector<double>& signal, const PsdOptions& o) {
        detail::require_range("sample_rate", o.sample_rate, 0.0, 1e12, detail::Bound::open_low);
        detail::require_range("segment_length", o.segment_length, 8, 1 << 25);
        detail::require_range("overlap", o.overlap, 0.0, 0.95);
        if (signal.size() < static_cast<std::size_t>(o.segment_length))
            throw std::invalid_argument(
                "signal: needs at least segment_length = " + std::to_string(o.segment_length) +
                " samples, got " + std::to_string(signal.size()));
        for (double x : signal)
            if (!std::isfinite(x))
                throw std::invalid_argument("signal: every sample must be finite");
        return o.segment_length;
    }

    const std::vector<double>& m_signal;
    int m_n;
    std::vector<double> m_w;
    int m_hop;
    fftw_plan m_plan;
    FftwBuffers m_buffers;
    bool m_remove_mean;
    std::vector<double> m_scale;
};

} // namespace

Psd welch_psd(const std::vector<double>& signal, const PsdOptions& o) {
    WelchSegments segments(signal, o);
    Psd psd;
    psd.density.assign(static_cast<std::size_t>(o.segment_length / 2 + 1), 0.0);
    psd.segments = segments.each([&](const std::vector<double>& density) {
        for (std::size_t k = 0; k < density.size(); ++k)
            psd.density[k] += density[k];
    });
    psd.df = o.sample_rate / o.segment_length;
    psd.frequency.resize(psd.density.size());
    for (std::size_t k = 0; k < psd.density.size(); ++k) {
        psd.density[k] /= psd.segments;
        psd.frequency[k] = static_cast<double>(k) * psd.df;
    }
    return psd;
}

namespace {

/// The variance of the mean of `count` overlapping segments against that of independent ones,
/// Welch (1967) eq. (12): 1 + 2 sum_k (1 - k / count) rho(k). The record's length in whole
/// segments instead (independent segments only) overstated it 1.3-1.4 times at Hann's half
/// overlap.
double overlap_inflation(const WelchSegments& segments, int count) {
    double inflation = 1.0;
    for (int k = 1; k < count; ++k) {
        const double rho = segments.correlation(k);
        if (rho == 0.0) break;
        inflation += 2.0 * (1.0 - static_cast<double>(k) / count) * rho;
    }
    return inflation;
}

/// Throws std::invalid_argument naming f_r, max_order or width out of range (f_r = 0 would
/// mark fractions forever).
void require_fractions(double f_r, int max_order, int width) {
    detail::require_range("f_r", f_r, 0.0, 1e12, detail::Bound::open_low);
    detail::require_range("max_order", max_order, 1, 1000);
    detail::require_range("width", width, 0, 1000);
}

/// Marks every bin (of `bins`, df apart) within `width` bins of some m/n f_r, n <= max_order.
std::vector<char> near_fractions(int bins, double df, double f_r, int max_order, int width) {
    require_fractions(f_r, max_order, width);
    std::vector<char> near(static_cast<std::size_t>(bins), 0);
    const double f_max = (bins - 1) * df;
    for (int q = 1; q <= max_order; ++q)
        for (int m = 1; m * f_r / q <= f_max + width * df; ++m) {
            const int centre = static_cast<int>(std::lround(m * f_r / q / df));
            for (int k = std::max(1, centre - width); k <= std::min(bins - 1, centre + width); ++k)
                near[static_cast<std::size_t>(k)] = 1;
        }
    return near;
}

} // namespace

std::vector<double> band_power_errors(const std::vector<double>& signal, const PsdOptions& o,
                                      const std::vector<std::pair<int, int>>& bands) {
    WelchSegments segments(signal, o);
    for (const auto& [first, last] : bands)
        if (first < 0 || last < first || last > o.segment_length / 2)
            throw std::invalid_argument("bands: each must be 0 <= first <= last <= " +
                                        std::to_string(o.segment_length / 2) + ", got [" +
                                        std::to_string(first) + ", " + std::to_string(last) + "]");
    const double df = o.sample_rate / o.segment_length;
    // Welford's running mean and spread of each band's power over the segments.
    std::vector<double> mean(bands.size(), 0.0), squares(bands.size(), 0.0);
    int count = 0;
    segments.each([&](const std::vector<double>& density) {
        ++count;
        for (std::size_t b = 0; b < bands.size(); ++b) {
            double power = 0.0;
            for (int k = bands[b].first; k <= bands[b].second; ++k)
                power += density[static_cast<std::size_t>(k)] * df;
            const double delta = power - mean[b];
            mean[b] += delta / count;
            squares[b] += delta * (power - mean[b]);
        }
    });
    std::vector<double> errors(bands.size(), std::numeric_limits<double>::quiet_NaN());
    if (count < 2) return errors;
    const double inflation = overlap_inflation(segments, count);
    for (std::size_t b = 0; b < bands.size(); ++b)
        errors[b] = std::sqrt(squares[b] / (count - 1) * inflation / count);
    return errors;
}

double broadband_share_error(const std::vector<double>& signal, const PsdOptions& o, double f_r,
                             int max_order, int width) {
    WelchSegments segments(signal, o);
    const std::vector<char> near = near_fractions(
        o.segment_length / 2 + 1, o.sample_rate / o.segment_length, f_r, max_order, width);
    // Each segment's power away from the fractions (a) and in all (t), bins 1 and up.
    std::vector<double> away, total;
    segments.each([&](const std::vector<double>& density) {
        double a = 0.0, t = 0.0;
        for (std::size_t k = 1; k < density.size(); ++k) {
            t += density[k];
            if (!near[k]) a += density[k];
        }
        away.push_back(a);
        total.push_back(t);
    });
    const auto count = static_cast<int>(away.size());
    if (count < 2) return std::numeric_limits<double>::quiet_NaN();
    const double mean_total = std::accumulate(total.begin(), total.end(), 0.0) / count;
    if (mean_total <= 0.0) return std::numeric_limits<double>::quiet_NaN();
    const double share = std::accumulate(away.begin(), away.end(), 0.0) / count / mean_total;
    // The share is a ratio of means: to first order its error is the standard error of the
    // mean of (a - share t) / mean(t) over the segments.
    double mean = 0.0, squares = 0.0;
    for (int k = 0; k < count; ++k) {
        const double z = (away[k] - share * total[k]) / mean_total;
        const double delta = z - mean;
        mean += delta / (k + 1);
        squares += delta * (z - mean);
    }
    return std::sqrt(squares / (count - 1) * overlap_inflation(segments, count) / count);
}

double broadband_share_resolution_error(const std::vector<double>& signal, const PsdOptions& o,
                                        double share, double f_r, int max_order,
                                        int samples_per_period) {
    PsdOptions half = o;
    half.segment_length = whole_segment_within(o.segment_length / 2, samples_per_period, max_order);
    if (half.segment_length == 0) return std::numeric_limits<double>::quiet_NaN();
    return std::abs(share -
                    spectral_content(welch_psd(signal, half), f_r, max_order).broadband_share);
}

int whole_segment_within(int length, int samples_per_period, int max_order) {
    detail::require_range("samples_per_period", samples_per_period, 1, 1 << 24);
    detail::require_range("length", length, 0, 1 << 30);
    const int unit = whole_period_unit(max_order) * samples_per_period;
    int segment = length / unit * unit;
    if (segment < 16) segment = length / samples_per_period * samples_per_period;
    return segment < 16 ? 0 : segment;
}

int whole_period_unit(int max_order) {
    detail::require_range("max_order", max_order, 1, 1 << 20);
    int unit = 1;
    for (int n = 2; n <= max_order; ++n) {
        const int next = std::lcm(unit, n);
        if (next > 128) break;
        unit = next;
    }
    return unit;
}

int whole_period_segment(long samples, int samples_per_period, int max_order, int min_segments) {
    detail::require_range("samples_per_period", samples_per_period, 1, 1 << 24);
    detail::require_range("min_segments", min_segments, 1, 1 << 20);
    const long unit = whole_period_unit(max_order);
    const long periods = (samples - 1) / samples_per_period; // whole periods recorded
    // k segments at half overlap span (k + 1) / 2 segments.
    const long fit = 2 * periods / (min_segments + 1);
    long chosen = std::max(unit, 128 / unit * unit);
    while (chosen > unit && chosen > fit)
        chosen -= unit;
    if (chosen > periods) chosen = periods;
    const long segment = std::max(16L, chosen * samples_per_period);
    return static_cast<int>(std::min(segment, std::max(16L, samples)));
}

PsdOptions doubled_rate_options(const PsdOptions& o) {
    PsdOptions fine = o;
    fine.sample_rate *= 2.0;
    fine.segment_length *= 2;
    // Twice the asked hop exactly (an odd segment's hop is rounded): segments start at the
    // same times.
    const double hop = std::max(1.0, std::round(o.segment_length * (1.0 - o.overlap)));
    fine.overlap = 1.0 - hop / o.segment_length;
    return fine;
}

double power_share_above(const Psd& psd, int bin) {
    double above = 0.0, total = 0.0;
    for (std::size_t k = 1; k < psd.density.size(); ++k) {
        total += psd.density[k];
        if (static_cast<int>(k) > bin) above += psd.density[k];
    }
    return total > 0.0 ? above / total : 0.0;
}

double aliased_share(const std::vector<double>& fine, const PsdOptions& asked) {
    return power_share_above(welch_psd(fine, doubled_rate_options(asked)),
                             asked.segment_length / 2);
}

std::string SpectralPeak::label() const {
    if (denominator == 0) return "-";
    if (denominator == 1) return std::to_string(numerator) + " f_r";
    return std::to_string(numerator) + "/" + std::to_string(denominator) + " f_r";
}

SpectralContent spectral_content(const Psd& psd, double f_r, int max_order, int width,
                                 int max_peaks) {
    require_fractions(f_r, max_order, width);
    const auto bins = static_cast<int>(psd.density.size());
    SpectralContent c;
    if (bins < 3) return c;
    const std::vector<char> near = near_fractions(bins, psd.df, f_r, max_order, width);
    double total = 0.0, away = 0.0, largest = 0.0;
    for (int k = 1; k < bins; ++k) {
        total += psd.density[k];
        if (!near[k]) away += psd.density[k];
        largest = std::max(largest, psd.density[k]);
    }
    c.broadband_share = total > 0.0 ? away / total : 0.0;
    c.fraction_bin_share =
        static_cast<double>(std::count(near.begin() + 1, near.end(), char{1})) / (bins - 1);
    // The last bin (the Nyquist frequency) has no right neighbour: at 2 samples per period the
    // forcing's own line sits there, and was not listed.
    for (int k = 1; k < bins; ++k) {
        const double d = psd.density[k];
        if (d <= psd.density[k - 1] || (k + 1 < bins && d < psd.density[k + 1]) ||
            d < 1e-6 * largest)
            continue;
        SpectralPeak p;
        p.frequency = psd.frequency[k];
        p.frequency_error = 0.5 * psd.df;
        p.first_bin = std::max(1, k - width);
        p.last_bin = std::min(bins - 1, k + width);
        for (int j = p.first_bin; j <= p.last_bin; ++j)
            p.power += psd.density[j] * psd.df;
        // The one fraction m/n (n <= max_order) of f_r whose nearest bin is the peak's; none
        // where two are (a segment of few forcing periods): an aliased 0.375 f_r, a bin from
        // 1/2 f_r, was labelled "1/2 f_r". A line's largest bin is its nearest one.
        const double within = 0.5 * psd.df * (1.0 + 1e-9);
        int labels = 0;
        for (int q = 1; q <= max_order; ++q)
            for (int m =
                     std::max(1, static_cast<int>(std::floor((p.frequency - within) * q / f_r)));
                 m * f_r / q <= p.frequency + within; ++m) {
                if (std::gcd(m, q) != 1 || std::abs(m * f_r / q - p.frequency) > within) continue;
                ++labels;
                p.numerator = m;
                p.denominator = q;
            }
        if (labels != 1) p.numerator = p.denominator = 0;
        c.peaks.push_back(p);
    }
    std::sort(c.peaks.begin(), c.peaks.end(),
              [](const SpectralPeak& a, const SpectralPeak& b) { return a.power > b.power; });
    if (static_cast<int>(c.peaks.size()) > max_peaks) c.peaks.resize(max_peaks);
    return c;
}

} // namespace gapchain
