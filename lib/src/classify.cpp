#include "gapchain/classify.hpp"

#include "detail/check.hpp"
#include "gapchain/bifurcation.hpp"
#include "gapchain/lyapunov.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/poincare.hpp"
#include "gapchain/signal.hpp"
#include "gapchain/spectrum.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace gapchain {

std::string_view to_string(Regime regime) {
    switch (regime) {
    case Regime::no_contact: return "no-contact";
    case Regime::periodic: return "periodic";
    case Regime::quasi_periodic: return "quasi-periodic";
    case Regime::chaotic: return "chaotic";
    }
    return "?";
}

void validate(const ClassifyOptions& o) {
    detail::require_range("--transient", static_cast<double>(o.transient_periods), 0.0, 1e9);
    detail::require_range("--record", static_cast<double>(o.record_periods), 10.0, 1e9);
    detail::require_range("--tolerance", o.tolerance, 1e-12, 0.1);
    detail::require_range("--max-period", o.max_period, 1, 1000);
    detail::require_range("period_tolerance", o.period_tolerance, 0.0, 1.0,
                          detail::Bound::open_low);
    detail::require_range("steady_tolerance", o.steady_tolerance, 0.0, 1.0,
                          detail::Bound::open_low);
    detail::require_range("samples_per_period", o.samples_per_period, 4, 4096);
    detail::require_range("chaos_threshold", o.chaos_threshold, 0.0, 1e6);
}

namespace {

int distinct_values(std::vector<double> v, double tolerance) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    double scale = 1.0;
    for (double x : v)
        scale = std::max(scale, std::abs(x));
    int distinct = 1;
    for (std::size_t i = 1; i < v.size(); ++i)
        if (v[i] - v[i - 1] > tolerance * scale) ++distinct;
    return distinct;
}

} // namespace

Classification classify(const ReducedParameters& p, const ClassifyOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    validate(o);
    validate(p);
    const Dynamics dyn(Chain::homogeneous(p), {p.f_r, 1.0});
    RunOptions run_options;
    run_options.periods = o.transient_periods + o.record_periods;
    run_options.transient_periods = o.transient_periods;
    run_options.scheme = o.scheme;
    run_options.tolerance = o.tolerance;
    const StepPlan plan = plan_for_sampling(dyn, run_options, o.samples_per_period);
    auto stepper = make_stepper(plan, dyn);

    // Phase 1, settling: up to transient_periods, stopped as soon as a periodic steady state
    // is found. The tangent vector rides along; for a periodic point its average over this
    // phase is the evidence of contraction.
    std::vector<double> y(dyn.dimension(), 0.0);
    TangentObserver tangent(dyn, 1, 0);
    SteadyStateDetector steady(dyn.dimension(), o.max_period, o.steady_tolerance, 0);
    Classification c;
    double t = 0.0;
    if (o.transient_periods > 0) {
        Observer* settling[] = {&steady, &tangent};
        const RunOutcome first =
            run(dyn, *stepper, plan, {o.transient_periods, 0, 0.0}, y, settling);
        c.periods_run = first.periods_done;
        c.status = first.status;
        if (first.status == RunStatus::non_finite) return c;
        t = first.t_end;
    }
    const LyapunovResult settling_lyap = tangent.result();

    // Phase 2, recording: one whole cycle of a periodic state, else record_periods, with the
    // forces, the stroboscopic section, u_1 and (restarted averages of) the tangent vector.
    const bool periodic_state = steady.period().has_value();
    const long record = periodic_state ? *steady.period() : o.record_periods;
    MaxForceTracker forces(dyn);
    std::vector<SectionPoint> section;
    PoincareSampler sampler(dyn, SectionSpec{},
                            [&](const SectionPoint& s) { section.push_back(s); });
    Signal u1;
    SignalRecorder recorder(dyn, SectionVariable{}, dyn.period() / o.samples_per_period, u1);
    Observer* recording[] = {&forces, &tangent, &sampler, &recorder};
    const RunOutcome outcome = run(dyn, *stepper, plan, {record, 0, t}, y, recording);
    c.periods_run += outcome.periods_done;
    c.status = outcome.status;
    if (outcome.status == RunStatus::non_finite) return c;
    const LyapunovResult lyap = periodic_state ? settling_lyap : tangent.result();
    c.lambda_max = lyap.exponents.front();
    c.lambda_max_error = lyap.errors.front();
    for (const auto& m : forces.contacts())
        c.F_m = std::max(c.F_m, m.force);
    std::vector<double> strobe;
    for (const auto& s : section)
        strobe.push_back(s.values.front());
    c.section_points = static_cast<int>(strobe.size());
    c.distinct_points = distinct_values(strobe, o.period_tolerance);
    long impacts = 0;
    for (const auto& m : forces.contacts())
        impacts += m.impacts;

    if (periodic_state) {
        c.stopped_at_steady_state = true;
        c.period = *steady.period();
        c.regime = (c.F_m > 0.0 || impacts > 0) ? Regime::periodic : Regime::no_contact;
    } else {
        if (u1.values.size() >= 256) {
            PsdOptions po;
            po.sample_rate = u1.sample_rate;
            int length = 256;
            while (2 * length <= static_cast<int>(u1.values.size()) / 4)
                length *= 2;
            po.segment_length = length;
            c.broadband_share = spectral_content(welch_psd(u1.values, po), p.f_r).broadband_share;
        }
        const int period = detect_period(section, o.max_period, o.period_tolerance);
        // lambda_max is clearly positive (chaos), clearly negative (an attracting cycle, of
        // period > max_period if none was found) or indistinguishable from 0 (a torus).
        const double margin = std::max(o.chaos_threshold, 3.0 * c.lambda_max_error);
        if (c.F_m == 0.0 && impacts == 0) {
            c.regime = Regime::no_contact;
            c.period = period;
        } else if (c.lambda_max > margin) {
            c.regime = Regime::chaotic;
        } else if (period > 0 || c.lambda_max < -margin) {
            c.regime = Regime::periodic;
            c.period = period;
        } else {
            c.regime = Regime::quasi_periodic;
        }
    }
    c.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return c;
}

RegimeMap regime_map(const ReducedParameters& base, const std::vector<double>& e_r,
                     const std::vector<double>& f_r, const ClassifyOptions& o, int threads,
                     const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    validate(o);
    detail::require_range("--threads", threads, 0, 4096);
    if (e_r.empty() || f_r.empty())
        throw std::invalid_argument("--e_r, --f_r: need at least one value each");
    for (double e : e_r)
        validate(ReducedParameters{base.Nm, base.fc, base.eps, e, base.f_r});
    for (double f : f_r)
        validate(ReducedParameters{base.Nm, base.fc, base.eps, base.e_r, f});
    RegimeMap map;
    map.e_r = e_r;
    map.f_r = f_r;
    const long cells = static_cast<long>(e_r.size() * f_r.size());
    map.cells.resize(cells);
    map.threads_used = threads > 0 ? threads : omp_get_max_threads();
    long done = 0;
    std::string failure;
#pragma omp parallel for schedule(dynamic, 1) num_threads(map.threads_used)
    for (long k = 0; k < cells; ++k) {
        try {
            ReducedParameters p = base;
            p.e_r = e_r[k / f_r.size()];
            p.f_r = f_r[k % f_r.size()];
            map.cells[k] = classify(p, o);
        } catch (const std::exception& e) {
#pragma omp critical(gapchain_map_failure)
            failure = e.what();
        }
#pragma omp critical(gapchain_map_progress)
        {
            ++done;
            if (progress) progress(static_cast<double>(done) / cells);
        }
    }
    if (!failure.empty()) throw std::runtime_error(failure);
    map.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return map;
}

} // namespace gapchain
