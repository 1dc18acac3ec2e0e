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

Psd welch_psd(const std::vector<double>& signal, const PsdOptions& o) {
    detail::require_range("sample_rate", o.sample_rate, 0.0, 1e12, detail::Bound::open_low);
    detail::require_range("segment_length", o.segment_length, 8, 1 << 24);
    detail::require_range("overlap", o.overlap, 0.0, 0.95);
    const int n = o.segment_length;
    if (signal.size() < static_cast<std::size_t>(n))
        throw std::invalid_argument("signal: needs at least segment_length = " + std::to_string(n) +
                                    " samples, got " + std::to_string(signal.size()));
    for (double x : signal)
        if (!std::isfinite(x)) throw std::invalid_argument("signal: every sample must be finite");
    const double mean =
        o.remove_mean ? std::accumulate(signal.begin(), signal.end(), 0.0) / signal.size() : 0.0;

    std::vector<double> w(n, 1.0);
    if (o.window == Window::hann)
        for (int i = 0; i < n; ++i)
            w[i] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * i / n);
    const double w2 = std::inner_product(w.begin(), w.end(), w.begin(), 0.0);

    const int hop = std::max(1, static_cast<int>(std::lround(n * (1.0 - o.overlap))));
    const fftw_plan plan = PlanCache::instance().plan(n);
    FftwBuffers buf(n);
    Psd psd;
    const int bins = n / 2 + 1;
    psd.density.assign(bins, 0.0);
    for (std::size_t start = 0; start + n <= signal.size(); start += hop) {
        for (int i = 0; i < n; ++i)
            buf.in[i] = (signal[start + i] - mean) * w[i];
        fftw_execute_dft_r2c(plan, buf.in, buf.out);
        for (int k = 0; k < bins; ++k)
            psd.density[k] += buf.out[k][0] * buf.out[k][0] + buf.out[k][1] * buf.out[k][1];
        ++psd.segments;
    }
    // One-sided density: |X_k|^2 / (fs sum w^2), doubled except at DC and (even n) Nyquist.
    psd.df = o.sample_rate / n;
    psd.frequency.resize(bins);
    for (int k = 0; k < bins; ++k) {
        const bool edge = k == 0 || (n % 2 == 0 && k == n / 2);
        psd.density[k] *= (edge ? 1.0 : 2.0) / (o.sample_rate * w2 * psd.segments);
        psd.frequency[k] = k * psd.df;
    }
    return psd;
}

std::string SpectralPeak::label() const {
    if (denominator == 0) return "-";
    if (denominator == 1) return std::to_string(numerator) + " f_r";
    return std::to_string(numerator) + "/" + std::to_string(denominator) + " f_r";
}

SpectralContent spectral_content(const Psd& psd, double f_r, int max_order, int width,
                                 int max_peaks) {
    detail::require_range("f_r", f_r, 0.0, 1e12, detail::Bound::open_low);
    detail::require_range("max_order", max_order, 1, 1000);
    detail::require_range("width", width, 0, 1000);
    const auto bins = static_cast<int>(psd.density.size());
    SpectralContent c;
    if (bins < 3) return c;
    // Mark every bin within `width` of some m/n f_r.
    std::vector<char> near(bins, 0);
    const double f_max = psd.frequency.back();
    for (int q = 1; q <= max_order; ++q)
        for (int m = 1; m * f_r / q <= f_max + width * psd.df; ++m) {
            const int centre = static_cast<int>(std::lround(m * f_r / q / psd.df));
            for (int k = std::max(1, centre - width); k <= std::min(bins - 1, centre + width); ++k)
                near[k] = 1;
        }
    double total = 0.0, away = 0.0, largest = 0.0;
    for (int k = 1; k < bins; ++k) {
        total += psd.density[k];
        if (!near[k]) away += psd.density[k];
        largest = std::max(largest, psd.density[k]);
    }
    c.broadband_share = total > 0.0 ? away / total : 0.0;
    for (int k = 1; k + 1 < bins; ++k) {
        const double d = psd.density[k];
        if (d <= psd.density[k - 1] || d < psd.density[k + 1] || d < 1e-6 * largest) continue;
        SpectralPeak p;
        p.frequency = psd.frequency[k];
        for (int j = std::max(1, k - width); j <= std::min(bins - 1, k + width); ++j)
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
