// gapchain.modes, bifurcation, poincare, spectrum and lyapunov: the analyses of one row.
#include "call.hpp"

#include "gapchain/bifurcation.hpp"
#include "gapchain/lyapunov.hpp"
#include "gapchain/modes.hpp"
#include "gapchain/poincare.hpp"
#include "gapchain/report.hpp"
#include "gapchain/signal.hpp"
#include "gapchain/spectrum.hpp"

#include <pybind11/stl.h>

#include <chrono>
#include <optional>

namespace gapchain::python {

namespace {

constexpr const char* modes_doc =
    R"(modes(Nm=None, fc=None, *, count=0, end="lowest", method="auto", shapes=True, max_dense=5000, scene=None, **keys) -> dict

Natural frequencies and mode shapes of the linear chain (e_r = 0, every contact acting both
ways; paper Section 5) against the paper's approximation eq (26),
f_ka = sqrt(1 + fc (k/Nm)^2 (4.935 - 2.935 (k/Nm)^1.81)): gapchain-modes in-process.

Nm      bodies, 1 .. 1e6;  fc  stiffness ratio Kc/K, (0, 1e9]; either, when given, overrides
        the scene's (without a scene: 5 and 100, the paper's defaults)
count   modes wanted, 0 .. Nm (0: all, dense solver only)
end     "lowest" or "highest" modes;  method "auto", "dense" or "sparse"
shapes  also return the mode shapes (phi^T M phi = 1)
max_dense  largest Nm for the dense solver, 1 .. 1e6 (memory 8 Nm^2 bytes, time ~Nm^3), as
        gapchain-modes --max-dense; with method "auto" beyond it the sparse solver is used
scene, **keys   a scene (dict or path) and scene keys for a non-uniform row.

Returns a dict: mode (int k, 1-based), frequency (reduced f_k = f/f0), approx (eq 26),
rel_error ((f_ka - f_k) / f_k), residual, shapes (Nm x modes float64, column k the shape of
mode k), method, status ("converged", ...), iterations, wall_time_s.)";

constexpr const char* bifurcation_doc =
    R"(bifurcation(scene=None, *, param="f_r", from_=2.0, to=4.5, steps=500, mode="independent", transient=200, record=100, variable="u1", phase=0.0, threads=0, confirm=True, progress=None, **keys) -> dict

Bifurcation diagram of the paper's uniform row over one parameter: at each value a transient
is discarded, then the stroboscopic section points (phase in [0, 1) of the forcing period) of
`variable` and F_m are recorded and the period detected. gapchain-bifurcation in-process.

param     "f_r", "e_r", "fc" or "eps";  from_, to  first and last value;  steps >= 1 values
mode      "independent" (each value from the scene's initial state, default rest, in
          parallel) or "continuation" (from from_ to to and back, from it; a leg is "up" where the value grows)
transient discarded periods per value, >= 0;  record  recorded periods per value, >= 1
variable  u1..uNm, v1..vNm, g0..gNm, F0..FNm;  threads OpenMP threads (0: all cores)
confirm   confirm a periodic row's orbit by Newton on the exact scheme (its F_m, minimal
          period and multipliers replace the window's; gapchain-bifurcation --no-newton is False)
progress  callable(fraction of values done)
scene, **keys  the row (Nm, fc, eps, e_r, f_r; of the run section scheme, tolerance and
          max_work are used) and its initial state. None is the paper's default row (fc 100,
          e_r 0.5); gapchain-bifurcation without a scene draws Fig 13's, which is
          data/scenes/fig13.json here.

Returns a dict of columns, one row per value and direction: value, direction ("up"/"down"),
F_m (over the orbit Newton confirmed, else over the recorded periods), F_m_error (the recorded
halves' spread of F_m, at least tolerance * F_m; on a confirmed orbit at least the recorded
maximum's difference from it; on a row that is not periodic, and on a periodic row Newton did
not confirm with confirm=True, and on a confirmed one that window did not reach
(ended_elsewhere), at least twice its difference from the same window on a finer plan), period (0: not periodic; the orbit's minimal period where
confirmed), points (section points recorded; the orbit's where points_from_orbit), status, newton_confirmed, max_multiplier (the
confirmed orbit's largest |Floquet multiplier|, NaN unless confirmed), points_from_orbit (the
row's section points are one cycle of the confirmed orbit, whose minimal period was shorter
than the window's), ended_elsewhere (the same window on a finer plan did not reach the confirmed
orbit: a start near a basin boundary, F_m_error covering twice the difference); and "section":
a dict
of columns value, direction, t (reduced time), point (the variable) of every section point;
wall_time_s, threads_used, cancelled (an interrupted call, by KeyboardInterrupt or an exception progress raises, sets what it had done, cancelled true, as the exception's partial).)";

constexpr const char* poincare_doc =
    R"(poincare(scene=None, *, section="stroboscopic", phase=None, trigger=None, level=None, direction=None, record=("u1", "v1"), error=True, progress=None, **keys) -> dict

Poincare section of the scene's run (run.periods after run.transient_periods), points located
on the dense output between steps: gapchain-poincare in-process.

section    "stroboscopic" (once per forcing period at phase in [0, 1), default 0) or "event"
           (trigger crossing level in direction "up", "down" or "both"; defaults u1, 0, "up");
           a keyword of the other kind of section is refused
trigger    u1..uNm, v1..vNm or g0..gNm (event sections)
record     names of the recorded values, each once: u1..uNm, v1..vNm, g0..gNm, F0..FNm or t
error      estimate the points' error: the first 1000 set against a run at half the step (a
           tenth of an adaptive scheme's tolerance and half its output interval; rk8pd at 1e-12
           for the exact scheme); it reruns the
           transient and those periods

Returns a dict: t ((n,) reduced times), points ((n, len(record)) float64), names (record),
repeats_every (the record's last points repeat after this many, to 1e-8 of their size, t left
out; None where they do not within 128), point_error (None with error=False or a run that did not complete, else a dict as
section.json's: compared, error (per recorded name: twice the largest difference before the
runs part; None for a stroboscopic section's t and an event's trigger), parted_at (the first compared point where the
runs differ by more than 1e-3 of a variable's largest value and from which on they grow apart,
a chaotic record: None if never; points that differ by a bounded amount, or of two runs that
both repeat, widen the error instead; 0: a record that parted before it began, and the error
then covers every compared point), crossings_differ (an event section whose runs found
different crossings: times more than a quarter period apart, points that agree once shifted by
one or two crossings, crossing rates a quarter apart, or a finer run finding fewer points by a
quarter and three square roots of their number, or one run none; a shallow crossing, or a
level within one run's error of an extremum, found by one run only, not chaos),
finer_repeats (runs that part where only the finer run's points repeat: the run too coarse to
follow the finer run's periodic orbit, or on another, chaotic attractor), comparison, status, not_estimated (why not, or None)), status, message, scheme and step (the
scheme the run took and its step in reduced time, an adaptive scheme's output interval),
wall_time_s. An
interrupted call keeps the points so far on the exception as `partial`.)";

constexpr const char* spectrum_doc =
    R"(spectrum(scene=None, *, variable="u1", samples_per_period=32, segment=0, window="hann", order=4, progress=None, **keys) -> dict

Power spectral density (Welch, FFTW) of a variable over the scene's run.periods after
run.transient_periods, peaks labelled as (sub)harmonics m/n f_r: gapchain-spectrum in-process.

variable  u1..uNm, v1..vNm, g0..gNm or F0..FNm;  samples_per_period  2 .. 100000
segment   Welch segment length in samples, 16 .. 2^24 and at most the recorded samples; 0 (the
          default): a whole number of forcing periods, a multiple of 12 (of lcm(1..order)
          up to 60), up to 128 periods, that the record holds twice at half overlap
window    "hann" or "rectangular";  order  largest subharmonic order n labelled, 1 .. 64
(the limits of gapchain-spectrum: both use RowSpectrumOptions)

Returns a dict: frequency ((n,) cycles per reduced time unit), f_over_f_r, density
(signal^2 per unit frequency), df, segment (the length used), segments, broadband_share (power away from m/n f_r, [0, 1]),
broadband_share_error (the segments' spread of it plus aliased_share, plus the leakage where
the segment is not whole periods; NaN with one segment), fraction_bin_share (the share of bins
next to some m/n f_r: above 0.5 the segment holds too few periods for the broadband share),
segment_periods, whole_periods (False: lines leak, the errors include it),
peaks (dict of columns frequency, frequency_error (df / 2), power, power_error (the larger of
its standard error over the Welch segments and 2 run.tolerance x power, plus its aliasing
error: what folds onto it from above the Nyquist frequency or how much the power moves when the
rate is doubled, the larger, and for a contact force also what folds onto it at twice the rate;
NaN with a single segment), numerator, denominator, label),
aliased_share (the share of the power between the Nyquist frequency and twice it, measured at
twice the rate, [0, 1]; above 1e-3, raise samples_per_period), sampled_range_share (the
samples' range over the variable's range at every step, [0, 1]; well below 1 the samples miss
its peaks), sample_rate, status,
wall_time_s.)";

constexpr const char* lyapunov_doc =
    R"(lyapunov(scene=None, *, count=0, progress=None, **keys) -> dict

Lyapunov exponents of a row (Benettin, QR every forcing period) over the scene's run.periods,
averaged after run.transient_periods: gapchain-lyapunov in-process.

count  exponents wanted, 0 .. 2 Nm (0: all 2 Nm)

Returns a dict: exponents (largest first up to their errors: Benettin's order, equal ones in
either order; per unit reduced time), errors (standard errors over 10 time blocks, or the
block rates' drift over the window for an exponent whose rates drift), drifting (True: some
exponent's rates trend, the run had not reached its attractor; raise run.transient_periods), sum, expected_sum (what the sum of all 2 Nm must be: the trace, -sum of the damping rates,
-4 pi eps Nm on the paper's row; NaN when count < 2 Nm), averaging_time, history (dict: t, and
exponents (n x count) running estimates), status, message, wall_time_s.)";

// Nor do the forcing, the start, the damping or the clearances (f_r=2, eps=7 were taken and
// ignored), nor such a member of a dict keyword.
void refuse_keys_unread_by_modes(const py::kwargs& keys) {
    const auto refuse = [](const std::string& name, const std::string& dotted) {
        if (key_unread_by_modes(dotted))
            throw std::invalid_argument(name +
                                        ": modes() does not read it (the linear chain's modes "
                                        "follow from its masses, springs and contact stiffnesses "
                                        "alone); drop the " +
                                        name + " keyword");
    };
    for (const auto& [key, value] : keys) {
        const std::string name = key.cast<std::string>();
        refuse(name, scene_key(name));
        // A dict sets its members: model.scatter={"clearance": 0.5} was taken and ignored
        // (helper-85).
        if (py::isinstance<py::dict>(value))
            for (const auto& [member, unused] : value.cast<py::dict>()) {
                const std::string dotted =
                    scene_key(name) + "." + py::str(member).cast<std::string>();
                refuse(dotted, dotted);
            }
    }
}

// modal_analysis(), its refusals naming modes()' keywords: the dense limit's said
// "max_dense_bodies: ... raise the limit", an argument modes() did not have (helper-85).
ModalResult modal_analysis_named(const Chain& chain, const ModalOptions& o) {
    try {
        return modal_analysis(chain, o);
    } catch (const std::invalid_argument& e) {
        const std::string field = "max_dense_bodies:";
        std::string message = e.what();
        if (message.rfind(field, 0) != 0) throw;
        message = "max_dense:" + message.substr(field.size());
        const std::string limit = "raise the limit";
        if (const auto at = message.find(limit); at != std::string::npos)
            message.replace(at, limit.size(), "raise max_dense");
        throw std::invalid_argument(message);
    }
}

py::dict modes_py(const py::object& Nm, const py::object& fc, int count, const std::string& end,
                  const std::string& method, bool shapes, int max_dense,
                  const py::object& scene_arg, py::kwargs keys) {
    // Given, they override the scene's; else the scene's (the paper's 5 and 100 without one).
    if (!Nm.is_none()) keys["Nm"] = Nm;
    if (!fc.is_none()) keys["fc"] = fc;
    // As gapchain-modes: a run or output keyword (periods=5) was taken and ignored.
    refuse_run_keys(keys, "modes", {}, "its modes follow from the model alone");
    refuse_keys_unread_by_modes(keys);
    const Scene scene = to_scene(scene_arg, keys);
    ModalOptions o;
    o.count = count;
    o.max_dense_bodies = max_dense;
    o.end =
        choice(end, "end", {"lowest", "highest"}) == 0 ? SpectrumEnd::lowest : SpectrumEnd::highest;
    o.method = parse_eigen_method(method);
    o.shapes = shapes;
    const ModalResult r = Call().run([&] { return modal_analysis_named(scene.chain(), o); });
    py::dict d;
    d["mode"] = column<int>(r.mode_numbers, [](int k) { return k; });
    d["frequency"] = array(r.frequencies);
    d["approx"] = array(r.approx);
    d["rel_error"] = array(r.rel_error);
    d["residual"] = array(r.residuals);
    const std::size_t n = static_cast<std::size_t>(scene.reduced.Nm);
    std::vector<double> s(n * r.shapes.size());
    for (std::size_t k = 0; k < r.shapes.size(); ++k)
        for (std::size_t i = 0; i < n; ++i)
            s[i * r.shapes.size() + k] = r.shapes[k][i];
    d["shapes"] = matrix(s, r.shapes.empty() ? 0 : n, r.shapes.size());
    d["method"] = std::string(to_string(r.method));
    d["status"] = r.status == ModalStatus::converged       ? "converged"
                  : r.status == ModalStatus::not_converged ? "not_converged"
                                                           : "numerical_issue";
    d["iterations"] = r.iterations;
    d["wall_time_s"] = r.wall_time_s;
    return d;
}

py::dict section_points_dict(const BifurcationResult& r) {
    std::vector<std::pair<const BifurcationRow*, const SectionPoint*>> all;
    for (const auto& row : r.rows)
        for (const auto& p : row.points)
            all.emplace_back(&row, &p);
    using Item = std::pair<const BifurcationRow*, const SectionPoint*>;
    py::dict d;
    d["value"] = column<double>(all, [](const Item& i) { return i.first->value; });
    d["direction"] = strings(all, [](const Item& i) { return to_string(i.first->direction); });
    d["t"] = column<double>(all, [](const Item& i) { return i.second->t; });
    d["point"] = column<double>(all, [](const Item& i) { return i.second->values.at(0); });
    return d;
}

py::dict bifurcation_dict(const BifurcationResult& all) {
    using Row = BifurcationRow;
    // The rows an interrupted diagram did not run (status cancelled, F_m 0 with an error of 0)
    // are left out, as gapchain-bifurcation's CSVs leave them out.
    BifurcationResult r = all;
    std::erase_if(r.rows, [](const Row& w) { return w.status == RunStatus::cancelled; });
    py::dict d;
    d["value"] = column<double>(r.rows, [](const Row& w) { return w.value; });
    d["direction"] = strings(r.rows, [](const Row& w) { return to_string(w.direction); });
    d["F_m"] = column<double>(r.rows, [](const Row& w) { return w.F_m; });
    d["F_m_error"] = column<double>(r.rows, [](const Row& w) { return w.F_m_error; });
    d["period"] = column<int>(r.rows, [](const Row& w) { return w.period; });
    d["points"] = column<long>(r.rows, [](const Row& w) { return w.points.size(); });
    d["status"] = strings(r.rows, [](const Row& w) { return to_string(w.status); });
    d["newton_confirmed"] = column<bool>(r.rows, [](const Row& w) { return w.newton_confirmed; });
    d["max_multiplier"] = column<double>(r.rows, [](const Row& w) { return w.max_multiplier; });
    d["points_from_orbit"] = column<bool>(r.rows, [](const Row& w) { return w.points_from_orbit; });
    d["ended_elsewhere"] = column<bool>(r.rows, [](const Row& w) { return w.ended_elsewhere; });
    d["section"] = section_points_dict(r);
    d["wall_time_s"] = r.wall_time_s;
    d["threads_used"] = r.threads_used;
    d["cancelled"] = r.cancelled;
    return d;
}

py::dict bifurcation_py(const py::object& scene_arg, const std::string& param, double from,
                        double to, int steps, const std::string& mode, long transient, long record,
                        const std::string& variable, double phase, int threads, bool confirm,
                        const py::object& progress, const py::kwargs& keys) {
    refuse_run_keys(keys, "bifurcation", run_settings_keys,
                    "each value runs transient, then record periods");
    const Scene scene = to_swept_scene(scene_arg, param, keys, "bifurcation");
    require_paper_row(scene, "bifurcation()");
    BifurcationOptions o;
    o.parameter = parse_swept_parameter(param);
    o.from = from, o.to = to, o.steps = steps;
    o.mode = parse_sweep_mode(mode);
    o.transient_periods = transient, o.record_periods = record;
    o.section.record = {SectionVariable::parse_state(variable, scene.reduced.Nm, "variable")};
    o.section.phase = phase;
    o.threads = threads;
    take_run_settings(scene, o);
    o.confirm_by_newton = confirm;
    validate(o, scene.reduced);
    Call call(progress);
    return call.run([&] { return bifurcation(scene.reduced, o, call.callback()); },
                    bifurcation_dict);
}

/// The section asked for. A keyword of the other kind of section is refused, as
/// gapchain-poincare refuses its flag: poincare(level=0.3) on a stroboscopic section returned
/// the section without it.
SectionSpec section_spec(const std::string& section, const std::optional<double>& phase,
                         const std::optional<std::string>& trigger,
                         const std::optional<double>& level,
                         const std::optional<std::string>& direction,
                         const std::vector<std::string>& record, int bodies) {
    SectionSpec spec;
    spec.kind = choice(section, "section", {"stroboscopic", "event"}) == 0
                    ? SectionSpec::Kind::stroboscopic
                    : SectionSpec::Kind::event;
    if (spec.kind == SectionSpec::Kind::stroboscopic) {
        for (const auto& [name, given] :
             {std::pair{"trigger", trigger.has_value()}, std::pair{"level", level.has_value()},
              std::pair{"direction", direction.has_value()}})
            if (given)
                throw std::invalid_argument(std::string(name) +
                                            ": applies to section=\"event\" only");
    } else if (phase) {
        throw std::invalid_argument("phase: applies to section=\"stroboscopic\" only");
    }
    spec.phase = phase.value_or(0.0);
    spec.trigger = SectionVariable::parse_trigger(trigger.value_or("u1"), bodies, "trigger");
    spec.level = level.value_or(0.0);
    spec.direction = static_cast<CrossingDirection>(
        choice(direction.value_or("up"), "direction", {"up", "down", "both"}));
    spec.record.clear();
    for (const auto& name : record)
        spec.record.push_back(SectionVariable::parse(name, bodies, "record"));
    validate(spec, bodies);
    return spec;
}

py::dict poincare_py(const py::object& scene_arg, const std::string& section,
                     const std::optional<double>& phase, const std::optional<std::string>& trigger,
                     const std::optional<double>& level,
                     const std::optional<std::string>& direction,
                     const std::vector<std::string>& record, bool error, const py::object& progress,
                     const py::kwargs& keys) {
    refuse_run_keys(keys, "poincare", once_through_run_keys, plain_run_reason);
    const Scene scene = to_scene(scene_arg, keys);
    const Dynamics dyn = scene.dynamics();
    const SectionSpec spec =
        section_spec(section, phase, trigger, level, direction, record, dyn.bodies());
    std::vector<double> t, values;
    std::vector<SectionPoint> first;
    RecordTailRepeats repeats(spec);
    const SectionSink sink = [&](const SectionPoint& p) {
        repeats.add(p);
        t.push_back(p.t);
        values.insert(values.end(), p.values.begin(), p.values.end());
        if (first.size() < section_error_points) first.push_back(p);
    };
    Call call(progress);
    const auto start = std::chrono::steady_clock::now();
    RunOutcome outcome;
    // The points so far, and the point error as gapchain-poincare's section.json gives it
    // (report.cpp's one list): what an interrupted call keeps as `partial` too.
    const auto section_dict = [&](const SectionAccuracy* accuracy) {
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        py::dict d;
        const int repeats_every = repeats.period();
        d["point_error"] = py::module_::import("json").attr("loads")(
            to_json(spec, static_cast<long>(t.size()), repeats_every, accuracy, wall, scene,
                    outcome))["point_error"];
        d["repeats_every"] = repeats_every > 0 ? py::object(py::int_(repeats_every)) : py::none();
        d["wall_time_s"] = wall;
        d["t"] = array(t);
        d["points"] = matrix(values, t.size(), record.size());
        d["names"] = record;
        d["status"] = std::string(to_string(outcome.status));
        d["message"] = outcome.message;
        const bool ran = outcome.step > 0.0;
        d["scheme"] = ran ? py::object(py::str(std::string(to_string(outcome.scheme))))
                          : py::object(py::none());
        d["step"] = ran ? py::object(py::float_(outcome.step)) : py::object(py::none());
        return d;
    };
    py::dict d = call.run(
        [&] {
            outcome = take_section(dyn, scene.run, spec, sink, scene.initial, call.callback());
            return outcome;
        },
        [&](const RunOutcome&) { return section_dict(nullptr); });
    if (!error || outcome.status != RunStatus::completed) return d;
    return call.run(
        [&] {
            return section_accuracy(dyn, scene.run, spec, scene.initial, first, call.callback());
        },
        [&](const SectionAccuracy& accuracy) { return section_dict(&accuracy); });
}

py::dict peaks_dict(const SpectralContent& content) {
    using Peak = SpectralPeak;
    py::dict d;
    d["frequency"] = column<double>(content.peaks, [](const Peak& p) { return p.frequency; });
    d["frequency_error"] =
        column<double>(content.peaks, [](const Peak& p) { return p.frequency_error; });
    d["power"] = column<double>(content.peaks, [](const Peak& p) { return p.power; });
    d["power_error"] = column<double>(content.peaks, [](const Peak& p) { return p.power_error; });
    d["numerator"] = column<int>(content.peaks, [](const Peak& p) { return p.numerator; });
    d["denominator"] = column<int>(content.peaks, [](const Peak& p) { return p.denominator; });
    d["label"] = strings(content.peaks, [](const Peak& p) { return p.label(); });
    return d;
}

py::dict spectrum_py(const py::object& scene_arg, const std::string& variable,
                     int samples_per_period, int segment, const std::string& window, int order,
                     const py::object& progress, const py::kwargs& keys) {
    refuse_run_keys(keys, "spectrum", once_through_run_keys, plain_run_reason);
    const Scene scene = to_scene(scene_arg, keys);
    const Dynamics dyn = scene.dynamics();
    RowSpectrumOptions o;
    o.variable = variable;
    o.samples_per_period = samples_per_period;
    o.segment = segment;
    o.window = parse_window(window);
    o.order = order;
    validate(o, dyn, scene.run);
    Call call(progress);
    const RowSpectrum s =
        call.run([&] { return row_spectrum(dyn, scene.run, o, scene.initial, call.callback()); });
    py::dict d;
    d["status"] = std::string(to_string(s.outcome.status));
    d["wall_time_s"] = s.wall_time_s;
    if (s.outcome.status != RunStatus::completed) return d;
    std::vector<double> ratio;
    for (double f : s.psd.frequency)
        ratio.push_back(f / scene.reduced.f_r);
    d["frequency"] = array(s.psd.frequency);
    d["f_over_f_r"] = array(ratio);
    d["density"] = array(s.psd.density);
    d["df"] = s.psd.df;
    d["segment"] = s.segment;
    d["segments"] = s.psd.segments;
    d["broadband_share"] = s.content.broadband_share;
    d["broadband_share_error"] = s.content.broadband_share_error;
    d["aliased_share"] = s.aliased_share;
    d["fraction_bin_share"] = s.content.fraction_bin_share;
    d["segment_periods"] = s.segment_periods;
    d["whole_periods"] = s.whole_periods;
    d["sampled_range_share"] = s.sampled_range_share;
    d["peaks"] = peaks_dict(s.content);
    d["sample_rate"] = s.sample_rate;
    return d;
}

py::dict lyapunov_py(const py::object& scene_arg, int count, const py::object& progress,
                     const py::kwargs& keys) {
    refuse_run_keys(keys, "lyapunov", once_through_run_keys, plain_run_reason);
    const Scene scene = to_scene(scene_arg, keys);
    const Dynamics dyn = scene.dynamics();
    // As gapchain-lyapunov --count: 0 means all, which the library's [1, 2 Nm] does not say.
    if (count < 0 || count > dyn.dimension())
        throw std::invalid_argument(
            "count: must be in [0, 2 Nm = " + std::to_string(dyn.dimension()) + "] (0: all), got " +
            std::to_string(count));
    const int k = count == 0 ? dyn.dimension() : count;
    Call call(progress);
    const LyapunovResult r =
        call.run([&] { return chain_lyapunov(dyn, scene.run, k, scene.initial, call.callback()); });
    py::dict d;
    d["exponents"] = array(r.exponents);
    d["errors"] = array(r.errors);
    d["drifting"] = r.drifting;
    d["sum"] = r.sum;
    d["expected_sum"] = r.expected_sum;
    d["averaging_time"] = r.averaging_time;
    std::vector<double> running;
    for (const auto& s : r.history)
        running.insert(running.end(), s.exponents.begin(), s.exponents.end());
    py::dict history;
    history["t"] = column<double>(r.history, [](const LyapunovSample& s) { return s.t; });
    history["exponents"] = matrix(running, r.history.size(), r.exponents.size());
    d["history"] = history;
    d["status"] = std::string(to_string(r.status));
    d["message"] = r.message;
    d["wall_time_s"] = r.wall_time_s;
    return d;
}

} // namespace

void register_analyses(py::module_& m) {
    m.def("modes", &modes_py, modes_doc, py::arg("Nm") = py::none(), py::arg("fc") = py::none(),
          py::kw_only(), py::arg("count") = 0, py::arg("end") = "lowest",
          py::arg("method") = "auto", py::arg("shapes") = true,
          py::arg("max_dense") = ModalOptions{}.max_dense_bodies, py::arg("scene") = py::none());
    const BifurcationOptions b;
    m.def("bifurcation", &bifurcation_py, bifurcation_doc, py::arg("scene") = py::none(),
          py::kw_only(), py::arg("param") = "f_r", py::arg("from_") = b.from, py::arg("to") = b.to,
          py::arg("steps") = b.steps, py::arg("mode") = "independent",
          py::arg("transient") = b.transient_periods, py::arg("record") = b.record_periods,
          py::arg("variable") = "u1", py::arg("phase") = 0.0, py::arg("threads") = 0,
          py::arg("confirm") = b.confirm_by_newton, py::arg("progress") = py::none());
    m.def("poincare", &poincare_py, poincare_doc, py::arg("scene") = py::none(), py::kw_only(),
          py::arg("section") = "stroboscopic", py::arg("phase") = py::none(),
          py::arg("trigger") = py::none(), py::arg("level") = py::none(),
          py::arg("direction") = py::none(),
          py::arg("record") = std::vector<std::string>{"u1", "v1"}, py::arg("error") = true,
          py::arg("progress") = py::none());
    m.def("spectrum", &spectrum_py, spectrum_doc, py::arg("scene") = py::none(), py::kw_only(),
          py::arg("variable") = "u1", py::arg("samples_per_period") = 32, py::arg("segment") = 0,
          py::arg("window") = "hann", py::arg("order") = 4, py::arg("progress") = py::none());
    m.def("lyapunov", &lyapunov_py, lyapunov_doc, py::arg("scene") = py::none(), py::kw_only(),
          py::arg("count") = 0, py::arg("progress") = py::none());
}

} // namespace gapchain::python
