#pragma once
/// \file lyapunov.hpp
/// Lyapunov exponents by Benettin's method: tangent vectors are propagated with the flow and
/// re-orthonormalised (QR); the exponents are the time averages of the log stretchings.
///
/// Two drivers share one accumulator: a generic one for any smooth system given by its
/// right-hand side and Jacobian (RK4 on the state and the tangent basis), and one for the row,
/// which rides the gapchain time loop as an observer.

#include "gapchain/dynamics.hpp"
#include "gapchain/run.hpp"
#include "gapchain/tangent_flow.hpp"

#include <limits>
#include <vector>

namespace gapchain {

/// Running estimate of the exponents at one time.
struct LyapunovSample {
    double t = 0.0;                ///< reduced time
    std::vector<double> exponents; ///< running averages so far
};

/// The spectrum and how well it is known.
struct LyapunovResult {
    /// [1 / unit time], in Benettin's order: the k-th is the growth rate of the k-th tangent
    /// direction, largest first up to its error (exponents equal within their errors, as on a
    /// contact-free row, can come out in either order).
    std::vector<double> exponents;
    /// Standard error of each, from 10 time blocks of the averaging window, or where the block
    /// rates drift (drifting) the drift over the window, if larger; infinite where fewer than 20
    /// periods are averaged (too few samples for the blocks).
    std::vector<double> errors;
    /// On a run that is attracted (the first exponent 3 standard errors below 0), the block
    /// rates of some exponent trend (a least-squares slope beyond 5 of its standard errors,
    /// whose change over the window exceeds the standard error): the run had not reached its
    /// orbit, or approaches it slowly (a multiplier near the unit circle); that exponent's error
    /// is the change. A longer run.transient_periods removes it. Not tested on a chaotic run,
    /// whose rates wander without a transient.
    bool drifting = false;
    double sum = 0.0; ///< sum of the exponents
    /// What the sum of all 2 Nm exponents must be: the Jacobian's trace, -sum of the bodies'
    /// damping rates (-4 pi eps Nm on the paper's row; contacts add no damping). NaN when fewer
    /// exponents were asked for, or outside chain_lyapunov().
    double expected_sum = std::numeric_limits<double>::quiet_NaN();
    double averaging_time = 0.0;         ///< time the averages cover
    Scheme scheme = Scheme::rk4;         ///< the scheme the trajectory and its tangents ran on
    double step = 0.0;                   ///< its step (output interval on exact), reduced time
    std::vector<LyapunovSample> history; ///< running estimates (at most ~500 samples)
    RunStatus status = RunStatus::completed;
    std::string message;      ///< why a run failed (empty otherwise)
    double wall_time_s = 0.0; ///< [s]
};

/// Orthonormal tangent basis (dimension x count, column-major) and the log-stretching sums.
/// Reusable by any driver: propagate basis() by the tangent map, then call orthonormalize().
class LyapunovAccumulator {
public:
    /// 1 <= count <= dimension. The initial basis is a fixed, generic orthonormal set.
    LyapunovAccumulator(int dimension, int count);
    /// The basis, column k at [k * dimension, (k + 1) * dimension).
    [[nodiscard]] std::vector<double>& basis() { return m_basis; }
    [[nodiscard]] int dimension() const { return m_dim; }
    [[nodiscard]] int count() const { return m_count; }
    /// Modified Gram-Schmidt QR of the basis at time t; when accumulate, adds log |R_kk|.
    /// Returns false if a column collapsed or became non-finite.
    bool orthonormalize(double t, bool accumulate);
    /// Starts the averages at time t (discarding what came before).
    void start(double t);
    /// Exponents, errors and history so far.
    [[nodiscard]] LyapunovResult result() const;

private:
    int m_dim;
    int m_count;
    std::vector<double> m_basis;
    double m_t_start = 0.0;
    bool m_started = false;
    std::vector<double> m_times; ///< time of each accumulated re-orthonormalisation
    std::vector<double> m_sums;  ///< cumulative log sums, count per entry
};

/// A smooth system for the generic driver.
class TangentSystem {
public:
    virtual ~TangentSystem() = default;
    [[nodiscard]] virtual int dimension() const = 0;
    virtual void rhs(double t, const double* y, double* dydt) const = 0;
    /// Row-major dimension x dimension Jacobian at (t, y).
    virtual void jacobian(double t, const double* y, double* jac) const = 0;
};

/// Options of the generic driver.
struct LyapunovOptions {
    int count = 0;                         ///< exponents wanted (0: all)
    double step = 0.01;                    ///< RK4 step, > 0
    double transient = 0.0;                ///< time integrated before averaging, >= 0
    double duration = 100.0;               ///< averaging time, > 0
    int steps_per_orthonormalization = 10; ///< >= 1
};

/// Lyapunov spectrum of a smooth system from y0 (RK4 on the state and the tangent basis).
LyapunovResult lyapunov_spectrum(const TangentSystem& system, std::vector<double> y0,
                                 const LyapunovOptions& options);

/// Observer that propagates a tangent basis along a run of the row with TangentFlow (exp(h J)
/// between switches, in scaled coordinates) and re-orthonormalises it every forcing period.
/// The contact force is continuous
/// in the gap, so the vector field is continuous across a switch and the tangent vectors need no
/// jump (saltation) matrix there: the saltation matrix I + (f+ - f-) n^T / (n^T f-) is the
/// identity when f+ = f- on the switching surface.
class TangentObserver final : public Observer {
public:
    /// dyn must outlive the observer; count in [1, 2 Nm]; averages start at the end of period
    /// `start_period`. Needs the linear contact law (std::invalid_argument otherwise).
    TangentObserver(const Dynamics& dyn, int count, long start_period);
    void on_step(const StepView& step) override;
    bool on_period(long n, double t, const double* y) override;
    /// As its tangent flow's: count steps of the row per step.
    [[nodiscard]] double step_cost() const override { return m_flow.step_cost(); }
    /// The exponents; errors infinite where fewer than 20 periods were averaged (the 10 blocks
    /// count re-orthonormalisations, several a period where damping is strong).
    [[nodiscard]] LyapunovResult result() const;
    /// False once the basis collapsed or became non-finite.
    [[nodiscard]] bool healthy() const { return m_healthy; }

private:
    void copy_basis_to_flow();
    /// QRs the flow's basis at time t (accumulating once past start_period); false if it
    /// collapsed.
    void orthonormalize(double t, bool accumulate);
    TangentFlow m_flow; ///< carries the basis between re-orthonormalisations
    LyapunovAccumulator m_accumulator;
    long m_start_period;
    /// Longest reduced time between re-orthonormalisations: max_qr_log_ratio over the
    /// exponents' spread bound (the row's largest damping rate, plus 2 pi for growth).
    double m_qr_interval;
    double m_next_qr;
    long m_periods_averaged = 0;
    bool m_healthy = true;
};

/// The scheme of a run that carries the tangent flow: `auto` is the exact propagator on rows of
/// up to 10 bodies that it takes (harmonic forcing, the linear law, contacts it resolves),
/// where rk4's trajectory at the default tolerance biases the exponents through stiff contacts;
/// any other request, or a row beyond those, is returned as it is.
Scheme tangent_run_scheme(const Dynamics& dyn, Scheme requested);

/// Tightest tolerance a tangent run on a scheme other than exact keeps: its multipliers and
/// exponents follow the trajectory's contact times, which need more than F_m does.
inline constexpr double max_tangent_run_tolerance = 1e-6;

/// The options of a run that carries the tangent flow: requested with tangent_run_scheme(), and,
/// on any scheme but exact without a user step, the tolerance at most
/// max_tangent_run_tolerance (Fig 13's row at fc = 2e8 on rk4 at 1e-4: largest multiplier 26
/// of a stable orbit whose rk8pd multiplier is 0.351, lambda_1 +10 against -3.14; at 1e-6:
/// 0.368, lambda_1 -3.08 +- 0.13; 5 % off at fc = 1e5 at 1e-4).
RunOptions tangent_run_options(const Dynamics& dyn, RunOptions requested);

/// Lyapunov spectrum of the row (count exponents, 1 .. 2 Nm) over options.periods, averaged
/// after options.transient_periods; runs the full length (no steady-state stop), with
/// tangent_run_options().
LyapunovResult chain_lyapunov(const Dynamics& dyn, const RunOptions& options, int count,
                              const std::vector<double>& initial = {},
                              const ProgressCallback& progress = {});

/// Options of the time-series estimate (Rosenstein, Collins & De Luca, Physica D 65, 1993).
struct TimeSeriesOptions {
    int embedding = 6;      ///< embedding dimension m, 1 .. 100
    int delay = 1;          ///< delay in samples, >= 1
    int min_separation = 0; ///< neighbours at least this many samples apart in time (Theiler
                            ///< window); 0: one mean period from the zero crossings
    int horizon = 0;        ///< samples each pair is followed; 0: 4 min_separation
    double fit_from = 0.25; ///< start of the fitted range, fraction of the horizon in [0, 1)
    double fit_to = 0.55;   ///< end of the fitted range, (fit_from, 1]
    int max_points = 4000;  ///< embedded points used (the series is decimated in time beyond)
};

/// The largest exponent from a measured series.
struct TimeSeriesExponent {
    double lambda = 0.0;            ///< slope of the mean log divergence [1 / time]
    double error = 0.0;             ///< standard error of the fitted slope
    std::vector<double> divergence; ///< mean log distance after i samples, i = 0 .. horizon
    double sample_interval = 0.0;   ///< time between samples
};

/// Largest Lyapunov exponent of a scalar series sampled every dt (> 0) by Rosenstein's method:
/// delay embedding, nearest neighbours outside a Theiler window, mean log divergence, and a
/// least-squares slope over [fit_from, fit_to] of the horizon.
TimeSeriesExponent largest_exponent_from_series(const std::vector<double>& series, double dt,
                                                const TimeSeriesOptions& options = {});

} // namespace gapchain
