#pragma once
/// \file poincare.hpp
/// Poincaré sections of a run: stroboscopic (once per forcing period at a chosen phase) and
/// event sections (a linear signal of the state crossing a level in a chosen direction, e.g.
/// u_1 = 0 upward, or every closing of contact j). Points are located on the quintic Hermite
/// dense output of the step they fall in, never at the nearest step, and streamed to a sink. A
/// crossing and its return inside one step (a shallow dip across the level) are found too: the
/// trigger's rate changes sign between the step's ends, and its turn lies across the level.

#include "gapchain/dynamics.hpp"
#include "gapchain/run.hpp"

#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

namespace detail {
class StepInterpolant;
}

/// A quantity read off the state at a section point.
struct SectionVariable {
    enum class Kind {
        displacement, ///< u_i
        velocity,     ///< v_i
        gap,          ///< g_j (> 0: penetration)
        force,        ///< reduced contact force F_j
        time,         ///< reduced time
    };
    Kind kind = Kind::displacement;
    int index = 0; ///< body i (0-based) or contact j (0 = left wall)

    /// Parses "u1".."uNm", "v1".."vNm" (1-based bodies), "g0".."gNm", "F0".."FNm" (contacts,
    /// 0 = left wall) or "t"; throws std::invalid_argument naming the key for anything else.
    static SectionVariable parse(std::string_view name, int bodies, const std::string& key);
    /// parse() of a state variable only, for what plots or transforms a variable (a spectrum,
    /// a diagram): "t" is refused with the rest, in one message naming key and what it takes.
    static SectionVariable parse_state(std::string_view name, int bodies, const std::string& key);
    /// parse() of an event section's trigger: u, v or g only (a linear signal of the state), in
    /// one message naming key and what it takes (parse()'s listed t and F, refused later).
    static SectionVariable parse_trigger(std::string_view name, int bodies, const std::string& key);
    /// The whole state of a row of `bodies` bodies, u_1 .. u_Nm then v_1 .. v_Nm: what a
    /// section records to tell states apart (a diagram's period, a label's section points).
    static std::vector<SectionVariable> whole_state(int bodies);
    /// The name parse() reads.
    [[nodiscard]] std::string name() const;
    /// Its value at reduced time t and state y.
    [[nodiscard]] double value(const Dynamics& dyn, double t, const double* y) const;
};

/// Crossing direction of an event section.
enum class CrossingDirection { up, down, both };

/// Which section to take.
struct SectionSpec {
    enum class Kind { stroboscopic, event };
    Kind kind = Kind::stroboscopic;
    double phase = 0.0;      ///< stroboscopic: fraction of the period, in [0, 1)
    SectionVariable trigger; ///< event: u_i, v_i or g_j (a linear signal of the state)
    double level = 0.0;      ///< event: level the trigger crosses
    CrossingDirection direction = CrossingDirection::up;    ///< event: crossing direction
    std::vector<SectionVariable> record{SectionVariable{}}; ///< values kept per point (u_1)
};

/// Throws std::invalid_argument if the spec is inconsistent with a row of `bodies` bodies.
void validate(const SectionSpec& spec, int bodies);

/// One section point: its time and the recorded values, in SectionSpec::record order.
struct SectionPoint {
    double t = 0.0;             ///< reduced time of the crossing
    std::vector<double> values; ///< reduced displacements / velocities, SectionSpec::record order
};

/// Receives section points in time order.
using SectionSink = std::function<void(const SectionPoint&)>;

/// Observer that takes a section of a run while it records (after the transient) and streams
/// its points to a sink. Stores nothing itself.
class PoincareSampler final : public Observer {
public:
    /// dyn must outlive the sampler; spec is validated.
    PoincareSampler(const Dynamics& dyn, SectionSpec spec, SectionSink sink);
    ~PoincareSampler() override;
    void on_step(const StepView& step) override;
    /// Points emitted so far.
    [[nodiscard]] long count() const { return m_count; }

private:
    void emit(double t, const double* y);
    [[nodiscard]] double trigger_value(const double* y) const;
    /// The trigger's time derivative at (t, y).
    [[nodiscard]] double trigger_rate(double t, const double* y) const;
    /// Whether a crossing upward (up) or downward is one the spec asks for.
    [[nodiscard]] bool wanted(bool up) const;
    /// Emits the crossing of the level inside [lo, hi] of this step (one sign change, the
    /// trigger s_lo at lo).
    void emit_crossing(const StepView& step, double lo, double hi, double s_lo);
    /// Bisects [lo, hi] of this step to full precision for where on_lo_side(t, state) turns
    /// false (it holds at lo, not at hi); returns that time, with m_state the state there.
    double bisect(const StepView& step, double lo, double hi,
                  const std::function<bool(double, const double*)>& on_lo_side);
    /// Emits a crossing and its return inside the step, where the trigger (s0, s1 at the ends,
    /// on one side of the level) turns across it.
    void emit_dip(const StepView& step, double s0, double s1);
    void state_at(const StepView& step, double t);

    const Dynamics& m_dyn;
    SectionSpec m_spec;
    SectionSink m_sink;
    std::vector<double> m_state;
    std::unique_ptr<detail::StepInterpolant> m_interpolant; ///< of the current step, if built
    SectionPoint m_point;
    long m_count = 0;
};

/// Smallest k <= max_period such that every recorded value repeats k points later to
/// tolerance * (1 + max |value|); 0 if none (or fewer than 2 k points).
int detect_period(const std::vector<SectionPoint>& points, int max_period, double tolerance);

/// detect_period() one point at a time, on values that need not be kept: the last max_period
/// points, per lag k the largest difference between values k points apart, and the largest
/// |value|. A bifurcation diagram reads its period from the section's whole state this way,
/// whatever single variable it plots.
class SectionRepeats {
public:
    /// max_period in [1, 1000].
    explicit SectionRepeats(int max_period);
    /// The next point's values (the same count each time).
    void add(const std::vector<double>& values);
    /// detect_period()'s answer for the points added so far, at tolerance (> 0). With
    /// distinct_cycle a period k > 1 also needs the last point to differ from each of the k - 1
    /// before it by more than the tolerance (k distinct points); where the last point is within
    /// it of the one j < k before (the first such j), the answer is j, the orbit the record
    /// closed in on: a slow spiral onto a period-1 orbit whose rotation is near 1/k comes back
    /// near its start every k periods while its points close in on one (Fig 13's row at
    /// f_r = 2.7715: |mu| 0.966, rotation 0.3255, read as period 3; an approach to a period-2
    /// orbit with a multiplier near -1 read as period 4 at 3.90-3.92).
    [[nodiscard]] int period(double tolerance, bool distinct_cycle = false) const;

private:
    int m_max_period;
    std::deque<std::vector<double>> m_recent;
    std::vector<double> m_largest_difference; ///< index k, lag k points
    double m_scale = 0.0;
    long m_count = 0;
};

/// Whether a section's record ends periodic, as gapchain-poincare and Python poincare() say it
/// (repeats_every in section.json): the smallest k <= max_repeat such that each of the
/// record's last points (its second half, at most 2 max_repeat, at least 2 k) comes back k
/// points later, every recorded value but t and an event's trigger (which tell nothing) within
/// repeat_tolerance (relative; above the round-off of a settled run's points and of an event's
/// located crossing) of its size; 0 where none does, or where nothing else is recorded. A
/// start-up before the second half does not count, as it does in detect_period().
class RecordTailRepeats {
public:
    static constexpr int max_repeat = 128;
    static constexpr double repeat_tolerance = 1e-8;
    explicit RecordTailRepeats(const SectionSpec& spec) : m_spec(spec) {}
    /// The next point of the section taken to the spec.
    void add(const SectionPoint& point);
    /// k, or 0.
    [[nodiscard]] int period() const;

private:
    SectionSpec m_spec;
    std::deque<std::vector<double>> m_last; ///< up to 3 max_repeat points, t left out
    long m_count = 0;
};

/// Runs dyn from initial (empty: rest) over options.periods, with options.transient_periods
/// discarded, on the step options.scheme / tolerance / step ask for, and streams the section
/// points to sink. Runs the full length (a section wants every period). Returns how the run
/// ended; a non-finite state is reported there, not thrown.
RunOutcome take_section(const Dynamics& dyn, const RunOptions& options, const SectionSpec& spec,
                        const SectionSink& sink, const std::vector<double>& initial = {},
                        const ProgressCallback& progress = {});

/// How far a section's points can be trusted: the run's first points set against the same
/// points of a run on a finer plan from the same start (section_accuracy()).
struct SectionAccuracy {
    long compared = 0; ///< points compared (the first of the record)
    /// Per recorded variable (SectionSpec::record order), twice the largest difference between
    /// the two runs over the points before they part: the error estimate of those points, in
    /// the variable's own units (twice, so that it covers the run's own error for any scheme of
    /// order >= 1; the finer run is half the step, a tenth of the tolerance and half the output
    /// interval). NaN where nothing was compared, for a stroboscopic section's time t (a
    /// multiple of the period), and for an event section's trigger variable (the level at every
    /// point); an event section's t has its error.
    std::vector<double> error;
    /// First compared point (0-based) at which some variable differs by more than 1e-3 of its
    /// largest |value| over the compared points, at least half of the next ten points differ
    /// too, and the runs grow apart by more than 1e-2 of it somewhere from there on: from there on
    /// the runs follow different trajectories (a chaotic record), so the points still sample the
    /// attractor but are no longer this start's; -1: they never part within the compared points.
    /// Points that differ by a bounded amount (a run too coarse to follow its points, or
    /// ill-conditioned ones such as the velocity at a shallow crossing), or whose runs both
    /// repeat (each run's points come back within 1e-3 after some P <= 128 points), are no
    /// parting: they widen error. 0: a chaotic record that parted before it began; error then
    /// covers every compared point (the largest difference over all of them, twice). Also where
    /// crossings_differ says so: compared itself where every compared point agrees but the
    /// finer run found fewer crossings (those beyond pair wrongly).
    long parted_at = -1;
    /// An event section whose runs found different crossings, not a chaotic parting: where they
    /// part, their crossing times differ by more than a quarter of the forcing period, or the
    /// points agree once one run's are shifted by one or two crossings, or the runs find
    /// crossings at rates a quarter apart (the finer run finding fewer of the run's points over
    /// the whole record by more than a quarter and three square roots of their number counts;
    /// one run finding none leaves nothing compared, parted_at 0). One run found a crossing the
    /// other did not (a dip shallower than one run's error, or a level within it of an extremum); a
    /// smaller run.tolerance or run.step settles which, and the points beyond are paired wrongly.
    bool crossings_differ = false;
    /// Runs that part (parted_at >= 0, not crossings_differ) where only the finer run's points
    /// repeat (some P <= 128 brings twenty of them back within 1e-3): the finer run is on a
    /// periodic orbit that this run does not follow. Either the run's step is too coarse to
    /// follow that orbit (rk4 at step 0.03 on Fig 13's periodic row at f_r = 3.0, event u1 =
    /// -0.105), or the run reached another, chaotic attractor; a smaller run.step or
    /// run.tolerance settles which. error covers the difference either way.
    bool finer_repeats = false;
    /// The finer plan: "half the step", "tolerance X, half the output interval" (adaptive
    /// schemes: a tenth of the run's), or "rk8pd at tolerance 1e-12" (the exact scheme).
    std::string comparison;
    /// The comparison run's end: cancelled or non_finite leave error NaN.
    RunStatus status = RunStatus::completed;
    /// Why error is NaN for every variable, empty where it was estimated: no finer run (an
    /// adaptive tolerance within 10 times 1e-12, or a finer run beyond run.max_work, which it
    /// is held to on its own: the main run is not refused for it), the finer run cancelled or
    /// non-finite, or no point to compare.
    std::string not_estimated;
};

/// How many of a section's first points gapchain-poincare and Python poincare() set against
/// the finer run (section_accuracy()).
constexpr std::size_t section_error_points = 1000;

/// The accuracy of main_points, the first points take_section() streamed for (dyn, options,
/// spec, initial): the same section is taken on a finer plan until it has as many points, and
/// the two are compared point by point (compared = the fewer of the two counts). Costs a run
/// of the transient and as many recorded periods on the finer plan (about twice the work of
/// that part of the main run; an event section's may run all of run.periods).
SectionAccuracy section_accuracy(const Dynamics& dyn, const RunOptions& options,
                                 const SectionSpec& spec, const std::vector<double>& initial,
                                 const std::vector<SectionPoint>& main_points,
                                 const ProgressCallback& progress = {});

} // namespace gapchain
