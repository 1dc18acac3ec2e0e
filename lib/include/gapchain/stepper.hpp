#pragma once
/// \file stepper.hpp
/// One stepper interface for every fixed-step scheme, and the choice of the step.

#include "gapchain/dynamics.hpp"

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

/// Largest row (bodies) the exact scheme takes: it sets up an O(Nm^3) eigendecomposition for
/// every contact state the row visits, and a long row's states hardly repeat.
inline constexpr int max_exact_bodies = 64;

/// Fastest contact oscillation the exact scheme takes (Dynamics::max_angular_frequency(), rad
/// per unit reduced time). Stiffer contacts make its eigendecompositions lose the accuracy
/// asked: against rk8pd at 1e-9 (Nm = 3, eps = 0.5, e_r = 0, f_r = 1) its relative F_m error
/// was 6e-6 at fc = 1e8 (8.9e4 rad), 3.5e-5 at 1.5e8 (1.1e5) and 62 % at 3e8 (1.5e5).
inline constexpr double max_exact_angular_frequency = 1e5;

/// The exact scheme's F_m is known to this fraction of itself at best: measured against rk8pd
/// at 1e-10 on three scenes, 6e-13 at most (docs/accuracy.md). Its comparison runs share its
/// eigendecompositions and so its round-off, and cannot see it. simulate() holds every scheme's
/// F_m_error to this floor: rk8pd at 1e-12 and exact differ by up to 2.3e-13 of F_m.
inline constexpr double exact_F_m_round_off = 1e-12;

/// Relative distance of a free mode's frequency from the forcing's below which the exact scheme
/// counts the row as resonant and refuses it (an undamped row only: its response grows as
/// t sin(w t), which no harmonic particular solution holds).
inline constexpr double exact_resonance_tolerance = 1e-8;

/// Why the exact scheme cannot take the row dyn (more than max_exact_bodies bodies, contacts
/// faster than max_exact_angular_frequency, or an undamped body forced at its natural
/// frequency), ending with the way out; nothing if it
/// can. The message ("exact takes ...") names the row's offending key (model.Nm, model.fc);
/// callers prefix the key that chose exact.
std::optional<std::string> exact_refusal(const Dynamics& dyn);

/// Whether the exact scheme can take the row dyn at all: the linear contact law, harmonic
/// forcing, and no exact_refusal().
bool exact_can_run(const Dynamics& dyn);

/// Integration schemes. `automatic` resolves to the scheme measured fastest for the accuracy.
enum class Scheme {
    automatic,          ///< "auto": chosen by choose_scheme()
    central_difference, ///< the paper's explicit scheme, order 2, one force evaluation per step
    rk4,                ///< classical Runge-Kutta, order 4 (steps are split at contact switches)
    rkf45,              ///< GSL adaptive Runge-Kutta-Fehlberg 4(5) inside each output interval
    rk8pd,              ///< GSL adaptive Prince-Dormand 8(9) inside each output interval
    exact,              ///< piecewise-linear propagation: exact between contact switches
};

/// Parses "auto", "central_difference", "rk4", "rkf45", "rk8pd" or "exact"; throws
/// std::invalid_argument otherwise.
Scheme parse_scheme(std::string_view name);
/// The scene name of a scheme.
std::string_view to_string(Scheme scheme);

/// Order of accuracy on smooth problems, and the stability limit on h * omega_max.
struct SchemeTraits {
    int order;              ///< global order on smooth problems (0: exact between switches)
    double stability_limit; ///< largest stable h * omega for an undamped oscillator (inf: none)
    int forces_per_step;    ///< right-hand-side evaluations per step (minimum, adaptive)
    bool adaptive;          ///< the step is an output interval with internal error control
};
/// Traits of a concrete scheme (not `automatic`).
SchemeTraits traits(Scheme scheme);

/// The scheme `automatic` stands for, at a relative F_m tolerance in (0, 1), for a row of
/// `bodies` bodies (measured in docs/accuracy.md).
Scheme choose_scheme(double tolerance, int bodies);

/// Advances a state (u, v) of a Dynamics by one fixed step. Not thread-safe: one per run.
class Stepper {
public:
    virtual ~Stepper() = default;
    /// Advance y (2 Nm entries) from reduced time t to t + h (h > 0).
    virtual void step(double t, double h, std::vector<double>& y) = 0;
    /// Forget cached evaluations; call after changing y other than through step().
    virtual void reset() {}
    /// Right-hand-side evaluations so far (for exact: matrix-vector propagations).
    [[nodiscard]] long evaluations() const { return m_evaluations; }
    /// Dense output of the last step taken: the state at reduced time t within it, into y
    /// (2 Nm entries). Returns false when the scheme has none beyond Hermite interpolation.
    virtual bool dense_state(double t, double* y) const {
        (void)t, (void)y;
        return false;
    }

protected:
    long m_evaluations = 0;
};

/// The step of a run: an integer number of steps per forcing period, so that every period
/// boundary is a step point.
struct StepPlan {
    Scheme scheme = Scheme::rk4;   ///< concrete scheme
    double step = 0.0;             ///< reduced time step (output interval if adaptive), > 0
    int steps_per_period = 0;      ///< forcing period / step, >= 1
    double tolerance = 1e-4;       ///< relative tolerance (adaptive schemes' error control)
    bool split_at_switches = true; ///< end steps on contact switches (off only to measure why)
};

/// A stepper for plan's scheme for dyn (which must outlive it).
std::unique_ptr<Stepper> make_stepper(const StepPlan& plan, const Dynamics& dyn);

/// Chooses the scheme (for `automatic`) and the step for a relative F_m tolerance in
/// [1e-12, 0.1]: the largest step with an
/// integer number of steps per period that keeps h * omega_max within the scheme's accuracy
/// and stability limits. A user step (> 0) is honoured (rounded down to fit the period) unless it
/// breaks the stability limit, which throws std::invalid_argument naming the limit.
StepPlan plan_step(const Dynamics& dyn, Scheme scheme, double tolerance,
                   std::optional<double> user_step = std::nullopt);

/// The plan a run that does not settle finishes on in AccuracyMode::automatic (simulate()):
/// rk4 at h omega_max = 0.4 (16 steps per fastest contact period, and at least 16 per forcing
/// period), whatever the tolerance, with steps not split at contact switches. Its F_m error on
/// periodic points of the paper's grid: 1.4e-3 rms (docs/performance.md).
StepPlan relaxed_plan(const Dynamics& dyn);

} // namespace gapchain
