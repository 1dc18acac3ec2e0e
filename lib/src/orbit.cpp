#include "gapchain/orbit.hpp"

#include "gapchain/tangent_flow.hpp"

#include "detail/check.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace gapchain {

std::string_view to_string(OrbitStatus status) {
    switch (status) {
    case OrbitStatus::converged: return "converged";
    case OrbitStatus::not_converged: return "not_converged";
    case OrbitStatus::singular: return "singular";
    case OrbitStatus::non_finite: return "non_finite";
    case OrbitStatus::cancelled: return "cancelled";
    }
    return "?";
}

void validate(const OrbitOptions& o) {
    detail::require_range("period", o.period, 1, 1000);
    detail::require_range("tolerance", o.tolerance, 1e-14, 1e-3);
    detail::require_range("max_iterations", o.max_iterations, 1, 1000);
    detail::require_range("integration_tolerance", o.integration_tolerance, 1e-14, 1e-3);
    detail::require_range("run.max_work", o.max_work, 1.0, 1e15);
    if (o.scheme == Scheme::automatic)
        throw std::invalid_argument("scheme: name a concrete scheme for the shooting, not auto");
    // Second order at the map's 1e-12 takes ~1e3 times rk4's steps (9 s against 0.04 s for a
    // 2-body row) for the same orbit: the tools never offered it.
    if (o.scheme == Scheme::central_difference)
        throw std::invalid_argument("scheme: the shooting takes exact, rk4, rkf45 or rk8pd, not "
                                    "central_difference (second order: ~1e3 times rk4's steps "
                                    "for the map's accuracy)");
}

void require_orbit_size(const Dynamics& dyn, Scheme scheme) {
    if (scheme == Scheme::exact)
        if (const auto refusal = exact_refusal(dyn))
            throw std::invalid_argument("scheme: " + *refusal);
    if (dyn.bodies() > max_orbit_bodies)
        throw std::invalid_argument("model.Nm: a periodic-orbit search takes rows of up to " +
                                    std::to_string(max_orbit_bodies) +
                                    " bodies (Newton's dense (2 Nm)^2 matrices), got " +
                                    std::to_string(dyn.bodies()));
}

double shooting_work(const Dynamics& dyn, const OrbitOptions& options) {
    const StepPlan plan = plan_step(dyn, options.scheme, options.integration_tolerance);
    // A run's own check sees the row only; each of the 2 Nm tangent columns carried along costs
    // about a row's step (measured: Nm = 200 on rk4, one period at the default 1e-12, 11.8 s
    // where this count, 5.6e8 body-steps, gives 56 s at 1e7 per second; Nm = 4096 would have
    // taken over an hour per shooting, after its transient run, with no estimate).
    return run_work(dyn, plan, options.period, dyn.dimension());
}

void require_shooting_affordable(const Dynamics& dyn, const OrbitOptions& options) {
    detail::require_work(shooting_work(dyn, options), options.max_work, "one shooting takes about",
                         "the row and its " + std::to_string(dyn.dimension()) +
                             " tangent vectors over " + std::to_string(options.period) +
                             " period(s)",
                         "fewer bodies (model.Nm), a shorter period or a larger run.max_work");
}

namespace {

/// The states at the period ends and the largest gap of every contact at step ends.
struct PeriodEnds final : public Observer {
    explicit PeriodEnds(const Dynamics& dyn) : m_dyn(dyn), m_max_gap(dyn.gaps(), -1e300) {}
    void on_step(const StepView& step) override {
        for (int j = 0; j < m_dyn.gaps(); ++j)
            m_max_gap[j] = std::max(m_max_gap[j], m_dyn.gap(j, step.y1));
    }
    bool on_period(long n, double, const double* y) override {
        if (n >= 1) m_states.emplace_back(y, y + m_dyn.dimension());
        return false;
    }
    const Dynamics& m_dyn;
    std::vector<double> m_max_gap;
    std::vector<std::vector<double>> m_states;
};

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic>;
using Vector = Eigen::VectorXd;

Vector as_vector(const std::vector<double>& x) {
    return Eigen::Map<const Vector>(x.data(), static_cast<Eigen::Index>(x.size()));
}

double relative_residual(const std::vector<double>& x, const std::vector<double>& end) {
    const Vector r = as_vector(end) - as_vector(x);
    return r.norm() / (1.0 + as_vector(x).norm());
}

/// Floquet multipliers (largest modulus first), their largest modulus and Liouville's check.
void read_stability(const Dynamics& dyn, int period, const std::vector<double>& monodromy,
                    PeriodicOrbit& orbit) {
    const auto dim = static_cast<Eigen::Index>(dyn.dimension());
    const Matrix m = Eigen::Map<const Matrix>(monodromy.data(), dim, dim);
    const Eigen::EigenSolver<Matrix> solver(m, false);
    orbit.multipliers.clear();
    for (Eigen::Index i = 0; i < dim; ++i)
        orbit.multipliers.push_back(solver.eigenvalues()[i]);
    std::sort(orbit.multipliers.begin(), orbit.multipliers.end(),
              [](auto a, auto b) { return std::abs(a) > std::abs(b); });
    orbit.max_multiplier = std::abs(orbit.multipliers.front());
    // det M = exp(trace J * k T) with trace J = -sum of the damping rates (MODEL.md §5).
    const auto& c = dyn.chain().damping;
    const double log_det = -std::accumulate(c.begin(), c.end(), 0.0) * period * dyn.period();
    // An undamped row (eps = 0) has det M = 1: its multipliers cannot all lie inside the unit
    // circle, and a largest one computed a hair below 1 is round-off. Neutral is not stable.
    orbit.stable = orbit.max_multiplier < 1.0 && log_det < 0.0;
    double log_product = 0.0;
    for (const auto& mu : orbit.multipliers)
        log_product += std::log(std::abs(mu));
    // The eigensolver resolves multipliers to ~1e-16 of the largest; when their geometric mean
    // is far below that (many periods of a strongly damped orbit: e^-240 over 30 periods of
    // issue 19's row), the smallest are noise and so is the check; when they underflow to 0
    // (1000 periods of Fig 13's orbit) there is nothing to check at all.
    const double geometric_mean = std::exp(log_det / static_cast<double>(dim));
    orbit.liouville_error =
        geometric_mean < 1e-6 * orbit.max_multiplier || !std::isfinite(log_product)
            ? std::numeric_limits<double>::quiet_NaN()
            : std::abs(log_product - log_det) / std::max(std::abs(log_det), 1.0);
}

/// The orbit's record once Newton has stopped: maxima over one orbit, stability, period.
void describe(const Dynamics& dyn, const OrbitOptions& o, const std::vector<double>& x,
              const ShootingResult& s, PeriodicOrbit& orbit) {
    orbit.state = x;
    orbit.residual = relative_residual(x, s.end_state);
    orbit.per_contact = s.per_contact;
    orbit.max_gap = s.max_gap;
    orbit.period_ends = s.at_ends;
    orbit.F_m = 0.0;
    for (const auto& c : s.per_contact)
        orbit.F_m = std::max(orbit.F_m, c.force);
    read_stability(dyn, o.period, s.monodromy, orbit);
    orbit.minimal_period = minimal_period(x, s, o.tolerance);
}

} // namespace

ShootingResult shoot(const Dynamics& dyn, const OrbitOptions& options, const std::vector<double>& x,
                     const ProgressCallback& keep_going) {
    require_harmonic(dyn, "periodic orbits");
    RunOptions run;
    run.periods = options.period;
    run.transient_periods = 0;
    run.scheme = options.scheme;
    run.tolerance = options.integration_tolerance;
    run.stop_at_steady_state = false;
    run.estimate_error = false;
    run.max_work = options.max_work;
    PlannedRun planned(dyn, run, x);
    require_shooting_affordable(dyn, options);
    TangentFlow flow(dyn, dyn.dimension());
    MaxForceTracker forces(dyn);
    PeriodEnds ends(dyn);
    Observer* observers[] = {&flow, &forces, &ends};
    const RunOutcome outcome = planned.run(observers, keep_going);
    ShootingResult s;
    s.cancelled = outcome.status == RunStatus::cancelled;
    s.end_state = planned.state();
    s.monodromy = flow.unscaled_matrix();
    s.at_ends = std::move(ends.m_states);
    s.per_contact = forces.contacts();
    s.max_gap = std::move(ends.m_max_gap);
    s.finite = outcome.status != RunStatus::non_finite &&
               std::all_of(s.monodromy.begin(), s.monodromy.end(),
                           [](double v) { return std::isfinite(v); });
    return s;
}

namespace {

/// One plain run of `run` (the checking scheme, its periods) from x: the largest force
/// and the end state; nothing if it stops early.
std::optional<std::pair<double, std::vector<double>>>
check_run(const Dynamics& dyn, const RunOptions& run, const std::vector<double>& x,
          const ProgressCallback& keep_going) {
    PlannedRun planned(dyn, run, x);
    MaxForceTracker forces(dyn);
    Observer* observers[] = {&forces};
    if (planned.run(observers, keep_going).status != RunStatus::completed) return std::nullopt;
    double F_m = 0.0;
    for (const auto& c : forces.contacts())
        F_m = std::max(F_m, c.force);
    return std::make_pair(F_m, planned.state());
}

/// The scheme an orbit found on `scheme` is checked against (its F_m's and its largest
/// multiplier's errors): rk8pd, or rkf45 for an orbit found on rk8pd, at check_tolerance.
Scheme checking_scheme(Scheme scheme) {
    return scheme == Scheme::rk8pd ? Scheme::rkf45 : Scheme::rk8pd;
}
constexpr double check_tolerance = 1e-10;
/// The checking run's own error, relative to F_m: rk8pd at check_tolerance lies 3e-12 and
/// 2.3e-12 of F_m from the exact scheme's orbit on Fig 13's row at f_r = 3.0 and 2.2, where an
/// rk4 orbit's bar (its difference from rk8pd alone) fell 5 % and 57 % short of its gap to
/// exact (a reviewer's probe, helper-75). It is added to the difference.
constexpr double checking_error = 1e-11;

} // namespace

std::optional<double> orbit_force_error(const Dynamics& dyn, Scheme scheme, int period,
                                        const std::vector<double>& x,
                                        const std::vector<double>& monodromy, double F_m,
                                        double max_work, const ProgressCallback& keep_going) {
    RunOptions run;
    run.periods = period;
    run.transient_periods = 0;
    run.scheme = checking_scheme(scheme);
    run.tolerance = check_tolerance;
    run.stop_at_steady_state = false;
    run.estimate_error = false;
    run.max_work = max_work;
    if (2.0 * dyn.bodies() * plan_run(dyn, run).steps_per_period * period > max_work)
        return std::nullopt;
    const auto first = check_run(dyn, run, x, keep_going);
    if (!first) return std::nullopt;
    // x is the orbit of `scheme`'s map; the checking scheme's orbit lies off it by about
    // (I - M)^-1 (P(x) - x), 1 / (1 - |mu|) times its one-period gap, and its F_m with it (rk4
    // at 1e-5 on Fig 5's row: the gap from x alone was half of the orbits' F_m difference).
    const auto n = static_cast<Eigen::Index>(x.size());
    const Matrix m = Eigen::Map<const Matrix>(monodromy.data(), n, n);
    const Eigen::FullPivLU<Matrix> lu(Matrix::Identity(n, n) - m);
    const Vector gap = as_vector(first->second) - as_vector(x);
    const Vector shift = lu.solve(gap);
    // Next to a fold (a multiplier near +1) the linear step overshoots: on Fig 13's line at
    // f_r 2.7587-2.7621 it gave 4e-11 to 2e-9 where rk8pd's own Newton orbit was 1e-13 away.
    // There the checking scheme's orbit is found by Newton itself.
    if (!lu.isInvertible() || !shift.allFinite() || shift.norm() > 1e2 * gap.norm()) {
        OrbitOptions check;
        check.period = period;
        check.scheme = run.scheme;
        check.integration_tolerance = run.tolerance;
        check.max_iterations = 8;
        check.max_work = max_work;
        if (shooting_work(dyn, check) > max_work) return std::nullopt;
        const PeriodicOrbit other = find_periodic_orbit(dyn, check, x, keep_going);
        if (other.status != OrbitStatus::converged) return std::nullopt;
        return std::abs(other.F_m - F_m) + checking_error * F_m;
    }
    std::vector<double> corrected(x);
    for (Eigen::Index i = 0; i < n; ++i)
        corrected[static_cast<std::size_t>(i)] += shift[i];
    const auto second = check_run(dyn, run, corrected, keep_going);
    if (!second) return std::nullopt;
    return std::abs(second->first - F_m) + checking_error * F_m;
}

std::optional<double> orbit_force_error(const Dynamics& dyn, const OrbitOptions& options,
                                        const std::vector<double>& x, double F_m) {
    if (shooting_work(dyn, options) > options.max_work) return std::nullopt;
    const ShootingResult s = shoot(dyn, options, x);
    if (!s.finite) return std::nullopt;
    return orbit_force_error(dyn, options.scheme, options.period, x, s.monodromy, F_m,
                             options.max_work);
}

namespace {

/// Why a Newton search stopped at run.max_work: run.max_work bounds the search, not each
/// shooting alone (fc = 1e9 on rk4: 3.9e9 body-steps a shooting, and 40 iterations of up to 11
/// shootings each could follow).
std::string over_budget_message(const Dynamics& dyn, const OrbitOptions& options, long shootings) {
    return "run.max_work = " + detail::format_number(options.max_work) + " reached after " +
           std::to_string(shootings) + " shooting(s) of about " +
           detail::format_number(shooting_work(dyn, options)) + " body-steps; raise run.max_work";
}

enum class DampedStep { improved, stalled, cancelled, over_budget };

/// The Newton step from x, damped: halved (up to 10 times) until the residual decreases (the map
/// is only piecewise smooth, so a full step can cross a switch and overshoot). When it improves,
/// x, s and residual are the new iterate's. shootings counts the search's shootings; one that
/// would take them beyond run.max_work is not started (over_budget).
DampedStep damped_step(const Dynamics& dyn, const OrbitOptions& options, const Vector& step,
                       const ProgressCallback& keep_going, std::vector<double>& x,
                       ShootingResult& s, double& residual, long& shootings) {
    for (int halving = 0; halving <= 10; ++halving) {
        if (static_cast<double>(shootings + 1) * shooting_work(dyn, options) > options.max_work)
            return DampedStep::over_budget;
        ++shootings;
        const double lambda = std::ldexp(1.0, -halving);
        std::vector<double> trial(x);
        for (Eigen::Index i = 0; i < step.size(); ++i)
            trial[i] += lambda * step[i];
        ShootingResult t = shoot(dyn, options, trial, keep_going);
        if (t.cancelled) return DampedStep::cancelled;
        const double r = relative_residual(trial, t.end_state);
        if (t.finite && r < residual) {
            x = std::move(trial);
            s = std::move(t);
            residual = r;
            return DampedStep::improved;
        }
    }
    return DampedStep::stalled;
}

/// The largest modulus of a shooting's Floquet multipliers.
double largest_modulus(const ShootingResult& s, Eigen::Index dim) {
    const Eigen::EigenSolver<Matrix> solver(Eigen::Map<const Matrix>(s.monodromy.data(), dim, dim),
                                            false);
    return solver.eigenvalues().cwiseAbs().maxCoeff();
}

/// The error of an orbit's largest multiplier modulus, the larger of two changes.
/// - Under one more Newton step, x + (I - M)^-1 (P(x) - x): the multiplier moves with the state
///   to first order, and the step takes the state's error to its square. Two mirror orbits of
///   Nm = 1 (identical multipliers) read -0.396456210 and -0.396456152 as exponents, "+- 0".
/// - Where the F_m error is estimated too, on another scheme shot from the same state (exact,
///   or checking_scheme() for an orbit on exact): the integration's own part. Fig 13's period-2
///   orbit at f_r = 2.3 read 0.5918509858164 +- 7.7e-14 on exact, 0.59185098431 +- 1.4e-13 on
///   rk8pd, where an independent implementation found 0.5918509858375 (the review of 2026-11-27).
/// NaN where the Newton step or its shooting fails, or beyond 1000 dimensions (a second dense
/// eigensolve of a long row costs minutes).
double largest_multiplier_error(const Dynamics& dyn, const OrbitOptions& options,
                                const std::vector<double>& x, const ShootingResult& s,
                                double max_multiplier, const ProgressCallback& keep_going) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    const auto dim = static_cast<Eigen::Index>(x.size());
    if (dim > 1000) return nan;
    double scheme_error = 0.0;
    // At the orbit's own tolerance: rk8pd at check_tolerance moved it by 9e-8 there. Against
    // the exact scheme where it can run: rk8pd and rkf45 place their switches on one
    // interpolant between the same outputs, and agreed to 3e-13 where both were 1.5e-9 off.
    OrbitOptions check = options;
    check.scheme = options.scheme != Scheme::exact && exact_can_run(dyn)
                       ? Scheme::exact
                       : checking_scheme(options.scheme);
    if (options.estimate_force_error && shooting_work(dyn, check) <= options.max_work) {
        const ShootingResult other = shoot(dyn, check, x, keep_going);
        if (other.finite && !other.cancelled)
            scheme_error = std::abs(largest_modulus(other, dim) - max_multiplier);
    }
    const Matrix a =
        Matrix::Identity(dim, dim) - Eigen::Map<const Matrix>(s.monodromy.data(), dim, dim);
    const Vector step = a.fullPivLu().solve(as_vector(s.end_state) - as_vector(x));
    if (!step.allFinite()) return nan;
    std::vector<double> next(x);
    for (Eigen::Index i = 0; i < dim; ++i)
        next[static_cast<std::size_t>(i)] += step[i];
    const ShootingResult t = shoot(dyn, options, next, keep_going);
    if (!t.finite || t.cancelled) return nan;
    return std::max({std::abs(largest_modulus(t, dim) - max_multiplier), scheme_error,
                     std::numeric_limits<double>::epsilon() * max_multiplier});
}

/// A converged orbit's max_multiplier_error, and its F_m_error where options ask.
void estimate_errors(const Dynamics& dyn, const OrbitOptions& options, const std::vector<double>& x,
                     const ShootingResult& s, const ProgressCallback& keep_going,
                     PeriodicOrbit& orbit) {
    orbit.max_multiplier_error =
        largest_multiplier_error(dyn, options, x, s, orbit.max_multiplier, keep_going);
    if (!options.estimate_force_error) return;
    if (const auto error = orbit_force_error(dyn, options.scheme, options.period, x, s.monodromy,
                                             orbit.F_m, options.max_work, keep_going))
        orbit.F_m_error = *error;
}

} // namespace

int minimal_period(const std::vector<double>& x, const ShootingResult& s, double tolerance) {
    const int k = static_cast<int>(s.at_ends.size());
    for (int d = 1; d < k; ++d)
        if (k % d == 0 &&
            relative_residual(x, s.at_ends[static_cast<std::size_t>(d) - 1]) <= 1e3 * tolerance)
            return d;
    return k;
}

namespace {

/// The result before any shooting: the period asked for and the scheme that will run.
PeriodicOrbit unsearched_orbit(const OrbitOptions& options) {
    PeriodicOrbit orbit;
    orbit.period = options.period;
    orbit.scheme = options.scheme;
    orbit.integration_tolerance = options.integration_tolerance;
    return orbit;
}

} // namespace

namespace {

/// Newton's progress: the iterations done of max_iterations, and within a shooting its own
/// fraction (a long one, 200 bodies on rk4, held the display at one value while its ETA grew:
/// a hostile probe, helper-85). An iteration's later shootings (a shortened step) start at 0
/// again: the largest fraction so far is shown.
ProgressCallback newton_progress(const ProgressCallback& progress, const int& iterations,
                                 int max_iterations) {
    if (!progress) return {};
    auto shown = std::make_shared<double>(0.0);
    return [progress, &iterations, max_iterations, shown](double within) {
        *shown = std::max(*shown, std::min(1.0, (static_cast<double>(iterations) + within) /
                                                    std::max(1, max_iterations)));
        return progress(*shown);
    };
}

} // namespace

PeriodicOrbit find_periodic_orbit(const Dynamics& dyn, const OrbitOptions& options,
                                  const std::vector<double>& start,
                                  const ProgressCallback& progress) {
    const auto clock = std::chrono::steady_clock::now();
    validate(options);
    require_orbit_size(dyn, options.scheme);
    require_shooting_affordable(dyn, options);
    detail::require_length("start state", start.size(), static_cast<std::size_t>(dyn.dimension()));
    PeriodicOrbit orbit = unsearched_orbit(options);
    const auto dim = static_cast<Eigen::Index>(dyn.dimension());
    std::vector<double> x = start;
    const ProgressCallback keep_going =
        newton_progress(progress, orbit.iterations, options.max_iterations);
    ShootingResult s = shoot(dyn, options, x, keep_going);
    long shootings = 1;
    double residual = relative_residual(x, s.end_state);
    auto finish = [&](OrbitStatus status, std::string message) {
        orbit.status = status;
        orbit.message = std::move(message);
        orbit.residual_history.push_back(residual);
        if (status != OrbitStatus::non_finite && status != OrbitStatus::cancelled)
            describe(dyn, options, x, s, orbit);
        if (status == OrbitStatus::converged)
            estimate_errors(dyn, options, x, s, keep_going, orbit);
        orbit.wall_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
        return orbit;
    };
    const auto cancelled = [&] {
        return finish(OrbitStatus::cancelled, "the Newton search was cancelled");
    };
    for (;;) {
        if (s.cancelled) return cancelled();
        if (!s.finite) return finish(OrbitStatus::non_finite, "the state became non-finite");
        if (residual <= options.tolerance) return finish(OrbitStatus::converged, "");
        if (orbit.iterations == options.max_iterations)
            return finish(OrbitStatus::not_converged, "no convergence in " +
                                                          std::to_string(options.max_iterations) +
                                                          " Newton iterations");
        orbit.residual_history.push_back(residual);
        ++orbit.iterations;
        const Matrix a =
            Eigen::Map<const Matrix>(s.monodromy.data(), dim, dim) - Matrix::Identity(dim, dim);
        const Eigen::FullPivLU<Matrix> lu(a);
        if (!lu.isInvertible())
            return finish(OrbitStatus::singular, "M - I is singular (a multiplier at +1)");
        const Vector step = lu.solve(as_vector(x) - as_vector(s.end_state));
        const DampedStep taken =
            damped_step(dyn, options, step, keep_going, x, s, residual, shootings);
        if (taken == DampedStep::cancelled) return cancelled();
        if (taken == DampedStep::over_budget)
            return finish(OrbitStatus::not_converged, over_budget_message(dyn, options, shootings));
        if (taken == DampedStep::stalled)
            return finish(OrbitStatus::not_converged,
                          "the damped Newton step no longer decreases the residual");
    }
}

PeriodicOrbit find_minimal_periodic_orbit(const Dynamics& dyn, const OrbitOptions& options,
                                          const std::vector<double>& start) {
    PeriodicOrbit orbit = find_periodic_orbit(dyn, options, start);
    if (orbit.status != OrbitStatus::converged || orbit.minimal_period == orbit.period)
        return orbit;
    OrbitOptions minimal_options = options;
    minimal_options.period = orbit.minimal_period;
    PeriodicOrbit minimal = find_periodic_orbit(dyn, minimal_options, orbit.state);
    if (minimal.status != OrbitStatus::converged) return orbit;
    minimal.wall_time_s += orbit.wall_time_s;
    minimal.iterations += orbit.iterations;
    return minimal;
}

std::optional<PeriodicOrbit> confirm_periodic_orbit(const Dynamics& dyn, int period,
                                                    const std::vector<double>& state,
                                                    double max_work) {
    OrbitOptions options;
    options.period = period;
    options.tolerance = 1e-9;
    options.max_iterations = 12;
    options.max_work = max_work;
    if (exact_refusal(dyn) || shooting_work(dyn, options) > max_work) return std::nullopt;
    PeriodicOrbit orbit = find_minimal_periodic_orbit(dyn, options, state);
    if (orbit.status != OrbitStatus::converged) return orbit;
    // Newton from a run's state can converge on an orbit the run is not on: a distant one, or
    // an unstable one close by.
    double distance = 0.0, size = 0.0;
    for (std::size_t i = 0; i < state.size(); ++i) {
        distance = std::max(distance, std::abs(state[i] - orbit.state[i]));
        size = std::max(size, std::abs(state[i]));
    }
    distance /= 1.0 + size;
    if (distance > confirmation_distance) {
        orbit.status = OrbitStatus::not_converged;
        orbit.message = "Newton converged on an orbit " + detail::format_number(distance) +
                        " (relative) from the run's state, above " +
                        detail::format_number(confirmation_distance) +
                        ": not the orbit the run is on";
    } else if (orbit.max_multiplier > confirmation_max_multiplier) {
        // Just past a period doubling the new orbit lies close to the old one, which is a
        // fixed point of the doubled map too: Newton can converge on either.
        orbit.status = OrbitStatus::not_converged;
        orbit.message = "Newton converged on an unstable orbit (largest |multiplier| " +
                        detail::format_number(orbit.max_multiplier) +
                        "): not the orbit the run settled on";
    }
    return orbit;
}

PeriodicOrbit find_periodic_orbit_after(const Dynamics& dyn, const OrbitOptions& options,
                                        const std::vector<double>& initial, long transient_periods,
                                        const ProgressCallback& progress) {
    const auto clock = std::chrono::steady_clock::now();
    validate(options);
    require_orbit_size(dyn, options.scheme);
    require_shooting_affordable(dyn, options);
    detail::require_count("transient_periods", transient_periods, 0, 10'000'000);
    std::vector<double> start =
        initial.empty() ? std::vector<double>(dyn.dimension(), 0.0) : initial;
    if (transient_periods > 0) {
        RunOptions run;
        run.periods = transient_periods;
        run.transient_periods = 0;
        run.scheme = options.scheme;
        run.tolerance = std::max(options.integration_tolerance, 1e-10);
        run.stop_at_steady_state = false;
        run.estimate_error = false;
        run.max_work = options.max_work;
        PlannedRun planned(dyn, run, start);
        // The transient run is the first half of the progress reported, Newton the second.
        const ProgressCallback first_half = [&](double f) { return !progress || progress(f / 2); };
        if (planned.run({}, first_half).status == RunStatus::cancelled) {
            PeriodicOrbit cancelled = unsearched_orbit(options);
            cancelled.status = OrbitStatus::cancelled;
            cancelled.message = "the transient run was cancelled";
            return cancelled;
        }
        start = planned.state();
    }
    const double newton_from = transient_periods > 0 ? 0.5 : 0.0;
    OrbitOptions estimating = options;
    estimating.estimate_force_error = true;
    PeriodicOrbit orbit = find_periodic_orbit(dyn, estimating, start, [&](double f) {
        return !progress || progress(newton_from + (1.0 - newton_from) * f);
    });
    orbit.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    return orbit;
}

} // namespace gapchain
