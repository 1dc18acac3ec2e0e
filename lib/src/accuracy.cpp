#include "gapchain/accuracy.hpp"

#include "detail/check.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace gapchain {

namespace {

/// Keeps the state at every period boundary.
class PeriodSampler final : public Observer {
public:
    void on_step(const StepView&) override {}
    bool on_period(long, double, const double* y) override {
        m_states.emplace_back(y, y + m_dim);
        return false;
    }
    explicit PeriodSampler(int dim) : m_dim(dim) {}
    std::vector<std::vector<double>> m_states;

private:
    int m_dim;
};

struct Trajectory {
    double F_m = 0.0;
    std::vector<std::vector<double>> samples;
    long evaluations = 0;
    double seconds = 0.0;
};

/// Nothing if progress stopped the run.
std::optional<Trajectory> integrate(const Dynamics& dyn, const StepPlan& plan, long periods,
                                    const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    auto stepper = make_stepper(plan, dyn);
    MaxForceTracker forces(dyn);
    PeriodSampler sampler(dyn.dimension());
    Observer* observers[] = {&forces, &sampler};
    std::vector<double> y(dyn.dimension(), 0.0);
    if (run(dyn, *stepper, plan, {periods, 0, 0.0}, y, observers, progress).status ==
        RunStatus::cancelled)
        return std::nullopt;
    Trajectory t;
    for (const auto& c : forces.contacts())
        t.F_m = std::max(t.F_m, c.force);
    t.samples = std::move(sampler.m_states);
    t.evaluations = stepper->evaluations();
    t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return t;
}

double max_norm_difference(const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        d = std::max(d, std::abs(a[i] - b[i]));
    return std::isfinite(d) ? d : std::numeric_limits<double>::infinity();
}

void validate(const WorkPrecisionOptions& o) {
    detail::require_range("periods", static_cast<double>(o.periods), 1.0, 1e7);
    detail::require_range("repeats", o.repeats, 1, 100);
    for (std::size_t k = 0; k < o.tolerances.size(); ++k) {
        detail::require_range("tolerances", o.tolerances[k], 1e-12, 0.1);
        // Each would be run and written again (duplicate rows), as a scheme listed twice.
        if (std::find(o.tolerances.begin(), o.tolerances.begin() + static_cast<long>(k),
                      o.tolerances[k]) != o.tolerances.begin() + static_cast<long>(k))
            throw std::invalid_argument("tolerances: " + detail::format_number(o.tolerances[k]) +
                                        " is listed twice");
    }
    for (Scheme s : o.schemes)
        if (s == Scheme::automatic)
            throw std::invalid_argument("schemes: name concrete schemes, not auto");
    detail::require_range("run.max_work", o.max_work, 1.0, 1e15);
}

/// The reference run's plan: the exact propagator at half its default interval.
StepPlan reference_plan_for(const Dynamics& dyn) {
    // The reference is the exact propagator: a row it cannot take has no reference.
    if (auto refusal = exact_refusal(dyn)) {
        // Its advice to take another scheme does not apply: the study needs this one.
        if (const auto advice = refusal->rfind("; use "); advice != std::string::npos)
            refusal->erase(advice);
        throw std::invalid_argument("model: a work-precision study's reference is the exact "
                                    "propagator, which cannot run this row: " +
                                    *refusal);
    }
    StepPlan plan = plan_step(dyn, Scheme::exact, 1e-12);
    plan.steps_per_period *= 2;
    plan.step /= 2;
    return plan;
}

/// Refuses a study whose runs together exceed o.max_work body-steps, with the estimate.
void require_affordable_study(const Dynamics& dyn, const WorkPrecisionOptions& o,
                              const StepPlan& reference_plan) {
    // run_work(): the exact reference's set-up of contact configurations counts too (a 46-body
    // study counted 182,620 body-steps and ran 8 s).
    const auto periods = static_cast<double>(o.periods);
    double work = run_work(dyn, reference_plan, periods);
    const auto count = [&](Scheme scheme, double copies) {
        for (double tol : o.tolerances)
            work += copies * run_work(dyn, plan_step(dyn, scheme, tol), periods);
    };
    for (Scheme scheme : o.schemes)
        count(scheme, o.repeats);
    for (Scheme scheme : unsplit_schemes(o))
        count(scheme, o.repeats);
    detail::require_work(work, o.max_work, "this study takes at least",
                         "every scheme, tolerance and repeat, Nm " + std::to_string(dyn.bodies()) +
                             ", " + std::to_string(o.periods) + " periods each",
                         "fewer --periods, --tolerances, --repeats or --schemes, a higher "
                         "excitation.f_r, or raise run.max_work");
}

/// A run's errors against the reference: F_m's (relative), the final state's and the RMS over
/// the once-per-period samples (max norm); F_m and evaluations copied.
WorkPrecisionPoint against_reference(const Trajectory& t, const Trajectory& reference) {
    WorkPrecisionPoint p;
    p.F_m = t.F_m;
    p.F_m_error =
        reference.F_m > 0.0 ? std::abs(t.F_m - reference.F_m) / reference.F_m : std::abs(t.F_m);
    p.final_error = max_norm_difference(t.samples.back(), reference.samples.back());
    double sum2 = 0.0;
    for (std::size_t k = 0; k < t.samples.size(); ++k) {
        const double e = max_norm_difference(t.samples[k], reference.samples[k]);
        sum2 += e * e;
    }
    p.l2_error = std::sqrt(sum2 / t.samples.size());
    p.evaluations = t.evaluations;
    return p;
}

} // namespace

std::vector<Scheme> unsplit_schemes(const WorkPrecisionOptions& o) {
    std::vector<Scheme> unsplit;
    if (!o.unsplit_too) return unsplit;
    for (Scheme s : {Scheme::central_difference, Scheme::rk4})
        if (std::find(o.schemes.begin(), o.schemes.end(), s) != o.schemes.end())
            unsplit.push_back(s);
    return unsplit;
}

WorkPrecision work_precision(const Dynamics& dyn, const WorkPrecisionOptions& o,
                             const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    validate(o);
    WorkPrecision study;
    const StepPlan reference_plan = reference_plan_for(dyn);
    require_affordable_study(dyn, o, reference_plan);
    const std::vector<Scheme> unsplit = unsplit_schemes(o);
    // Each run reports its own fraction; the study's counts the runs before it.
    const std::size_t plans = (o.schemes.size() + unsplit.size()) * o.tolerances.size();
    const double runs = 1.0 + static_cast<double>(plans) * o.repeats;
    double runs_done = 0.0;
    const auto next_run = [&](const StepPlan& plan) {
        std::optional<Trajectory> t = integrate(dyn, plan, o.periods, [&](double f) {
            return !progress || progress((runs_done + f) / runs);
        });
        runs_done += 1.0;
        if (!t) study.cancelled = true;
        return t;
    };
    const std::optional<Trajectory> reference_run = next_run(reference_plan);
    if (!reference_run) return study;
    const Trajectory& reference = *reference_run;
    study.F_m_reference = reference.F_m;
    study.F_m_reference_error = exact_F_m_round_off * reference.F_m;

    auto measure = [&](Scheme scheme, bool split, double tolerance) {
        if (study.cancelled) return;
        StepPlan plan = plan_step(dyn, scheme, tolerance);
        plan.split_at_switches = split;
        std::vector<double> seconds;
        Trajectory t;
        for (int r = 0; r < o.repeats; ++r) {
            std::optional<Trajectory> repeat = next_run(plan);
            if (!repeat) return;
            t = std::move(*repeat);
            seconds.push_back(t.seconds);
        }
        std::sort(seconds.begin(), seconds.end());
        WorkPrecisionPoint p = against_reference(t, reference);
        p.scheme = scheme;
        p.split = split;
        p.tolerance = tolerance;
        p.step = plan.step;
        p.wall_time_s = seconds[seconds.size() / 2];
        study.points.push_back(p);
    };
    for (Scheme scheme : o.schemes)
        for (double tol : o.tolerances)
            measure(scheme, true, tol);
    for (Scheme scheme : unsplit)
        for (double tol : o.tolerances)
            measure(scheme, false, tol);
    study.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return study;
}

std::optional<WorkPrecisionPoint> fastest_for(const WorkPrecision& study, double target) {
    std::optional<WorkPrecisionPoint> best;
    for (const auto& p : study.points)
        if (p.split && p.F_m_error <= target && (!best || p.wall_time_s < best->wall_time_s))
            best = p;
    return best;
}

std::optional<double> observed_order(const WorkPrecision& study, Scheme scheme, bool split) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (const auto& p : study.points) {
        // A relative error at the reference's own round-off is not resolved: it has no order.
        if (p.scheme != scheme || p.split != split || !(p.F_m_error > exact_F_m_round_off))
            continue;
        const double x = std::log(p.step), y = std::log(p.F_m_error);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
        ++n;
    }
    if (n < 3) return std::nullopt;
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

} // namespace gapchain
