#include "gapchain/lyapunov.hpp"

#include "detail/check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>

namespace gapchain {

LyapunovAccumulator::LyapunovAccumulator(int dimension, int count)
    : m_dim(dimension), m_count(count), m_basis(static_cast<std::size_t>(dimension) * count, 0.0) {
    detail::require_range("dimension", dimension, 1, 100'000'000);
    detail::require_range("count", count, 1, dimension);
    // A generic start (not aligned with any coordinate axis, where a symmetric system could
    // keep it on an invariant subspace): a fixed deterministic fill, then orthonormalised.
    for (int k = 0; k < count; ++k)
        for (int i = 0; i < dimension; ++i)
            m_basis[static_cast<std::size_t>(k) * dimension + i] =
                (i == k ? 1.0 : 0.0) + 0.1 * std::sin(1.0 + 7.3 * i + 3.1 * k * k + 0.7 * i * k);
    orthonormalize(0.0, false);
}

bool LyapunovAccumulator::orthonormalize(double t, bool accumulate) {
    std::vector<double> logs(m_count);
    for (int k = 0; k < m_count; ++k) {
        double* qk = &m_basis[static_cast<std::size_t>(k) * m_dim];
        for (int j = 0; j < k; ++j) {
            const double* qj = &m_basis[static_cast<std::size_t>(j) * m_dim];
            const double r = std::inner_product(qj, qj + m_dim, qk, 0.0);
            for (int i = 0; i < m_dim; ++i)
                qk[i] -= r * qj[i];
        }
        const double norm = std::sqrt(std::inner_product(qk, qk + m_dim, qk, 0.0));
        if (!(norm > 0.0) || !std::isfinite(norm)) return false;
        for (int i = 0; i < m_dim; ++i)
            qk[i] /= norm;
        logs[k] = std::log(norm);
    }
    if (accumulate && m_started) {
        const std::size_t base = m_sums.size();
        m_sums.resize(base + m_count);
        for (int k = 0; k < m_count; ++k)
            m_sums[base + k] =
                (base >= static_cast<std::size_t>(m_count) ? m_sums[base - m_count + k] : 0.0) +
                logs[k];
        m_times.push_back(t);
    }
    return true;
}

void LyapunovAccumulator::start(double t) {
    m_t_start = t;
    m_started = true;
    m_times.clear();
    m_sums.clear();
}

namespace {

/// The error of the mean of a window's block rates, and their drift (0 where they show none).
struct BlockError {
    double error = 0.0;
    double drift = 0.0;
};

/// The standard error of the mean of the block rates (consecutive blocks of the averaging
/// window), widened by the drift where the rates trend. Blocks are independent draws only once
/// the run is on its attractor: near a period doubling (the largest multiplier -0.982 at Fig
/// 13's f_r = 4.1215) 200 transient periods leave the trajectory 3 % of its start away, the
/// rates fall block after block, and the standard error (4.1e-6) missed the bias (3.5e-5)
/// 8.5 times. A slope of the least-squares line through the rates more than 5 of its own
/// standard errors from 0 is a drift (t with 8 degrees of freedom: 1e-3 of stationary windows
/// an exponent; at 3, 1.7 % of them, one run in 6-16 of all 2 Nm exponents, took a bar 8 times
/// its standard error, a second reader found); the line's change over blocks x slope, more
/// than the (blocks - 1) / 2 x slope by which the mean lies from the window's end, since the
/// limit lies beyond it, is then the error (4.2e-5 there, t = 46).
BlockError block_error(const std::vector<double>& rates) {
    const auto n = static_cast<double>(rates.size());
    const double mean = std::accumulate(rates.begin(), rates.end(), 0.0) / n;
    double var = 0.0, spread = 0.0, cross = 0.0;
    for (std::size_t b = 0; b < rates.size(); ++b) {
        const double x = static_cast<double>(b) - 0.5 * (n - 1);
        var += (rates[b] - mean) * (rates[b] - mean);
        spread += x * x;
        cross += x * (rates[b] - mean);
    }
    BlockError e;
    e.error = std::sqrt(var / (n - 1) / n);
    const double slope = cross / spread;
    const double residuals = std::max(0.0, var - slope * cross); // what the line leaves
    const double slope_error = std::sqrt(residuals / (n - 2) / spread);
    const double drift = std::abs(slope) * n;
    // Rates equal but for round-off (a periodic orbit's blocks of whole periods) have a slope
    // of round-off that the residuals can call significant.
    const double round_off =
        64.0 * std::numeric_limits<double>::epsilon() *
        std::abs(*std::max_element(rates.begin(), rates.end(),
                                   [](double a, double b) { return std::abs(a) < std::abs(b); }));
    if (std::abs(slope) > 5.0 * slope_error && drift > std::max(e.error, round_off))
        e.drift = drift;
    return e;
}

} // namespace

LyapunovResult LyapunovAccumulator::result() const {
    LyapunovResult r;
    r.exponents.assign(m_count, 0.0);
    r.errors.assign(m_count, 0.0);
    const std::size_t samples = m_times.size();
    if (samples == 0) return r;
    auto sum_at = [&](std::size_t s, int k) { return m_sums[s * m_count + k]; };
    r.averaging_time = m_times.back() - m_t_start;
    for (int k = 0; k < m_count; ++k)
        r.exponents[k] = sum_at(samples - 1, k) / r.averaging_time;
    r.sum = std::accumulate(r.exponents.begin(), r.exponents.end(), 0.0);
    constexpr int blocks = 10;
    if (samples >= 2 * blocks) {
        std::vector<BlockError> block_errors;
        for (int k = 0; k < m_count; ++k) {
            std::vector<double> rates;
            double prev_t = m_t_start, prev_sum = 0.0;
            for (int b = 1; b <= blocks; ++b) {
                const std::size_t s = b * samples / blocks - 1;
                rates.push_back((sum_at(s, k) - prev_sum) / (m_times[s] - prev_t));
                prev_t = m_times[s];
                prev_sum = sum_at(s, k);
            }
            block_errors.push_back(block_error(rates));
            r.errors[k] = block_errors.back().error;
        }
        // A drift is a transient only where the run is attracted (the largest exponent 3 errors
        // below 0: an orbit or a rest state, whose block rates are deterministic). On a chaotic
        // row the rates of an exponent wander for hundreds of periods: Fig 13's lambda_5 at
        // f_r = 3.3 rose from -2.55 to -2.17 over one window (t = 6.8) where windows of 400-1300
        // periods scatter by 0.03; its standard error, 0.049, stands there.
        if (r.exponents[0] < -3.0 * r.errors[0])
            for (int k = 0; k < m_count; ++k)
                if (block_errors[k].drift > 0.0) {
                    r.errors[k] = block_errors[k].drift;
                    r.drifting = true;
                }
    } else {
        r.errors.assign(m_count, std::numeric_limits<double>::infinity());
    }
    const std::size_t stride = std::max<std::size_t>(1, samples / 500);
    for (std::size_t s = stride - 1; s < samples; s += stride) {
        LyapunovSample h;
        h.t = m_times[s];
        for (int k = 0; k < m_count; ++k)
            h.exponents.push_back(sum_at(s, k) / (h.t - m_t_start));
        r.history.push_back(std::move(h));
    }
    return r;
}

namespace {

/// Throws std::invalid_argument naming the first option of lyapunov_spectrum() outside its
/// range for a system of dimension n and an initial state of y_size entries.
void validate_spectrum_options(const LyapunovOptions& o, int n, std::size_t y_size) {
    detail::require_length("initial state", y_size, static_cast<std::size_t>(n));
    detail::require_range("count", o.count, 0, n);
    detail::require_range("step", o.step, 0.0, 1e6, detail::Bound::open_low);
    detail::require_range("transient", o.transient, 0.0, 1e12);
    detail::require_range("duration", o.duration, 0.0, 1e12, detail::Bound::open_low);
    detail::require_range("steps_per_orthonormalization", o.steps_per_orthonormalization, 1,
                          1'000'000);
}

/// RK4 on the augmented state z = (y, Q) of a tangent system: z' = (f(y), J(y) Q). Owns its
/// stages, so that a step allocates nothing.
class AugmentedRk4 {
public:
    /// count: columns of Q.
    AugmentedRk4(const TangentSystem& sys, int count)
        : m_sys(sys), m_n(sys.dimension()), m_count(count),
          m_size(static_cast<std::size_t>(m_n) * (1 + count)), m_z(m_size), m_k1(m_size),
          m_k2(m_size), m_k3(m_size), m_k4(m_size), m_tmp(m_size),
          m_jac(static_cast<std::size_t>(m_n) * m_n) {}
    /// One step of length h from t: y (n entries) and q (count columns of n) in place.
    void step(double t, double h, std::vector<double>& y, std::vector<double>& q);

private:
    void derivative(double t, const std::vector<double>& in, std::vector<double>& out);

    const TangentSystem& m_sys;
    int m_n;
    int m_count;
    std::size_t m_size;
    std::vector<double> m_z, m_k1, m_k2, m_k3, m_k4, m_tmp, m_jac;
};

void AugmentedRk4::derivative(double t, const std::vector<double>& in, std::vector<double>& out) {
    const int n = m_n;
    m_sys.rhs(t, in.data(), out.data());
    m_sys.jacobian(t, in.data(), m_jac.data());
    for (int c = 0; c < m_count; ++c) {
        const double* col = &in[static_cast<std::size_t>(n) * (1 + c)];
        double* dcol = &out[static_cast<std::size_t>(n) * (1 + c)];
        for (int i = 0; i < n; ++i) {
            double s = 0.0;
            for (int j = 0; j < n; ++j)
                s += m_jac[static_cast<std::size_t>(i) * n + j] * col[j];
            dcol[i] = s;
        }
    }
}

void AugmentedRk4::step(double t, double h, std::vector<double>& y, std::vector<double>& q) {
    const std::size_t m = m_size;
    std::copy(y.begin(), y.end(), m_z.begin());
    std::copy(q.begin(), q.end(), m_z.begin() + m_n);
    derivative(t, m_z, m_k1);
    for (std::size_t i = 0; i < m; ++i)
        m_tmp[i] = m_z[i] + 0.5 * h * m_k1[i];
    derivative(t + 0.5 * h, m_tmp, m_k2);
    for (std::size_t i = 0; i < m; ++i)
        m_tmp[i] = m_z[i] + 0.5 * h * m_k2[i];
    derivative(t + 0.5 * h, m_tmp, m_k3);
    for (std::size_t i = 0; i < m; ++i)
        m_tmp[i] = m_z[i] + h * m_k3[i];
    derivative(t + h, m_tmp, m_k4);
    for (std::size_t i = 0; i < m; ++i)
        m_z[i] += h / 6.0 * (m_k1[i] + 2 * (m_k2[i] + m_k3[i]) + m_k4[i]);
    std::copy(m_z.begin(), m_z.begin() + m_n, y.begin());
    std::copy(m_z.begin() + m_n, m_z.end(), q.begin());
}

} // namespace

LyapunovResult lyapunov_spectrum(const TangentSystem& sys, std::vector<double> y,
                                 const LyapunovOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    const int n = sys.dimension();
    validate_spectrum_options(o, n, y.size());
    const int count = o.count == 0 ? n : o.count;
    LyapunovAccumulator acc(n, count);
    std::vector<double>& q = acc.basis();
    AugmentedRk4 rk4(sys, count);
    const long transient_steps = std::lround(o.transient / o.step);
    const long total = transient_steps + std::lround(o.duration / o.step);
    double t = 0.0;
    if (transient_steps == 0) acc.start(0.0);
    for (long s = 0; s < total; ++s) {
        rk4.step(t, o.step, y, q);
        t = (s + 1) * o.step;
        if (s + 1 == transient_steps) acc.start(t);
        if ((s + 1) % o.steps_per_orthonormalization == 0 || s + 1 == total) {
            if (!acc.orthonormalize(t, s + 1 > transient_steps)) {
                LyapunovResult failure;
                failure.status = RunStatus::non_finite;
                failure.message =
                    "the tangent basis became non-finite at t = " + detail::format_number(t);
                return failure;
            }
        }
    }
    LyapunovResult r = acc.result();
    r.step = o.step;
    r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

namespace {

/// The largest log-ratio of two tangent vectors' growth between re-orthonormalisations:
/// beyond about 36 (1 / 2.2e-16) the smaller one is round-off in the larger one's direction.
/// Once a period was too seldom where damping is strong: at eps = 5 (decay rates up to
/// 2 pi (5 + sqrt 24) = 62 per unit time, f_r = 1) lambda_6..10 came out -37 +- 0.2, a tangent
/// vector's log-floor per period, and the sum -190 against the trace's -314.
constexpr double max_qr_log_ratio = 20.0;

/// Reduced time between re-orthonormalisations: the exponents of the row's contact-free modes
/// lie in [-d_max, 0] (diagonal damping d_i = c_i / m_i; an overdamped mode's fast root is at
/// most d), chaos adds a few units: their spread grows by at most max_qr_log_ratio over it.
double qr_interval(const Dynamics& dyn) {
    const auto& d = dyn.chain().damping;
    const double spread = *std::max_element(d.begin(), d.end()) + 2.0 * std::numbers::pi;
    return max_qr_log_ratio / spread;
}

} // namespace

TangentObserver::TangentObserver(const Dynamics& dyn, int count, long start_period)
    : m_flow(dyn, count), m_accumulator(dyn.dimension(), count), m_start_period(start_period),
      m_qr_interval(qr_interval(dyn)), m_next_qr(m_qr_interval) {
    copy_basis_to_flow();
}

void TangentObserver::copy_basis_to_flow() {
    const std::vector<double>& q = m_accumulator.basis();
    const auto dim = static_cast<std::size_t>(m_accumulator.dimension());
    for (int c = 0; c < m_accumulator.count(); ++c)
        std::copy_n(q.begin() + static_cast<std::ptrdiff_t>(c * dim), dim, m_flow.column(c));
}

void TangentObserver::orthonormalize(double t, bool accumulate) {
    std::vector<double>& q = m_accumulator.basis();
    const auto dim = static_cast<std::size_t>(m_accumulator.dimension());
    for (int c = 0; c < m_accumulator.count(); ++c)
        std::copy_n(m_flow.column(c), dim, q.begin() + static_cast<std::ptrdiff_t>(c * dim));
    if (!m_accumulator.orthonormalize(t, accumulate)) m_healthy = false;
    copy_basis_to_flow();
    m_next_qr = t + m_qr_interval;
}

void TangentObserver::on_step(const StepView& step) {
    if (!m_healthy) return;
    m_flow.on_step(step);
    // Within a period where damping is strong; the period's end does its own below.
    // A step of period p lies between on_period(p) and on_period(p + 1); the averages start at
    // on_period(m_start_period).
    if (step.t1 >= m_next_qr) orthonormalize(step.t1, step.period >= m_start_period);
}

bool TangentObserver::on_period(long n, double t, const double*) {
    if (!m_healthy) return false;
    // The flow carried the basis over the period; QR it and carry on from the new basis.
    orthonormalize(t, n > m_start_period);
    if (n == m_start_period) m_accumulator.start(t);
    if (n > m_start_period) ++m_periods_averaged;
    return false;
}

LyapunovResult TangentObserver::result() const {
    LyapunovResult r = m_accumulator.result();
    // The accumulator's rule counts samples; with several a period (strong damping) 10 periods
    // gave "+- 1e-16" where they give no error estimate.
    if (m_periods_averaged < 20)
        r.errors.assign(r.errors.size(), std::numeric_limits<double>::infinity());
    return r;
}

Scheme tangent_run_scheme(const Dynamics& dyn, Scheme requested) {
    // The tangent flow is exact along the trajectory it is given, and rk4's at the default
    // tolerance is not close enough through stiff contacts: Fig 13's row at fc = 2000 gave
    // lambda_1 = -1.957 +- 0.0011 against exact's -1.9755, at fc = 3e6 +0.240 on a stable
    // orbit (Newton: -2.88). The exact propagator is as fast or faster on short rows (0.18 s
    // against 0.21 s at fc = 2000); on longer ones its set-up per contact state costs more than
    // it saves (Table 4's 46-body chaotic row: minutes against seconds).
    if (requested == Scheme::automatic && dyn.bodies() <= 10 && exact_can_run(dyn))
        return Scheme::exact;
    return requested;
}

RunOptions tangent_run_options(const Dynamics& dyn, RunOptions requested) {
    requested.scheme = tangent_run_scheme(dyn, requested.scheme);
    if (requested.scheme != Scheme::exact && !requested.step)
        requested.tolerance = std::min(requested.tolerance, max_tangent_run_tolerance);
    return requested;
}

LyapunovResult chain_lyapunov(const Dynamics& dyn, const RunOptions& options, int count,
                              const std::vector<double>& initial,
                              const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    validate(options);
    require_harmonic(dyn, "lyapunov");
    detail::require_range("count", count, 1, dyn.dimension());
    const RunOptions run = tangent_run_options(dyn, options);
    PlannedRun planned(dyn, run, initial);
    // Each of the count tangent vectors costs about a step of the row: the run's own
    // affordability check (body-steps) sees only the row.
    const double work = run_work(dyn, planned.plan(), static_cast<double>(options.periods), count);
    detail::require_work(work, options.max_work, "this run takes about",
                         "the row and its " + std::to_string(count) + " tangent vectors",
                         "fewer exponents (count), a shorter run (run.periods) or a larger "
                         "run.max_work");
    TangentObserver tangent(dyn, count, planned.transient_periods());
    Observer* observers[] = {&tangent};
    const RunOutcome outcome = planned.run(observers, progress);
    LyapunovResult r = tangent.result();
    r.scheme = planned.plan().scheme;
    r.step = planned.plan().step;
    if (count == dyn.dimension()) {
        const auto& d = dyn.chain().damping;
        r.expected_sum = -std::accumulate(d.begin(), d.end(), 0.0);
    }
    r.status = outcome.status;
    r.message = outcome.message;
    if (!tangent.healthy() && r.status == RunStatus::completed) {
        r.status = RunStatus::non_finite;
        r.message = "the tangent basis became non-finite";
    }
    r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

namespace {

/// Throws std::invalid_argument on a time step, option or sample
/// largest_exponent_from_series() cannot take.
void validate_series(const std::vector<double>& x, double dt, const TimeSeriesOptions& o) {
    detail::require_range("dt", dt, 0.0, 1e12, detail::Bound::open_low);
    detail::require_range("embedding", o.embedding, 1, 100);
    detail::require_range("delay", o.delay, 1, 1'000'000);
    detail::require_range("min_separation", o.min_separation, 0, 100'000'000);
    detail::require_range("horizon", o.horizon, 0, 100'000'000);
    detail::require_range("fit_from", o.fit_from, 0.0, 0.99);
    detail::require_range("fit_to", o.fit_to, o.fit_from + 1e-9, 1.0);
    detail::require_range("max_points", o.max_points, 100, 1'000'000);
    for (double v : x)
        if (!std::isfinite(v)) throw std::invalid_argument("series: every sample must be finite");
}

/// The mean period of x in samples, from its mean-crossings (n / 10 without two of them).
long mean_period_samples(const std::vector<double>& x) {
    const long n = static_cast<long>(x.size());
    const double mean = std::accumulate(x.begin(), x.end(), 0.0) / std::max(1L, n);
    long crossings = 0;
    for (long i = 1; i < n; ++i)
        crossings += (x[i - 1] < mean) != (x[i] < mean);
    return crossings > 1 ? 2 * n / crossings : n / 10;
}

/// The delay embedding of a series: point a is (x[a], x[a + delay], ..., x[a + (m - 1) delay]).
class DelayEmbedding {
public:
    DelayEmbedding(const std::vector<double>& x, int embedding, int delay)
        : m_x(x), m_embedding(embedding), m_delay(delay) {}
    /// Squared distance between points a and b.
    [[nodiscard]] double distance2(long a, long b) const {
        double d = 0.0;
        for (int k = 0; k < m_embedding; ++k) {
            const double e = m_x[a + k * m_delay] - m_x[b + k * m_delay];
            d += e * e;
        }
        return d;
    }

private:
    const std::vector<double>& m_x;
    int m_embedding;
    int m_delay;
};

/// The reference points of the neighbour search: 0, stride, ... below points; neighbours lie
/// more than separation samples apart.
struct ReferencePoints {
    long points;
    long stride;
    long separation;
};

/// Nearest distinct neighbour of point a outside its Theiler window, or -1.
long nearest_neighbour(const DelayEmbedding& e, const ReferencePoints& ref, long a) {
    long best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (long b = 0; b < ref.points; b += ref.stride) {
        if (std::abs(a - b) <= ref.separation) continue;
        const double d = e.distance2(a, b);
        if (d > 0.0 && d < best_d) {
            best_d = d;
            best = b;
        }
    }
    return best;
}

/// Mean log distance of the neighbour pairs after i = 0 .. horizon samples (0 where no pair
/// stays distinct).
std::vector<double> mean_log_divergence(const DelayEmbedding& e, const ReferencePoints& ref,
                                        long horizon) {
    std::vector<double> sum(horizon + 1, 0.0);
    std::vector<long> count(horizon + 1, 0);
    for (long a = 0; a < ref.points; a += ref.stride) {
        const long best = nearest_neighbour(e, ref, a);
        if (best < 0) continue;
        for (long i = 0; i <= horizon; ++i) {
            const double d = e.distance2(a + i, best + i);
            if (d > 0.0) {
                sum[i] += 0.5 * std::log(d);
                ++count[i];
            }
        }
    }
    std::vector<double> divergence(horizon + 1);
    for (long i = 0; i <= horizon; ++i)
        divergence[i] = count[i] > 0 ? sum[i] / count[i] : 0.0;
    return divergence;
}

/// Least-squares slope of r.divergence[i] against i dt over i0 .. i1, and its standard error,
/// into r.lambda and r.error.
void fit_divergence_slope(long i0, long i1, double dt, TimeSeriesExponent& r) {
    double st = 0, sy = 0, stt = 0, sty = 0;
    const double m = static_cast<double>(i1 - i0 + 1);
    for (long i = i0; i <= i1; ++i) {
        const double t = i * dt, y = r.divergence[i];
        st += t, sy += y, stt += t * t, sty += t * y;
    }
    const double denom = m * stt - st * st;
    r.lambda = (m * sty - st * sy) / denom;
    const double intercept = (sy - r.lambda * st) / m;
    double sse = 0.0;
    for (long i = i0; i <= i1; ++i) {
        const double e = r.divergence[i] - intercept - r.lambda * i * dt;
        sse += e * e;
    }
    r.error = std::sqrt(sse / std::max(1.0, m - 2) * m / denom);
}

} // namespace

TimeSeriesExponent largest_exponent_from_series(const std::vector<double>& x, double dt,
                                                const TimeSeriesOptions& o) {
    validate_series(x, dt, o);
    const long n = static_cast<long>(x.size());
    // Mean period from the mean-crossings: the Theiler window keeps neighbours that are merely
    // the next sample on the same trajectory out of the search.
    const long separation = o.min_separation == 0 ? mean_period_samples(x) : o.min_separation;
    const long horizon = o.horizon > 0 ? o.horizon : 4 * separation;
    const long span = static_cast<long>(o.embedding - 1) * o.delay;
    const long points = n - span - horizon;
    if (points < 10 * 2 + 2 * separation)
        throw std::invalid_argument(
            "series: too short for embedding " + std::to_string(o.embedding) + ", delay " +
            std::to_string(o.delay) + " and horizon " + std::to_string(horizon) + " (" +
            std::to_string(n) + " samples)");
    // Reference points, decimated to bound the O(P^2) neighbour search.
    const ReferencePoints ref{points, std::max(1L, points / o.max_points), separation};
    TimeSeriesExponent r;
    r.sample_interval = dt;
    r.divergence = mean_log_divergence(DelayEmbedding(x, o.embedding, o.delay), ref, horizon);
    const long i0 = static_cast<long>(o.fit_from * horizon);
    const long i1 = std::max(i0 + 2, static_cast<long>(o.fit_to * horizon));
    fit_divergence_slope(i0, i1, dt, r);
    return r;
}

} // namespace gapchain
