#include "gapchain/ground_motion.hpp"

#include "detail/check.hpp"
#include "detail/random.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_spline.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace gapchain {

using detail::Bound;
using detail::require_range;

void validate(const Accelerogram& record, const char* key) {
    const std::string k = key;
    if (record.time.size() != record.acceleration.size())
        throw std::invalid_argument(k + ": time and acceleration must have equal lengths, got " +
                                    std::to_string(record.time.size()) + " and " +
                                    std::to_string(record.acceleration.size()));
    if (record.time.size() < 2)
        throw std::invalid_argument(k + ": needs at least 2 samples, got " +
                                    std::to_string(record.time.size()));
    for (std::size_t i = 0; i < record.time.size(); ++i) {
        if (!std::isfinite(record.time[i]) || !std::isfinite(record.acceleration[i]))
            throw std::invalid_argument(k + ": sample " + std::to_string(i + 1) +
                                        " is not a finite number");
        if (i > 0 && !(record.time[i] > record.time[i - 1]))
            throw std::invalid_argument(k + ": times must increase strictly, sample " +
                                        std::to_string(i + 1) +
                                        " has t = " + detail::format_number(record.time[i]) +
                                        " after " + detail::format_number(record.time[i - 1]));
    }
    // The run starts at t = 0: samples before it were dropped unseen (a record from -3 s to 0 s
    // ran as silence, F_m = 0).
    if (record.time.front() < 0.0)
        throw std::invalid_argument(k + ": times must be >= 0 (the run starts at t = 0), got t = " +
                                    detail::format_number(record.time.front()) +
                                    " at sample 1; shift the record's times");
    if (peak_ground_acceleration(record) == 0.0)
        throw std::invalid_argument(k + ": the record is zero everywhere (PGA must be > 0)");
}

double peak_ground_acceleration(const Accelerogram& record) {
    double peak = 0.0;
    for (double a : record.acceleration)
        peak = std::max(peak, std::abs(a));
    return peak;
}

void validate(const KanaiTajimi& p) {
    require_range("excitation.ground_frequency", p.ground_frequency, 0.01, 100.0);
    require_range("excitation.ground_damping", p.ground_damping, 0.01, 5.0);
    require_range("excitation.duration", p.duration, 0.1, 1e5);
    const double finest = std::min({1.0, p.duration / 16.0, 1.0 / (8.0 * p.ground_frequency)});
    require_range("excitation.sample_interval", p.sample_interval, 0.0, finest, Bound::open_low);
    // The record is held in memory, 16 bytes per sample.
    if (p.duration / p.sample_interval > 1e8)
        throw std::invalid_argument(
            "excitation.sample_interval: excitation.duration / sample_interval = " +
            detail::format_number(p.duration / p.sample_interval) +
            " samples, above the limit of 1e8 (1.6 GB); take a longer sample_interval");
    require_range("excitation.rise", p.rise, 0.0, 1e5);
    require_range("excitation.hold", p.hold, 0.0, 1e5);
    require_range("excitation.decay", p.decay, 0.0, 1e3);
}

double envelope(const KanaiTajimi& p, double t) {
    if (t < 0.0) return 0.0;
    if (t < p.rise) return (t / p.rise) * (t / p.rise);
    if (t <= p.rise + p.hold) return 1.0;
    return std::exp(-p.decay * (t - p.rise - p.hold));
}

double kanai_tajimi_shape(const KanaiTajimi& p, double f) {
    const double wg = 2.0 * std::numbers::pi * p.ground_frequency;
    const double w = 2.0 * std::numbers::pi * f;
    const double c = 4.0 * p.ground_damping * p.ground_damping * wg * wg * w * w;
    const double d = wg * wg - w * w;
    return (wg * wg * wg * wg + c) / (d * d + c);
}

Accelerogram kanai_tajimi_accelerogram(const KanaiTajimi& p, double pga) {
    validate(p);
    require_range("excitation.a0", pga, 0.0, 1e6, Bound::open_low);
    const double wg = 2.0 * std::numbers::pi * p.ground_frequency;
    const double zeta = p.ground_damping;
    const double dt = p.sample_interval;
    const auto samples = static_cast<long>(std::floor(p.duration / dt + 1e-9)) + 1;
    const auto warm_up = static_cast<long>(std::ceil(10.0 / (zeta * wg) / dt));

    // The white noise is held constant over each sample interval (variance 1/dt, so that its
    // level does not depend on dt); the filter is a linear ODE integrated by RK4 substeps,
    // whose error at w_g h <= 0.2 is far below the noise's own sampling.
    constexpr int substeps = 4;
    const double h = dt / substeps;
    double x = 0.0, v = 0.0;
    auto filter_step = [&](double w) {
        auto acc = [&](double xx, double vv) { return -w - 2.0 * zeta * wg * vv - wg * wg * xx; };
        const double k1x = v, k1v = acc(x, v);
        const double k2x = v + 0.5 * h * k1v, k2v = acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
        const double k3x = v + 0.5 * h * k2v, k3v = acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
        const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    };
    Accelerogram record;
    record.time.reserve(samples);
    record.acceleration.reserve(samples);
    const double noise_scale = 1.0 / std::sqrt(dt);
    constexpr std::uint64_t noise_stream = 11;
    for (long k = -warm_up; k < samples; ++k) {
        if (k >= 0) {
            const double t = static_cast<double>(k) * dt;
            record.time.push_back(t);
            record.acceleration.push_back(envelope(p, t) * (2.0 * zeta * wg * v + wg * wg * x));
        }
        const double w =
            noise_scale *
            detail::standard_normal(p.seed, noise_stream, static_cast<std::uint64_t>(k + warm_up));
        for (int s = 0; s < substeps; ++s)
            filter_step(w);
    }
    const double peak = peak_ground_acceleration(record);
    if (!(peak > 0.0))
        throw std::invalid_argument("excitation: the synthetic record is zero everywhere; "
                                    "lengthen excitation.duration or excitation.hold");
    for (double& a : record.acceleration)
        a *= pga / peak;
    return record;
}

struct GroundMotion::Interpolant {
    gsl_spline* spline = nullptr;
    double front = 0.0;
    double back = 0.0;
    Interpolant(const std::vector<double>& t, const std::vector<double>& a)
        : front(t.front()), back(t.back()) {
        // A natural cubic spline: C2, so the integrators see a smooth forcing between samples,
        // and fourth-order accurate in the sample interval away from the two ends.
        spline = gsl_spline_alloc(t.size() > 2 ? gsl_interp_cspline : gsl_interp_linear, t.size());
        if (!spline) throw std::bad_alloc();
        gsl_spline_init(spline, t.data(), a.data(), t.size());
    }
    ~Interpolant() { gsl_spline_free(spline); }
    Interpolant(const Interpolant&) = delete;
    Interpolant& operator=(const Interpolant&) = delete;
};

GroundMotion GroundMotion::harmonic(double f_r, double amplitude) {
    require_range("excitation.f_r", f_r, 0.0, 1e4, Bound::open_low);
    require_range("excitation.amplitude", amplitude, 0.0, 1e6);
    GroundMotion g;
    g.m_f_r = f_r;
    g.m_amplitude = amplitude;
    g.m_resolved_frequency = f_r;
    return g;
}

GroundMotion GroundMotion::record(std::vector<double> time, std::vector<double> acceleration) {
    const Accelerogram reduced{std::move(time), std::move(acceleration)};
    validate(reduced, "excitation.record");
    double finest = reduced.time.back() - reduced.time.front();
    for (std::size_t i = 1; i < reduced.time.size(); ++i)
        finest = std::min(finest, reduced.time[i] - reduced.time[i - 1]);
    GroundMotion g;
    // The spline's evaluation with a null accelerator is a read-only binary search, so one
    // interpolant serves every thread.
    g.m_record = std::make_shared<const Interpolant>(reduced.time, reduced.acceleration);
    g.m_resolved_frequency = 0.25 / finest;
    return g;
}

GroundMotion GroundMotion::from_accelerogram(const Accelerogram& accelerogram, double f0,
                                             double a0) {
    validate(accelerogram);
    require_range("natural frequency f0", f0, 0.0, 1e9, Bound::open_low);
    require_range("excitation.a0", a0, 0.0, 1e6, Bound::open_low);
    std::vector<double> t(accelerogram.time.size()), a(accelerogram.time.size());
    for (std::size_t i = 0; i < t.size(); ++i) {
        t[i] = accelerogram.time[i] * f0;
        a[i] = accelerogram.acceleration[i] / a0;
    }
    return record(std::move(t), std::move(a));
}

double GroundMotion::end_time() const {
    return m_record ? m_record->back : std::numeric_limits<double>::infinity();
}

double GroundMotion::acceleration(double t) const {
    if (!m_record) return m_amplitude * std::cos(2.0 * std::numbers::pi * m_f_r * t);
    if (t < m_record->front || t > m_record->back) return 0.0;
    return gsl_spline_eval(m_record->spline, t, nullptr);
}

double GroundMotion::acceleration_rate(double t) const {
    if (!m_record) {
        const double w = 2.0 * std::numbers::pi * m_f_r;
        return -m_amplitude * w * std::sin(w * t);
    }
    if (t < m_record->front || t > m_record->back) return 0.0;
    return gsl_spline_eval_deriv(m_record->spline, t, nullptr);
}

} // namespace gapchain
