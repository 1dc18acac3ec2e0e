#include "gapchain/classify.hpp"

#include "gapchain/orbit.hpp"

#include "detail/accuracy_policy.hpp"
#include "detail/check.hpp"
#include "detail/parallel.hpp"
#include "gapchain/lyapunov.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/poincare.hpp"
#include "gapchain/signal.hpp"
#include "gapchain/spectrum.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>

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
    detail::require_count("transient_periods", o.transient_periods, 0, 1'000'000'000);
    // Fewer than 20 recorded periods leave lambda_max without an error (its 10 blocks need
    // them): the margin was then infinite and every non-repeating record, chaotic or not, was
    // labelled quasi-periodic ("lambda_max = -1.19 +- inf" on a row settling on period 2).
    detail::require_count("record_periods", o.record_periods, 20, 1'000'000'000);
    detail::require_run_length(o.transient_periods, o.record_periods);
    detail::require_range("tolerance", o.tolerance, 1e-12, 0.1);
    detail::require_range("max_period", o.max_period, 1, 1000);
    detail::require_range("period_tolerance", o.period_tolerance, 0.0, 1.0,
                          detail::Bound::open_low);
    detail::require_range("steady_tolerance", o.steady_tolerance, 0.0, 1.0,
                          detail::Bound::open_low);
    detail::require_range("samples_per_period", o.samples_per_period, 4, 4096);
    detail::require_range("chaos_threshold", o.chaos_threshold, 0.0, 1e6);
    // The recorded samples of u_1 (8 bytes each, twice samples_per_period a period) and section
    // points (~64 bytes each) are held in memory (per thread in a map): refuse up front what
    // would end in bad_alloc.
    const double per_period = 16.0 * o.samples_per_period + 64;
    const double bytes = static_cast<double>(o.record_periods) * per_period;
    if (bytes > 4e9)
        throw std::invalid_argument(
            "record_periods: " + std::to_string(o.record_periods) +
            " recorded periods hold about " + detail::format_number(std::ceil(bytes * 1e-9)) +
            " GB of samples; at most 4 GB (about " +
            detail::format_number(std::floor(4e9 / per_period)) + " periods here)");
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

/// The evidence of phase 2 (recording) that decides a non-periodic label.
struct RecordedEvidence {
    std::vector<SectionPoint> section;
    Signal u1; ///< at twice samples_per_period
    long impacts = 0;
};

/// Share of u_1's spectral power away from the forcing's harmonics and subharmonics, and its
/// error, from u_1 recorded at twice the asked rate: the share is read on every other sample;
/// its error is the segments' spread (broadband_share_error()) plus the power the asked rate
/// folds back (aliased_share()), which can land away from the fractions, plus the move on
/// segments of half the periods (broadband_share_resolution_error()). Too short a record
/// (fewer than 256 asked samples, or segments so short that most bins lie next to some m/n
/// f_r) is not read: 0, error NaN.
std::pair<double, double> broadband_reading(const Signal& fine, double f_r,
                                            int samples_per_period) {
    const Signal u1 = every_other(fine);
    if (u1.values.size() < 256) return {0.0, std::numeric_limits<double>::quiet_NaN()};
    PsdOptions po;
    po.sample_rate = u1.sample_rate;
    // Whole periods, as gapchain-spectrum's default: the lines fall on bins and do not leak
    // into the share; four segments at least, for its error.
    po.segment_length =
        whole_period_segment(static_cast<long>(u1.values.size()), samples_per_period, 4, 4);
    const SpectralContent content = spectral_content(welch_psd(u1.values, po), f_r);
    // Segments of few periods leave the share little to read (20 recorded periods read
    // 0.000 +- 3e-5 on a chaotic row whose share is 0.04, a second reader found).
    if (content.fraction_bin_share > 0.5) return {0.0, std::numeric_limits<double>::quiet_NaN()};
    return {content.broadband_share,
            broadband_share_error(u1.values, po, f_r) + aliased_share(fine.values, po) +
                broadband_share_resolution_error(u1.values, po, content.broadband_share, f_r, 4,
                                                 samples_per_period)};
}

/// The label of a run that did not settle: lambda_max clearly positive (chaos), clearly
/// negative (an attracting cycle, of period > max_period if none was found) or
/// indistinguishable from 0 (a torus).
void label_unsettled(const ClassifyOptions& o, const RecordedEvidence& evidence, double f_r,
                     Classification& c) {
    std::tie(c.broadband_share, c.broadband_share_error) =
        broadband_reading(evidence.u1, f_r, o.samples_per_period);
    // The repetition test reads the record's second half: an attracting orbit the run is still
    // approaching (a multiplier of 0.73 per 3 periods on Nm = 3, fc = 200, e_r = 0.03, f_r = 5.5)
    // repeats there to period_tolerance, and a torus or chaos does not repeat in either half.
    const std::vector<SectionPoint> settled(
        evidence.section.begin() + static_cast<std::ptrdiff_t>(evidence.section.size() / 2),
        evidence.section.end());
    int period = detect_period(settled, o.max_period, o.period_tolerance);
    // A cycle longer than max_period that attracts (lambda_max 3 errors below 0, where a torus
    // reads 0) is searched for too: Fig 13's row at f_r = 2.55 settles on a stable period-20
    // orbit (|mu| 0.930, lambda -0.0093 +- 1e-7, 20 distinct section points of 3000) and read
    // quasi-periodic, being above -chaos_threshold.
    const auto longest = static_cast<int>(std::min<std::size_t>(1000, settled.size() / 4));
    if (period == 0 && longest > o.max_period && std::isfinite(c.lambda_max_error) &&
        c.lambda_max < -3.0 * c.lambda_max_error)
        period = detect_period(settled, longest, o.period_tolerance);
    const double margin = std::max(o.chaos_threshold, 3.0 * c.lambda_max_error);
    if (c.F_m == 0.0 && evidence.impacts == 0) {
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

/// The run of classify(): transient_periods, then record_periods, at the options' accuracy.
RunOptions classify_run_options(const Dynamics& dyn, const ClassifyOptions& o) {
    RunOptions run_options;
    run_options.periods = o.transient_periods + o.record_periods;
    run_options.transient_periods = o.transient_periods;
    // lambda_max of a run that does not settle decides chaotic against quasi-periodic, and it
    // comes from the tangent flow along this run: on rk4's trajectory through stiff contacts it
    // is biased (Fig 13's row at fc = 1e5, f_r = 2.5: +1.60 +- 0.07 against 1.13-1.19 from
    // rk8pd at 1e-8, rk4 at 1e-6 and the exact propagator), so the run takes the scheme the
    // Lyapunov spectrum takes.
    run_options.scheme = o.scheme;
    run_options.tolerance = o.tolerance;
    run_options.max_work = o.max_work;
    return tangent_run_options(dyn, run_options);
}

/// Counts the stroboscopic section's points, and its distinct first values, into c.
void count_section_points(const std::vector<SectionPoint>& section, double tolerance,
                          Classification& c) {
    std::vector<double> strobe;
    for (const auto& s : section)
        strobe.push_back(s.values.front());
    c.section_points = static_cast<int>(strobe.size());
    c.distinct_points = distinct_values(strobe, tolerance);
}

long total_impacts(const MaxForceTracker& forces) {
    long impacts = 0;
    for (const auto& m : forces.contacts())
        impacts += m.impacts;
    return impacts;
}

/// A periodic label checked by Newton on the k-period map from the state at the end of the run
/// (a period boundary, so phase 0): a multiplier near -1 can make the approach repeat after 2k
/// periods before it repeats after k; the converged orbit's minimal period settles it.
void confirm_periodic(const Dynamics& dyn, const std::vector<double>& state, double max_work,
                      Classification& c) {
    // A row the exact scheme refuses, or a shooting beyond the limit the run kept to, leaves the
    // label unconfirmed.
    const auto found = confirm_periodic_orbit(dyn, c.period, state, max_work);
    if (!found || found->status != OrbitStatus::converged) return;
    const PeriodicOrbit& orbit = *found;
    c.newton_confirmed = true;
    c.period = orbit.minimal_period;
    c.max_multiplier = orbit.max_multiplier;
    // The orbit's exponent is its largest multiplier's, as the attractor search reports it. The
    // tangent average of the run is biased where rk4 crosses stiff contacts: +0.47 +- 1.1 on
    // Fig 13's row at fc = 3e6, f_r = 3, where the orbit's |mu| = 0.382 gives -2.89.
    c.lambda_max = std::log(orbit.max_multiplier) / (orbit.minimal_period * dyn.period());
    c.lambda_max_error =
        orbit.max_multiplier_error / (orbit.max_multiplier * orbit.minimal_period * dyn.period());
    // The record's maximum is the orbit's only once the run has reached it; a run still on its
    // way took a larger one (0.877712 +- 0.00073 against the orbit's 0.874235 at Nm = 3,
    // fc = 1094.253, eps = 0.05, e_r = 0.164487, f_r = 2.47593, on the build of 2026-11-26).
    // The regime's F_m is the orbit's, and its error bar covers the record's.
    c.F_m_error = std::max(c.F_m_error, std::abs(c.F_m - orbit.F_m));
    c.F_m = orbit.F_m;
    // Impacts in the record that the orbit does not have were the start-up's.
    if (orbit.F_m == 0.0) c.regime = Regime::no_contact;
}

/// The period in 1 .. max_period over which the record's last section point comes back closest
/// (max norm) to an earlier one: the candidate for a stable cycle a run is still approaching
/// (the distance falls as |mu| per cycle at the cycle's period, stays of the orbit's size at
/// others); 0 for a record too short.
int closest_return_period(const std::vector<SectionPoint>& section, int max_period) {
    int best = 0;
    double closest = std::numeric_limits<double>::infinity();
    const std::vector<double>& last = section.back().values;
    for (int p = 1; p <= max_period && static_cast<std::size_t>(p) < section.size(); ++p) {
        const std::vector<double>& earlier = section[section.size() - 1 - p].values;
        double distance = 0.0;
        for (std::size_t k = 0; k < last.size(); ++k)
            distance = std::max(distance, std::abs(last[k] - earlier[k]));
        if (distance < closest) {
            closest = distance;
            best = p;
        }
    }
    return best;
}

/// A run whose exponent says it approaches a stable cycle (label periodic) that did not repeat
/// to period_tolerance within the record: Newton from the end state on the closest return's
/// period (closest_return_period()). Fig 13's row at f_r = 2.25 (|mu| 0.976 per period) kept
/// 228 distinct section points of 300 after 400 periods and read "period 0: longer than max",
/// F_m 1.12595 +- 0.0023; its period-1 orbit's is 1.12358. Unconfirmed, the label stays so.
void confirm_approached_cycle(const Dynamics& dyn, const ClassifyOptions& o,
                              const std::vector<SectionPoint>& section,
                              const std::vector<double>& end_state, Classification& c) {
    if (!o.confirm_by_newton || c.regime != Regime::periodic || c.period != 0 || section.empty())
        return;
    c.period = closest_return_period(section, o.max_period);
    if (c.period == 0) return;
    confirm_periodic(dyn, end_state, o.max_work, c);
    if (!c.newton_confirmed) c.period = 0;
}

/// Whether Newton is to confirm the state c settled on: a periodic one, or a no-contact one,
/// the linear row's orbit, whose exponent Newton gives exactly where the settling run's short
/// tangent average read -3.08 +- inf for -pi (the probe of 2026-11-26).
bool newton_confirms(const ClassifyOptions& o, const Classification& c) {
    return o.confirm_by_newton && c.period > 0 &&
           (c.regime == Regime::periodic || c.regime == Regime::no_contact);
}

/// F_m, its error (the halves' spread and, for a record that does not repeat, the spread of
/// its per-period maxima's tail; at least the tolerance) and the impacts, into c and evidence.
void take_forces(const MaxForceTracker& forces, double tolerance, bool repeats,
                 RecordedEvidence& evidence, Classification& c) {
    c.F_m = forces.max_force();
    c.F_m_error = forces.window_error(tolerance, repeats);
    evidence.impacts = total_impacts(forces);
}

/// A record that turned periodic while recording (labelled so from its section points)
/// repeats: its per-period maxima take k values, no tail to read; F_m_error without it.
void drop_tail_if_periodic(const MaxForceTracker& forces, double tolerance, Classification& c) {
    if (c.regime == Regime::periodic && c.period > 0)
        c.F_m_error = forces.window_error(tolerance, true);
}

/// The regime of a point that settled on a cycle of `period` periods (periodic or no contact),
/// or else from the recorded evidence.
void label_regime(const ClassifyOptions& o, const RecordedEvidence& evidence, double f_r,
                  std::optional<int> period, Classification& c) {
    if (!period) {
        label_unsettled(o, evidence, f_r, c);
        return;
    }
    c.stopped_at_steady_state = true;
    c.period = *period;
    c.regime = (c.F_m > 0.0 || evidence.impacts > 0) ? Regime::periodic : Regime::no_contact;
}

/// The fewest periods over which a periodic label's exponent is measured on its orbit (without
/// Newton, or where Newton does not confirm it): its 10 blocks' error needs them.
constexpr long min_orbit_exponent_periods = 20;

/// Whole cycles of a period-`period` orbit that span min_orbit_exponent_periods.
long orbit_exponent_cycles(int period) {
    return (min_orbit_exponent_periods + period - 1) / period;
}

/// Refuses a map of more than 1e6 cells (days of work, and more than fits in memory: larger
/// studies are sweeps, resumable and sharded), or whose cells, each run to its full length
/// (a periodic one stops sooner), exceed run.max_work together: a 3000 x 3000 map from Python
/// and a 1000 x 1000 one of 100,000 recorded periods from the tool were accepted with
/// estimates of days. A cell that does not settle runs its twin too, as long again: counted,
/// so that a map of unsettled cells keeps to the limit.
void require_map_work(const ReducedParameters& base, std::size_t rows,
                      const std::vector<double>& f_r, const ClassifyOptions& o) {
    const double cells = static_cast<double>(rows) * static_cast<double>(f_r.size());
    if (cells > 1e6)
        throw std::invalid_argument("e_r, f_r: " + detail::format_number(cells) +
                                    " map cells; at most 1e6 (a sweep with \"keep\": "
                                    "[\"regime\"] runs larger studies)");
    // A cell that settles at the record's end runs its cycle on: one (up to max_period
    // periods), or without Newton at least 20 periods of it (record_cycle(); a reread,
    // helper-86: such a cell could run twice the estimate). Where Newton does not confirm the
    // cycle, at least 20 periods more (measure_unconfirmed_exponent()).
    const long at_most = min_orbit_exponent_periods + o.max_period;
    const long cycle = o.confirm_by_newton ? at_most + o.max_period : at_most;
    const double periods = static_cast<double>(o.transient_periods + o.record_periods + cycle);
    double body_steps = 0.0;
    for (double f : f_r) {
        const Dynamics dyn = Dynamics::paper_row({base.Nm, base.fc, base.eps, base.e_r, f});
        body_steps +=
            static_cast<double>(rows) *
            run_work(dyn, plan_run(dyn, classify_run_options(dyn, o), 2 * o.samples_per_period),
                     periods);
    }
    const double runs_per_cell = o.twin_check ? 2.0 : 1.0;
    detail::require_work(runs_per_cell * body_steps, o.max_work, "this map runs up to",
                         detail::format_number(cells) + " cells of " +
                             detail::format_number(periods) + " periods at full length" +
                             (o.twin_check ? ", each with its twin" : ""),
                         "fewer cells, a shorter record or settling, no twin, or raise "
                         "run.max_work");
}

/// As gapchain-sim says it: a lightly damped row's start-up outlasts the default transient,
/// and its record then labels the start-up (a settled label cannot be the start-up's).
void flag_start_up(const Dynamics& dyn, const ClassifyOptions& o, Classification& c) {
    if (c.regime != Regime::quasi_periodic && c.regime != Regime::chaotic) return;
    c.start_up_periods = start_up_decay_periods(dyn, o.tolerance);
    c.start_up_in_record = o.transient_periods < c.start_up_periods;
}

/// A stroboscopic section recording the whole state.
SectionSpec whole_state_section(int bodies) {
    SectionSpec spec;
    spec.record = SectionVariable::whole_state(bodies);
    return spec;
}

/// The observers of a record and what they keep: the forces (split in halves at `split`
/// periods, -1: not split), the stroboscopic section and u_1 at twice the asked rate.
struct Recording {
    Recording(const Dynamics& dyn, const ClassifyOptions& o, long split)
        : forces(dyn, split),
          sampler(dyn, SectionSpec{},
                  [this](const SectionPoint& s) { evidence.section.push_back(s); }),
          recorder(dyn, SectionVariable{}, dyn.period() / (2 * o.samples_per_period), evidence.u1) {
        if (o.keep_section_states)
            state_sampler.emplace(dyn, whole_state_section(dyn.bodies()),
                                  [this](const SectionPoint& s) { states.push_back(s.values); });
    }
    /// Its observers, to run with the phase's own.
    std::vector<Observer*> observers() {
        std::vector<Observer*> list{&forces, &sampler, &recorder};
        if (state_sampler) list.push_back(&*state_sampler);
        return list;
    }
    RecordedEvidence evidence;
    MaxForceTracker forces;
    PoincareSampler sampler;
    SignalRecorder recorder;
    std::vector<std::vector<double>> states; ///< with keep_section_states: the whole states
    std::optional<PoincareSampler> state_sampler;
};

/// Whether a phase's outcome ends the classification (the run went non-finite or was
/// cancelled), after adding its periods and status to c.
bool phase_ends(const RunOutcome& outcome, Classification& c) {
    c.periods_run += outcome.periods_done;
    c.status = outcome.status;
    return outcome.status == RunStatus::non_finite || outcome.status == RunStatus::cancelled;
}

/// The label of a record (of a cycle where the state settled, period), its evidence and
/// checks into c: the exponent, the forces (the bar covering a transient's maximum before a
/// settle in the record), the section, Newton from end_state and the start-up's flag.
void label_recorded(const Dynamics& dyn, double f_r, const ClassifyOptions& o,
                    const std::vector<double>& end_state, Recording& record,
                    std::optional<int> period, const LyapunovResult& lyap, double transient_maximum,
                    Classification& c) {
    c.lambda_max = lyap.exponents.front();
    c.lambda_max_error = lyap.errors.front();
    take_forces(record.forces, o.tolerance, period.has_value(), record.evidence, c);
    // The record's maximum before it settled was the transient's: the label's F_m is the
    // cycle's, and its error bar covers the record's, as for a confirmed orbit (and as
    // gapchain-sim's for a run that settled late).
    c.F_m_error = std::max(c.F_m_error, transient_maximum - c.F_m);
    count_section_points(record.evidence.section, o.period_tolerance, c);
    label_regime(o, record.evidence, f_r, period, c);
    if (!period) drop_tail_if_periodic(record.forces, o.tolerance, c);
    if (newton_confirms(o, c))
        confirm_periodic(dyn, end_state, o.max_work, c);
    else
        confirm_approached_cycle(dyn, o, record.evidence.section, end_state, c);
    flag_start_up(dyn, o, c);
}

/// One whole cycle of a periodic state from t, into a fresh record; whether it ended the
/// classification (phase_ends()). After a settle in the record the exponent is restarted
/// there: the average so far is the transient's (+0.68 +- 0.19 on a period-1 orbit of the
/// Nm = 6 row); over one cycle it has no error (null) until Newton gives it. Without Newton the
/// cycles run on to at least 20 periods, the exponent restarted at the settle.
bool record_cycle(const Dynamics& dyn, const ClassifyOptions& o, int period, double& t,
                  const ProgressCallback& keep_going, PlannedRun& planned,
                  std::optional<Recording>& record, LyapunovResult& lyap, Classification& c) {
    record.emplace(dyn, o, -1);
    // Without Newton the exponent is the orbit's own: restarted at the settle and averaged over
    // whole cycles of at least 20 periods, which its 10 blocks' error needs. A settle in the
    // discarded periods kept their average, the transient's, and a settle in the record one
    // cycle's: Python classify(confirm=False) read +0.625 (no error) and +0.125 +- 0.39 on
    // orbits whose multipliers give -0.169 and -0.553 (a hostile probe, helper-85). With Newton
    // to come, one cycle (no tangent where the settle was in the discarded periods).
    const bool orbit_exponent = !o.confirm_by_newton;
    const long cycles = orbit_exponent ? orbit_exponent_cycles(period) : 1;
    TangentObserver restarted(dyn, 1, 0);
    std::vector<Observer*> cycle = record->observers();
    if (c.settled_in_record || orbit_exponent) cycle.push_back(&restarted);
    const RunOutcome outcome = planned.run({cycles * period, 0, t}, cycle, keep_going);
    if (phase_ends(outcome, c)) return true;
    t = outcome.t_end;
    if (c.settled_in_record || orbit_exponent) lyap = restarted.result();
    return false;
}

/// Where Newton was asked for but did not confirm a settled periodic (or contact-free) state
/// (no convergence, an unstable orbit, a row the exact scheme refuses, a shooting beyond
/// run.max_work), the exponent measured on the orbit as without Newton: restarted at t and
/// averaged over whole cycles of at least 20 periods. It was one cycle's, with no error (or the
/// transient's average), where the orbit's is negative. A run of those cycles beyond
/// run.max_work leaves it so, as does a run of them that ends the classification.
void measure_unconfirmed_exponent(const Dynamics& dyn, const ClassifyOptions& o, int period,
                                  double t, const ProgressCallback& keep_going, PlannedRun& planned,
                                  Classification& c) {
    if (!o.confirm_by_newton || c.newton_confirmed ||
        (c.regime != Regime::periodic && c.regime != Regime::no_contact))
        return;
    const long periods = orbit_exponent_cycles(period) * period;
    if (run_work(dyn, planned.plan(), static_cast<double>(periods), 1) > o.max_work) return;
    TangentObserver restarted(dyn, 1, 0);
    Observer* cycles[] = {&restarted};
    if (phase_ends(planned.run({periods, 0, t}, cycles, keep_going), c)) return;
    const LyapunovResult lyap = restarted.result();
    c.lambda_max = lyap.exponents.front();
    c.lambda_max_error = lyap.errors.front();
}

/// One classification of the row from `initial` (classify() without the twin).
Classification classify_from(const Dynamics& dyn, double f_r, const ClassifyOptions& o,
                             const std::vector<double>& initial,
                             const ProgressCallback& keep_going) {
    const RunOptions run_options = classify_run_options(dyn, o);
    // u_1 is recorded at twice the asked rate (broadband_reading()).
    PlannedRun planned(dyn, run_options, initial, 2 * o.samples_per_period);

    // Phase 1, settling: up to transient_periods, stopped as soon as a periodic steady state
    // is found. The tangent vector rides along; for a periodic point its average over this
    // phase is the evidence of contraction.
    TangentObserver tangent(dyn, 1, 0);
    SteadyStateDetector steady(dyn.dimension(), o.max_period, o.steady_tolerance, 0,
                               natural_angular_frequency);
    Classification c;
    c.scheme_used = planned.plan().scheme;
    c.tolerance_used = run_options.tolerance;
    double t = 0.0;
    if (o.transient_periods > 0) {
        Observer* settling[] = {&steady, &tangent};
        const RunOutcome first = planned.run({o.transient_periods, 0, 0.0}, settling, keep_going);
        if (phase_ends(first, c)) return c;
        t = first.t_end;
    }
    std::optional<int> period = steady.period();
    LyapunovResult lyap = tangent.result();

    // Phase 2, recording record_periods where the state did not settle. A detector of its own
    // keeps watching: a chaotic transient that outlasts the discarded periods can end while
    // recording (Nm = 2, fc = 15.70, eps = 0.287, e_r = 0.0615, f_r = 3.642 from rest read
    // quasi-periodic, F_m 0.263; it settles on period 2, F_m 0.0749, after 278 periods).
    std::optional<Recording> record;
    double transient_maximum = 0.0;
    if (!period) {
        // Split in two: the halves' maxima give F_m's sampling spread.
        record.emplace(dyn, o, o.record_periods / 2);
        SteadyStateDetector watch(dyn.dimension(), o.max_period, o.steady_tolerance, 0,
                                  natural_angular_frequency);
        std::vector<Observer*> recording = record->observers();
        recording.insert(recording.end(), {&tangent, &watch});
        const RunOutcome second = planned.run({o.record_periods, 0, t}, recording, keep_going);
        if (phase_ends(second, c)) return c;
        lyap = tangent.result();
        // A period the watch found but had not yet stopped for (it waits up to 4096 periods
        // for a shorter divisor) is a settle too: Newton reads the minimal period.
        if (second.status == RunStatus::steady_state || watch.period()) {
            period = watch.period();
            c.settled_in_record = true;
            transient_maximum = record->forces.max_force();
            t = second.t_end;
            record.reset();
        }
    }
    if (period && record_cycle(dyn, o, *period, t, keep_going, planned, record, lyap, c)) return c;
    label_recorded(dyn, f_r, o, planned.state(), *record, period, lyap, transient_maximum, c);
    if (period)
        measure_unconfirmed_exponent(dyn, o, *period, t, keep_going, planned, c);
    else
        c.section_states = std::move(record->states);
    return c;
}

/// Compares c with its twin (ClassifyOptions::twin_check): each is a valid answer for a start
/// 1e-8 apart, so the error bars cover the difference, and a label or F_m beyond them says the
/// answer depends on the start.
void compare_with_twin(const Classification& twin, Classification& c) {
    c.twin_checked = true;
    const double difference = std::abs(twin.F_m - c.F_m);
    c.start_dependent =
        twin.regime != c.regime || difference > 3.0 * std::max(c.F_m_error, twin.F_m_error);
    c.F_m_error = std::max(c.F_m_error, difference);
    // Two records of one chaos (or torus) decorrelate within a few periods of the 1e-8 move:
    // their exponents are two samples, and the blocks' standard error (which a reviewer's probe
    // of gapchain-lyapunov found about 3x small on intermittent chaos) is held to cover it. A twin
    // of another label measured another motion: its exponent says nothing of this one's error.
    if (twin.regime == c.regime && std::isfinite(c.lambda_max_error))
        c.lambda_max_error = std::max(c.lambda_max_error, std::abs(twin.lambda_max - c.lambda_max));
}

} // namespace

Classification classify(const ReducedParameters& p, const ClassifyOptions& o,
                        const ProgressCallback& keep_going) {
    const auto start = std::chrono::steady_clock::now();
    validate(o);
    validate(p);
    const Dynamics dyn = Dynamics::paper_row(p);
    Classification c = classify_from(dyn, p.f_r, o, o.initial, keep_going);
    // A settled label came from a state that repeats; only a record that never repeated can be
    // a transient's (Nm = 6, fc = 324.45, eps = 0.2399, e_r = 0.2086, f_r = 2.131 from
    // u_1 = 6e-6 reads chaotic over the whole default record and settles on period 1 later).
    const bool unsettled = c.regime == Regime::quasi_periodic || c.regime == Regime::chaotic;
    if (o.twin_check && unsettled && c.status == RunStatus::completed) {
        auto twin = std::make_shared<const Classification>(classify_from(
            dyn, p.f_r, o,
            detail::perturbed(o.initial.empty() ? std::vector<double>(dyn.dimension(), 0.0)
                                                : o.initial),
            keep_going));
        if (twin->status == RunStatus::cancelled) c.status = RunStatus::cancelled;
        if (twin->status == RunStatus::completed) compare_with_twin(*twin, c);
        c.twin = std::move(twin);
    }
    c.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return c;
}

RegimeMap regime_map(const ReducedParameters& base, const std::vector<double>& e_r,
                     const std::vector<double>& f_r, const ClassifyOptions& o, int threads,
                     const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    validate(o);
    detail::require_range("threads", threads, 0, 4096);
    if (e_r.empty() || f_r.empty())
        throw std::invalid_argument("e_r, f_r: need at least one value each");
    for (double e : e_r)
        validate(ReducedParameters{base.Nm, base.fc, base.eps, e, base.f_r});
    for (double f : f_r)
        validate(ReducedParameters{base.Nm, base.fc, base.eps, base.e_r, f});
    require_map_work(base, e_r.size(), f_r, o);
    // A value twice classified the same cells twice, one row or column of the map shown twice.
    detail::require_distinct("e_r", e_r);
    detail::require_distinct("f_r", f_r);
    // A bad start is refused here, once, rather than by every cell's run.
    (void)initial_state(Dynamics::paper_row({base.Nm, base.fc, base.eps, e_r[0], f_r[0]}),
                        o.initial);
    RegimeMap map;
    map.e_r = e_r;
    map.f_r = f_r;
    const long cells = static_cast<long>(e_r.size() * f_r.size());
    map.cells.resize(cells);
    for (auto& cell : map.cells)
        cell.status = RunStatus::cancelled;
    map.threads_used = detail::thread_count(threads);
    detail::SharedProgress shared(progress, cells);
    const auto end = detail::parallel_for(
        cells, map.threads_used,
        [&](long k) {
            ReducedParameters p = base;
            p.e_r = e_r[k / f_r.size()];
            p.f_r = f_r[k % f_r.size()];
            map.cells[k] = classify(p, o, shared.item_callback());
        },
        [&](long) { return shared.finished(); });
    map.cancelled = end == detail::LoopEnd::cancelled;
    map.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return map;
}

RunOptions classify_search_run(const ClassifyOptions& options) {
    // Built from the defaults, not from the scene's run section: a scene's
    // run.max_steady_period changed the search's transients while gapchain-classify refused a
    // --set of it as a key it does not read.
    RunOptions run;
    run.scheme = options.scheme;
    run.tolerance = options.tolerance;
    run.max_work = options.max_work;
    run.max_steady_period = options.max_period;
    run.transient_periods = options.transient_periods;
    run.periods = options.transient_periods + options.record_periods;
    return run;
}

} // namespace gapchain
