#include "gapchain/stepper.hpp"

#include "detail/check.hpp"
#include "detail/steppers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace gapchain {

Scheme parse_scheme(std::string_view name) {
    if (name == "auto") return Scheme::automatic;
    if (name == "central_difference") return Scheme::central_difference;
    if (name == "rk4") return Scheme::rk4;
    if (name == "rkf45") return Scheme::rkf45;
    if (name == "rk8pd") return Scheme::rk8pd;
    if (name == "exact") return Scheme::exact;
    throw std::invalid_argument(
        "run.scheme: must be one of auto, central_difference, rk4, rkf45, rk8pd, exact, got \"" +
        std::string(name) + "\"");
}

std::string_view to_string(Scheme scheme) {
    switch (scheme) {
    case Scheme::automatic: return "auto";
    case Scheme::central_difference: return "central_difference";
    case Scheme::rk4: return "rk4";
    case Scheme::rkf45: return "rkf45";
    case Scheme::rk8pd: return "rk8pd";
    case Scheme::exact: return "exact";
    }
    return "?";
}

SchemeTraits traits(Scheme scheme) {
    constexpr double unbounded = std::numeric_limits<double>::infinity();
    switch (scheme) {
    case Scheme::central_difference: return {2, 2.0, 1, false};
    case Scheme::rk4: return {4, 2.78, 4, false};
    case Scheme::rkf45: return {4, unbounded, 6, true};
    case Scheme::rk8pd: return {8, unbounded, 13, true};
    case Scheme::exact: return {0, unbounded, 1, true};
    case Scheme::automatic: break;
    }
    throw std::invalid_argument("traits: the scheme must be concrete, got auto");
}

std::optional<std::string> exact_refusal(const Dynamics& dyn) {
    // Each contact state the row visits costs an eigendecomposition of (2 Nm)^2 numbers,
    // O(Nm^3), which no cancel can interrupt: a long row, whose states hardly repeat, spends
    // its time there (Nm = 150: 14 min for one orbit, Nm = 2000: hours).
    if (dyn.bodies() > max_exact_bodies)
        return "exact takes rows of up to " + std::to_string(max_exact_bodies) +
               " bodies (an O(Nm^3) set-up per contact state), got model.Nm = " +
               std::to_string(dyn.bodies()) + "; use rk4";
    if (dyn.max_angular_frequency() > max_exact_angular_frequency)
        return "exact takes contacts of up to " +
               detail::format_number(max_exact_angular_frequency) +
               " rad per unit time (model.fc up to about 1.27e8 in the paper's row; stiffer ones "
               "cost its eigendecompositions their accuracy), got " +
               detail::format_number(dyn.max_angular_frequency()) + "; use rk4 or rk8pd";
    // An undamped body forced at its natural frequency (eps = 0, f_r = 1 in the paper's row)
    // answers with t sin(w t), which no harmonic particular solution holds: (i w - A) is
    // singular and the closed form was off by hundreds (the probe of 2026-11-26). This is the
    // contact-free configuration; ExactPropagator refuses any other one it meets resonant.
    if (dyn.ground_motion().is_harmonic()) {
        const Chain& c = dyn.chain();
        const double w = 2.0 * std::numbers::pi * dyn.ground_motion().f_r();
        for (std::size_t i = 0; i < c.mass.size(); ++i)
            if (c.damping[i] == 0.0 &&
                std::abs(std::sqrt(c.spring[i] / c.mass[i]) - w) <= exact_resonance_tolerance * w)
                return "exact cannot take an undamped row forced at a natural frequency (body " +
                       std::to_string(i + 1) +
                       " at f_r = " + detail::format_number(dyn.ground_motion().f_r()) +
                       ": the response grows as t sin); use rk4 or rk8pd";
    }
    return std::nullopt;
}

bool exact_can_run(const Dynamics& dyn) {
    return dyn.chain().law == ContactLaw::linear && dyn.ground_motion().is_harmonic() &&
           !exact_refusal(dyn);
}

Scheme choose_scheme(double tolerance, int bodies) {
    detail::require_range("run.tolerance", tolerance, 0.0, 1.0, detail::Bound::open_low);
    // From the work-precision studies of docs/accuracy.md: rk4 (with steps split at contact
    // switches) beats the central difference at every tolerance from 1e-2 down; the exact
    // propagator beats rk4 from 1e-6 down on rows of up to 10 bodies, and from 1e-8 down up to
    // 20 bodies (its O(Nm^2) step and per-configuration set-up lose on longer rows).
    if ((tolerance <= 1e-6 && bodies <= 10) || (tolerance <= 1e-8 && bodies <= 20))
        return Scheme::exact;
    return Scheme::rk4;
}

namespace {

/// The paper's explicit central-difference scheme in kick-drift-kick form. The damping is
/// diagonal, so the closing half-kick solves for v_{n+1} exactly and the scheme stays explicit
/// and second order, with one force evaluation per step (the end force is reused).
class CentralDifference final : public Stepper {
public:
    explicit CentralDifference(const Dynamics& dyn)
        : m_dyn(dyn), m_n(dyn.bodies()), m_restoring(m_n), m_half(m_n) {}

    void step(double t, double h, std::vector<double>& y) override {
        double* u = y.data();
        double* v = y.data() + m_n;
        const double* d = m_dyn.chain().damping.data();
        if (!m_cached || m_t != t) {
            m_dyn.restoring_acceleration(m_dyn.ground(t), u, m_restoring.data());
            ++m_evaluations;
        }
        for (int i = 0; i < m_n; ++i) {
            m_half[i] = v[i] + 0.5 * h * (m_restoring[i] - d[i] * v[i]);
            u[i] += h * m_half[i];
        }
        m_dyn.restoring_acceleration(m_dyn.ground(t + h), u, m_restoring.data());
        ++m_evaluations;
        for (int i = 0; i < m_n; ++i)
            v[i] = (m_half[i] + 0.5 * h * m_restoring[i]) / (1.0 + 0.5 * h * d[i]);
        m_cached = true;
        m_t = t + h;
    }
    void reset() override { m_cached = false; }

private:
    const Dynamics& m_dyn;
    int m_n;
    std::vector<double> m_restoring;
    std::vector<double> m_half;
    bool m_cached = false;
    double m_t = 0.0;
};

class RungeKutta4 final : public Stepper {
public:
    /// plan_step: the plan's step, whose ground terms are tabulated (0: none).
    RungeKutta4(const Dynamics& dyn, double plan_step)
        : m_dyn(dyn), m_n(dyn.bodies()), m_k(4, std::vector<double>(2 * m_n)), m_tmp(2 * m_n) {
        build_table(plan_step);
    }

    void step(double t, double h, std::vector<double>& y) override {
        const int dim = 2 * m_n;
        double g0 = 0.0, gh = 0.0, g1 = 0.0;
        if (!tabulated_ground(t, h, g0, gh, g1)) {
            // Consecutive steps share an end: reuse its ground term (one cosine fewer per step).
            g0 = (m_have_end && m_end_t == t) ? m_end_ground : m_dyn.ground(t);
            gh = m_dyn.ground(t + 0.5 * h);
            g1 = m_dyn.ground(t + h);
        }
        m_end_t = t + h;
        m_end_ground = g1;
        m_have_end = true;
        evaluate(g0, y.data(), m_k[0].data());
        axpy(0.5 * h, m_k[0], y);
        evaluate(gh, m_tmp.data(), m_k[1].data());
        axpy(0.5 * h, m_k[1], y);
        evaluate(gh, m_tmp.data(), m_k[2].data());
        axpy(h, m_k[2], y);
        evaluate(g1, m_tmp.data(), m_k[3].data());
        const double w = h / 6.0;
        for (int i = 0; i < dim; ++i)
            y[i] += w * (m_k[0][i] + 2.0 * (m_k[1][i] + m_k[2][i]) + m_k[3][i]);
        m_evaluations += 4;
    }

private:
    /// Harmonic forcing repeats every period, and a plan's steps fall on the same phases in
    /// every period: the ground terms at a plan step's start, middle and end come from a table
    /// of one period (the cosines were a tenth of a relaxed run's time, and a step's start,
    /// computed from the step count, rarely equals the previous step's end to the bit). Other
    /// steps return false and are computed directly. The table's values differ from the
    /// direct ones in the last bits, so plans that split at switches (strict runs) keep the
    /// direct ones: a strict run stays bit for bit what it was.
    bool tabulated_ground(double t, double h, double& start, double& middle, double& end) const {
        // A plan step's length arrives as a difference of two times counted from the run's
        // start, so it carries their rounding (~1e-16 t: 1e-10 of a step late in a long stiff
        // run); a step that is not the plan's (a split piece) differs by far more.
        if (m_table_middle.empty() ||
            std::abs(h - m_table_step) > 1e-12 * m_table_step + 1e-14 * std::abs(t))
            return false;
        // Counted in the table's step: h's rounding, times the step count, would reach the
        // 1e-6 bound after ~1e5 steps and send every later step to the cosines.
        const double steps = t / m_table_step;
        const double k = std::round(steps);
        if (std::abs(steps - k) > 1e-6) return false;
        const auto i = static_cast<std::size_t>(static_cast<long long>(k) %
                                                static_cast<long long>(m_table_middle.size()));
        start = m_table_start[i];
        middle = m_table_middle[i];
        end = m_table_end[i];
        return true;
    }
    /// The table for the plan's step, if one period is a whole number of them (up to 2^20).
    void build_table(double h) {
        if (!m_dyn.ground_motion().is_harmonic() || !(h > 0.0)) return;
        const double per_period = m_dyn.period() / h;
        const double whole = std::round(per_period);
        if (whole < 1.0 || whole > 1048576.0 || std::abs(per_period - whole) > 1e-9) return;
        m_table_step = h;
        const auto size = static_cast<std::size_t>(whole);
        m_table_start.resize(size);
        m_table_middle.resize(size);
        m_table_end.resize(size);
        for (std::size_t i = 0; i < size; ++i) {
            m_table_start[i] = m_dyn.ground(static_cast<double>(i) * h);
            m_table_middle[i] = m_dyn.ground((static_cast<double>(i) + 0.5) * h);
            m_table_end[i] = m_dyn.ground((static_cast<double>(i) + 1.0) * h);
        }
    }

    void evaluate(double ground, const double* y, double* dydt) const {
        for (int i = 0; i < m_n; ++i)
            dydt[i] = y[m_n + i];
        m_dyn.acceleration(ground, y, y + m_n, dydt + m_n);
    }
    void axpy(double a, const std::vector<double>& k, const std::vector<double>& y) {
        for (std::size_t i = 0; i < y.size(); ++i)
            m_tmp[i] = y[i] + a * k[i];
    }

    const Dynamics& m_dyn;
    int m_n;
    std::vector<std::vector<double>> m_k;
    std::vector<double> m_tmp;
    bool m_have_end = false;
    double m_end_t = 0.0;
    double m_end_ground = 0.0;
    double m_table_step = 0.0;
    std::vector<double> m_table_start, m_table_middle, m_table_end;
};

/// Largest h * omega_max that meets a relative tolerance. Calibrated on the smooth and stiff
/// scenes of docs/performance.md, where the relative F_m error measured C (h omega)^p with
/// C = 0.062 (central difference, p = 2) and C = 7.4e-4 (rk4, p = 4, switch-aligned steps);
/// the constants below keep a factor 2 in hand (rk4: 5, lowered to 4 after the nearly
/// undamped extreme case, eps = 1e-3, needed it).
double accuracy_limit(Scheme scheme, double tolerance) {
    switch (scheme) {
    case Scheme::central_difference: return 2.8 * std::sqrt(tolerance);
    case Scheme::rk4: return std::min(0.7, 4.0 * std::pow(tolerance, 0.25));
    // Adaptive schemes control their own error; the output interval only has to keep the
    // quintic Hermite interpolation between outputs (peaks, switches) within the tolerance:
    // its error is about (h omega)^6 / 720.
    case Scheme::rkf45:
    case Scheme::rk8pd: return std::min(0.4, 3.0 * std::pow(tolerance, 1.0 / 6.0));
    // Exact between switches, with exact dense output for peaks and switches: the interval
    // only has to stay below the shortest contact half-period (pi / omega), so that a contact
    // struck at speed cannot open and close within one interval. A graze, shorter than any
    // contact period, can: the time loop's switch search looks inside the step for it.
    case Scheme::exact: return 0.5 * std::numbers::pi;
    case Scheme::automatic: break;
    }
    return 0.0;
}

/// The scheme a run takes: scheme itself, or automatic resolved for the row. Throws
/// std::invalid_argument if the row's contact law or forcing rules it out.
Scheme resolved_scheme(const Dynamics& dyn, Scheme scheme, double tolerance) {
    const bool linear = dyn.chain().law == ContactLaw::linear;
    const bool harmonic = dyn.ground_motion().is_harmonic();
    if (scheme == Scheme::automatic) {
        scheme = linear && harmonic ? choose_scheme(tolerance, dyn.bodies()) : Scheme::rk4;
        if (scheme == Scheme::exact && exact_refusal(dyn)) scheme = Scheme::rk4;
    }
    if (scheme == Scheme::exact && !linear)
        throw std::invalid_argument("run.scheme: exact propagates the linear contact law only; "
                                    "use rk4, rkf45 or rk8pd with a nonlinear "
                                    "model.contact_law");
    if (scheme == Scheme::central_difference && dyn.dissipative_contacts())
        throw std::invalid_argument("run.scheme: central_difference needs contact forces that do "
                                    "not depend on the velocities; use rk4, rkf45 or rk8pd with "
                                    "model.contact_law = hunt_crossley");
    if (scheme == Scheme::exact)
        if (const auto refusal = exact_refusal(dyn))
            throw std::invalid_argument("run.scheme: " + *refusal);
    if (scheme == Scheme::exact && !harmonic)
        throw std::invalid_argument("run.scheme: exact needs harmonic forcing (its particular "
                                    "solution is closed-form); use rk4, rkf45 or rk8pd with "
                                    "a ground-motion record");
    return scheme;
}

} // namespace

std::unique_ptr<Stepper> make_stepper(const StepPlan& plan, const Dynamics& dyn) {
    switch (plan.scheme) {
    case Scheme::central_difference: return std::make_unique<CentralDifference>(dyn);
    case Scheme::rk4:
        return std::make_unique<RungeKutta4>(dyn, plan.split_at_switches ? 0.0 : plan.step);
    case Scheme::rkf45: return detail::make_gsl_stepper(dyn, false, plan.tolerance);
    case Scheme::rk8pd: return detail::make_gsl_stepper(dyn, true, plan.tolerance);
    case Scheme::exact: return detail::make_exact_propagator(dyn);
    case Scheme::automatic: break;
    }
    throw std::invalid_argument("make_stepper: the scheme must be concrete, got auto");
}

StepPlan plan_step(const Dynamics& dyn, Scheme scheme, double tolerance,
                   std::optional<double> user_step) {
    detail::require_range("run.tolerance", tolerance, 1e-12, 0.1);
    scheme = resolved_scheme(dyn, scheme, tolerance);
    const SchemeTraits tr = traits(scheme);
    // The fastest of the contact oscillations, an overdamped body's decay and the forcing
    // sets the step's accuracy and stability; the exact propagator integrates the decay
    // exactly, so only the oscillations bound its output interval (20 times fewer steps at
    // eps = 100).
    const double period = dyn.period();
    const double fastest = scheme == Scheme::exact ? dyn.max_angular_frequency() : dyn.max_rate();
    const double omega =
        std::max(fastest, 2.0 * std::numbers::pi * dyn.ground_motion().resolved_frequency());
    const double stable = tr.stability_limit / omega;
    double h = 0.0;
    if (user_step) {
        detail::require_range("run.step", *user_step, 0.0, period, detail::Bound::open_low);
        if (!tr.adaptive && *user_step * omega >= tr.stability_limit)
            throw std::invalid_argument("run.step: " + std::string(to_string(scheme)) +
                                        " is unstable for this row above " +
                                        detail::format_number(stable) + " (stability bound " +
                                        detail::format_number(tr.stability_limit) +
                                        " / omega_max), got " + detail::format_number(*user_step));
        h = *user_step;
    } else {
        // Fixed-step schemes resolve the fastest contact oscillation (at least ~16 steps per
        // contact period, so that no impact falls between two steps); every scheme resolves
        // the forcing (at least 16 steps per period).
        const double hw =
            tr.adaptive
                ? accuracy_limit(scheme, tolerance)
                : std::min({accuracy_limit(scheme, tolerance), 0.4, 0.9 * tr.stability_limit});
        h = std::min(hw / omega, period / 16.0);
    }
    // A forcing period of more than 1e9 steps (a tiny f_r, a tiny run.step, a record sampled
    // far too finely) is refused here, before the count overflows.
    if (!(period / h <= 1e9)) {
        const bool record = !dyn.ground_motion().is_harmonic();
        const std::string key = user_step ? "run.step"
                                : record  ? "excitation.file"
                                          : "excitation.f_r";
        const std::string cure = user_step ? "take a longer run.step"
                                 : record  ? "resample the record (the steps resolve a quarter "
                                             "of its sampling rate)"
                                           : "raise f_r (f_r >= 1e-5 keeps to the limit)";
        throw std::invalid_argument(key + ": one " + (record ? "natural" : "forcing") +
                                    " period (" + detail::format_number(period) +
                                    " reduced time units) would take " +
                                    detail::format_number(period / h) + " steps of " +
                                    detail::format_number(h) + ", above 1e9; " + cure);
    }
    StepPlan plan;
    plan.scheme = scheme;
    plan.steps_per_period = static_cast<int>(std::ceil(period / h - 1e-9));
    plan.step = period / plan.steps_per_period;
    plan.tolerance = tolerance;
    return plan;
}

StepPlan relaxed_plan(const Dynamics& dyn) {
    StepPlan plan = plan_step(dyn, Scheme::rk4, 1e-4);
    plan.split_at_switches = false;
    return plan;
}

} // namespace gapchain
