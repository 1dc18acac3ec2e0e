#include "gapchain/bifurcation.hpp"

#include "detail/check.hpp"
#include "gapchain/observers.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace gapchain {

SweptParameter parse_swept_parameter(std::string_view name) {
    if (name == "f_r") return SweptParameter::f_r;
    if (name == "e_r") return SweptParameter::e_r;
    if (name == "fc") return SweptParameter::fc;
    if (name == "eps") return SweptParameter::eps;
    throw std::invalid_argument("--param: must be one of f_r, e_r, fc, eps, got \"" +
                                std::string(name) + "\"");
}

std::string_view to_string(SweptParameter p) {
    switch (p) {
    case SweptParameter::f_r: return "f_r";
    case SweptParameter::e_r: return "e_r";
    case SweptParameter::fc: return "fc";
    case SweptParameter::eps: return "eps";
    }
    return "?";
}

SweepMode parse_sweep_mode(std::string_view name) {
    if (name == "independent") return SweepMode::independent;
    if (name == "continuation") return SweepMode::continuation;
    throw std::invalid_argument("--mode: must be independent or continuation, got \"" +
                                std::string(name) + "\"");
}

std::string_view to_string(SweepDirection d) {
    return d == SweepDirection::up ? "up" : "down";
}

namespace {

ReducedParameters with_value(ReducedParameters p, SweptParameter which, double value) {
    switch (which) {
    case SweptParameter::f_r: p.f_r = value; break;
    case SweptParameter::e_r: p.e_r = value; break;
    case SweptParameter::fc: p.fc = value; break;
    case SweptParameter::eps: p.eps = value; break;
    }
    return p;
}

double value_at(const BifurcationOptions& o, int k) {
    if (o.steps == 1) return o.from;
    return o.from + (o.to - o.from) * static_cast<double>(k) / (o.steps - 1);
}

/// One value: run transient + record periods from y (updated to the end state).
BifurcationRow diagram_row(const ReducedParameters& p, const BifurcationOptions& o,
                           std::vector<double>& y, SweepDirection direction, double value) {
    const Dynamics dyn(Chain::homogeneous(p), {p.f_r, 1.0});
    const StepPlan plan = plan_step(dyn, o.scheme, o.tolerance);
    auto stepper = make_stepper(plan, dyn);
    BifurcationRow row;
    row.value = value;
    row.direction = direction;
    row.points.reserve(static_cast<std::size_t>(o.record_periods));
    PoincareSampler sampler(dyn, o.section,
                            [&row](const SectionPoint& s) { row.points.push_back(s); });
    MaxForceTracker forces(dyn);
    Observer* observers[] = {&sampler, &forces};
    const RunSpan span{o.transient_periods + o.record_periods, o.transient_periods, 0.0};
    const RunOutcome outcome = run(dyn, *stepper, plan, span, y, observers);
    row.status = outcome.status;
    for (const auto& c : forces.contacts())
        row.F_m = std::max(row.F_m, c.force);
    row.period = detect_period(row.points, o.max_period, o.period_tolerance);
    return row;
}

} // namespace

void validate(const BifurcationOptions& o, const ReducedParameters& base) {
    detail::require_range("--steps", o.steps, 1, 10'000'000);
    detail::require_range("--transient", static_cast<double>(o.transient_periods), 0.0, 1e9);
    detail::require_range("--record", static_cast<double>(o.record_periods), 1.0, 1e9);
    detail::require_range("--max-period", o.max_period, 1, 1000);
    detail::require_range("--period-tolerance", o.period_tolerance, 0.0, 1.0,
                          detail::Bound::open_low);
    detail::require_range("--threads", o.threads, 0, 4096);
    detail::require_range("--tolerance", o.tolerance, 1e-12, 0.1);
    // Both ends must make a valid row; validate() names the parameter and its range.
    validate(with_value(base, o.parameter, o.from));
    validate(with_value(base, o.parameter, o.to));
    validate(o.section, base.Nm);
}

int detect_period(const std::vector<SectionPoint>& points, int max_period, double tolerance) {
    const auto n = static_cast<int>(points.size());
    double scale = 0.0;
    for (const auto& p : points)
        for (double v : p.values)
            scale = std::max(scale, std::abs(v));
    const double tol = tolerance * (1.0 + scale);
    for (int k = 1; k <= max_period && 2 * k <= n; ++k) {
        bool repeats = true;
        for (int i = 0; i + k < n && repeats; ++i)
            for (std::size_t c = 0; c < points[i].values.size(); ++c)
                if (std::abs(points[i].values[c] - points[i + k].values[c]) > tol) {
                    repeats = false;
                    break;
                }
        if (repeats) return k;
    }
    return 0;
}

BifurcationResult bifurcation(const ReducedParameters& base, const BifurcationOptions& o,
                              const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    validate(o, base);
    BifurcationResult result;
    const int dim = 2 * base.Nm;
    if (o.mode == SweepMode::independent) {
        result.rows.resize(static_cast<std::size_t>(o.steps));
        const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
        result.threads_used = threads;
        int done = 0;
        bool cancelled = false;
        std::string failure;
        // Each value is computed from rest into its own slot, so the rows do not depend on the
        // number of threads or on the order in which they finish.
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
        for (int k = 0; k < o.steps; ++k) {
            try {
                const double value = value_at(o, k);
                std::vector<double> y(dim, 0.0);
                result.rows[k] = diagram_row(with_value(base, o.parameter, value), o, y,
                                             SweepDirection::up, value);
            } catch (const std::exception& e) {
#pragma omp critical(gapchain_bifurcation_failure)
                failure = e.what();
            }
#pragma omp critical(gapchain_bifurcation_progress)
            {
                ++done;
                if (progress && !cancelled)
                    cancelled = !progress(static_cast<double>(done) / o.steps);
            }
        }
        if (!failure.empty()) throw std::runtime_error(failure);
    } else {
        std::vector<double> y(dim, 0.0);
        const int total = 2 * o.steps;
        int done = 0;
        for (SweepDirection dir : {SweepDirection::up, SweepDirection::down}) {
            for (int i = 0; i < o.steps; ++i) {
                const int k = dir == SweepDirection::up ? i : o.steps - 1 - i;
                const double value = value_at(o, k);
                result.rows.push_back(
                    diagram_row(with_value(base, o.parameter, value), o, y, dir, value));
                // A run that blew up cannot seed the next value: restart that one from rest.
                if (result.rows.back().status == RunStatus::non_finite)
                    std::fill(y.begin(), y.end(), 0.0);
                if (progress) progress(static_cast<double>(++done) / total);
            }
        }
    }
    result.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

} // namespace gapchain
