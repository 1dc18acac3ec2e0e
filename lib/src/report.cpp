#include "gapchain/report.hpp"

#include "detail/json_reader.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <sys/file.h>
#include <unistd.h>

namespace gapchain {

using nlohmann::json;

namespace {

/// The operating system's reason for the last failed call.
std::string reason() {
    return std::strerror(errno);
}

/// A CSV field that may be unknown (NaN: not computed; inf: a window too short for a standard
/// error): the number, or nothing, as the attractor, map and sweep rows write it.
void write_if_finite(std::ostream& os, double x) {
    if (std::isfinite(x)) os << x;
}

/// The five reduced parameters, as every JSON result gives them.
nlohmann::json parameters_json(const ReducedParameters& p) {
    return {{"Nm", p.Nm}, {"fc", p.fc}, {"eps", p.eps}, {"e_r", p.e_r}, {"f_r", p.f_r}};
}

/// Each body's largest force on either side, when, their errors (the per-contact errors of the
/// contacts on either side, null where not estimated), and in newtons for physical scenes.
json per_body_json(const SimulationResult& r, const Scene& scene) {
    json bodies = json::array();
    const auto known = [](double x) { return std::isnan(x) ? json(nullptr) : json(x); };
    for (const BodyMaximum& b : r.per_body) {
        json e = {
            {"left", b.left}, {"right", b.right}, {"t_left", b.t_left}, {"t_right", b.t_right}};
        e["left_error"] = known(b.left_error);
        e["right_error"] = known(b.right_error);
        if (scene.physical) {
            e["left_newton"] = force_in_newtons(b.left, *scene.physical);
            e["right_newton"] = force_in_newtons(b.right, *scene.physical);
        }
        bodies.push_back(e);
    }
    return bodies;
}

/// The row that ran, in its own units (Chain, model.hpp), not the scene's: after the scatter.
/// Needs scene.row.
json chain_json(const Scene& scene) {
    return {{"mass", scene.row->mass},
            {"spring", scene.row->spring},
            {"damping", scene.row->damping},
            {"clearance", scene.row->clearance},
            {"contact", scene.row->contact},
            {"contact_law", to_string(scene.row->law)},
            {"contact_damping", scene.row->contact_damping}};
}

/// The scene's five numbers, null where an array replaced one: it did not run (the chain says
/// what did).
json scene_parameters_json(const Scene& scene) {
    json j = parameters_json(scene.reduced);
    if (scene.clearance_array) j["e_r"] = nullptr;
    if (scene.damping_array) j["eps"] = nullptr;
    // A record or Kanai-Tajimi motion has no forcing frequency: its reduced f_r (1) read as one.
    if (!scene.harmonic()) j["f_r"] = nullptr;
    return j;
}

/// What ran: the reduced parameters and run options, and what the five numbers do not say, so
/// that a result read alone (after --set on arrays, a scatter, a start) names the row and the
/// start it ran.
// A once-through run (Lyapunov) lists only the run keys it reads (scene.hpp's
// once_through_run_keys); the tool refuses the others.
void add_provenance(json& j, const Scene& scene, bool once_through = false) {
    j["parameters"] = scene_parameters_json(scene);
    j["parameters"].update({{"periods", scene.run.periods},
                            {"transient_periods", scene.run.transient_periods == auto_transient
                                                      ? json("auto")
                                                      : json(scene.run.transient_periods)},
                            {"tolerance", scene.run.tolerance}});
    if (!once_through)
        j["parameters"].update({{"accuracy_mode", to_string(scene.run.accuracy_mode)},
                                {"estimate_error", scene.run.estimate_error},
                                {"multistability_check", scene.run.multistability_check}});
    if (scene.row) j["chain"] = chain_json(scene);
    if (std::any_of(scene.initial.begin(), scene.initial.end(), [](double x) { return x != 0.0; }))
        j["initial"] = scene.initial;
}

/// The scheme and fixed step the scene asked for (null: from the tolerance) in j's
/// parameters, and the scheme and step the run took, as gapchain-sim's JSON gives them, for
/// results whose numbers depend on the plan beyond its tolerance (a section's points, a
/// spectrum): "auto" and null alone did not say which ran (a reviewer's probe, helper-77).
void add_scheme_and_step(json& j, const Scene& scene, const RunOutcome& outcome) {
    j["parameters"]["scheme"] = to_string(scene.run.scheme);
    j["parameters"]["step"] = scene.run.step ? json(*scene.run.step) : json(nullptr);
    // A run that never started (step 0) names no scheme (helper-80).
    const bool ran = outcome.step > 0.0;
    j["scheme"] = ran ? json(std::string(to_string(outcome.scheme))) : json(nullptr);
    j["step"] = ran ? json(outcome.step) : json(nullptr);
}

} // namespace

namespace {

/// Each contact's maximum, its error (null where none was estimated), time and impacts.
json per_contact_json(const SimulationResult& r) {
    json contacts = json::array();
    for (std::size_t j = 0; j < r.per_contact.size(); ++j) {
        const auto& c = r.per_contact[j];
        contacts.push_back(
            {{"force", c.force},
             {"force_error",
              j < r.per_contact_error.size() ? json(r.per_contact_error[j]) : json(nullptr)},
             {"time", c.time},
             {"impacts", c.impacts}});
    }
    return contacts;
}

json simulation_json(const SimulationResult& r, const Scene& scene) {
    json j;
    j["F_m"] = r.F_m;
    const bool estimated = has_error_estimate(r);
    j["F_m_error"] = estimated ? json(r.F_m_error) : json(nullptr);
    j["F_m_error_method"] = to_string(r.error_method);
    j["F_m_contact"] = r.F_m_contact;
    j["F_m_time"] = r.F_m_time;
    j["contact"] = r.contact;
    j["multistable"] =
        r.multistability_checked || r.multistable ? json(r.multistable) : json(nullptr);
    // Every key in every result, null where its run did not happen (they were left out, where
    // Python gave None: a reader had to know both; a reviewer's probe, helper-77).
    const auto optional = [](const std::optional<double>& x) {
        return x ? json(*x) : json(nullptr);
    };
    j["F_m_twin"] = r.twin_checked ? json(r.F_m_twin) : json(nullptr);
    j["F_m_comparison"] = optional(r.F_m_comparison);
    j["comparison_ended_elsewhere"] = r.comparison_ended_elsewhere;
    j["F_m_orbit"] = optional(r.F_m_orbit);
    j["F_m_orbit_error"] = optional(r.F_m_orbit_error);
    j["maximum_in_transient"] = r.F_m_orbit ? json(r.maximum_in_transient) : json(nullptr);
    j["start_up_periods"] = r.start_up_periods;
    j["start_up_in_window"] = r.start_up_in_window;
    j["accuracy_mode_used"] = to_string(r.accuracy_mode_used);
    j["relaxed_from_period"] =
        r.relaxed_from_period >= 0 ? json(r.relaxed_from_period) : json(nullptr);
    if (scene.physical) {
        j["F_m_newton"] = force_in_newtons(r.F_m, *scene.physical);
        j["F_m_error_newton"] =
            estimated ? json(force_in_newtons(r.F_m_error, *scene.physical)) : json(nullptr);
        j["excitation"] = {{"harmonic", scene.harmonic()},
                           {"a0_m_s2", scene.physical->a0},
                           {"natural_frequency_hz", natural_frequency(*scene.physical)}};
        j["excitation"]["type"] = scene.ground_motion_type;
        if (!scene.harmonic()) j["excitation"]["duration_s"] = scene.record_duration;
        if (!scene.record_file.empty()) j["excitation"]["record_file"] = scene.record_file;
    }
    j["per_body"] = per_body_json(r, scene);
    j["per_contact"] = per_contact_json(r);
    j["steady_state_period"] = r.steady_state_period ? json(*r.steady_state_period) : json(nullptr);
    j["steady_state_time"] = r.steady_state_time ? json(*r.steady_state_time) : json(nullptr);
    j["cycle_entry_period"] =
        r.cycle_entry_period >= 0 ? json(r.cycle_entry_period) : json(nullptr);
    j["longer_cycle_period"] = r.longer_cycle_period ? json(*r.longer_cycle_period) : json(nullptr);
    j["status"] = std::string(to_string(r.status));
    j["scheme"] = std::string(to_string(r.scheme));
    j["step"] = r.step;
    j["periods_simulated"] = r.periods_simulated;
    j["transient_periods_used"] = r.transient_periods_used;
    j["steps"] = r.steps;
    j["evaluations"] = r.evaluations;
    j["wall_time_s"] = r.wall_time_s;
    add_provenance(j, scene);
    j["scene"] = scene.source;
    return j;
}

/// The transients' lifetime as attractors.json and gapchain-sim's design value give it.
nlohmann::ordered_json transients_json(const TransientLifetime& t) {
    return {{"from_period", t.from_period},
            {"lifetime", t.lifetime},
            {"lifetime_error", t.lifetime_error},
            {"ended", t.ended},
            {"censored", t.censored},
            {"rate_ratio", t.rate_ratio},
            {"rate_ratio_error", t.rate_ratio_error},
            {"constant_rate", to_string(t.constant_rate)},
            {"periods_until_1_percent", t.periods_until(0.01)}};
}

} // namespace

std::string row_label(const Scene& scene) {
    const ReducedParameters& p = scene.reduced;
    std::ostringstream os;
    os << "Nm=" << p.Nm << " fc=" << p.fc << " eps=";
    scene.damping_array ? os << "array" : os << p.eps;
    os << " e_r=";
    scene.clearance_array ? os << "array" : os << p.e_r;
    return os.str();
}

std::string to_json(const SimulationResult& r, const Scene& scene) {
    return simulation_json(r, scene).dump(2) + "\n";
}

namespace {

/// The run options each start of an attractor search ran with.
nlohmann::ordered_json search_run_json(const RunOptions& run) {
    return {
        {"periods", run.periods},
        {"transient_periods", run.transient_periods == auto_transient
                                  ? nlohmann::ordered_json("auto")
                                  : nlohmann::ordered_json(run.transient_periods)},
        {"scheme", to_string(run.scheme)},
        {"tolerance", run.tolerance},
        {"step", run.step ? nlohmann::ordered_json(*run.step) : nlohmann::ordered_json(nullptr)},
        {"accuracy_mode", to_string(run.accuracy_mode)},
        {"steady_state", run.stop_at_steady_state},
        {"steady_tolerance", run.steady_tolerance},
        {"max_steady_period", run.max_steady_period},
        {"max_work", run.max_work}};
}

/// The "design_value" block of a run set against its row's attractors.
json design_value_json(const DesignValue& design, const AttractorOptions& options,
                       const Scene& scene) {
    const AttractorSet& set = design.search;
    json d = {
        {"samples", options.samples},
        {"seed", options.seed},
        {"box", options.box},
        {"center", box_center(options, scene.reduced.Nm)},
        {"attractors", set.attractor_count()},
        {"unsettled", set.unsettled},
        {"failed", set.failed},
        {"F_m_max", design.F_m_max},
        {"F_m_max_error",
         std::isnan(design.F_m_max_error) ? json(nullptr) : json(design.F_m_max_error)},
        {"from_run", design.from_run},
        {"start_below", design.start_below},
        {"run_above", design.run_above},
        {"attractors_F_m_max", set.F_m_max_id >= 0 ? json(set.F_m_max) : json(nullptr)},
        {"attractors_F_m_max_error", set.F_m_max_id >= 0 ? json(set.F_m_max_error) : json(nullptr)},
        {"transients", transients_json(set.transients)},
        {"run", search_run_json(options.run)},
        {"wall_time_s", set.wall_time_s}};
    if (set.F_m_max_id >= 0) {
        const Attractor& a = set.attractors[static_cast<std::size_t>(set.F_m_max_id)];
        d["attractor"] = {{"regime", regime_label(a)},
                          {"period", a.period},
                          {"basin_fraction", a.basin_fraction},
                          {"basin_fraction_error", a.basin_fraction_error},
                          {"initial_state", a.initial_state}};
    } else {
        d["attractor"] = nullptr;
    }
    if (scene.physical) {
        d["F_m_max_newton"] = force_in_newtons(design.F_m_max, *scene.physical);
        // As gapchain-attractors and a sweep's attractors give it (it was missing here).
        d["F_m_max_error_newton"] =
            std::isnan(design.F_m_max_error)
                ? json(nullptr)
                : json(force_in_newtons(design.F_m_max_error, *scene.physical));
    }
    return d;
}

} // namespace

std::string to_json(const SimulationResult& r, const Scene& scene, const DesignValue& design,
                    const AttractorOptions& options) {
    json j = simulation_json(r, scene);
    j["multistable"] = multistable(r, design);
    j["design_value"] = design_value_json(design, options, scene);
    return j.dump(2) + "\n";
}

std::string points_csv(const BifurcationResult& result, const SectionSpec& section) {
    std::ostringstream os;
    os.precision(12);
    os << "value,direction,point,t";
    for (const auto& v : section.record)
        os << ',' << v.name();
    os << '\n';
    for (const auto& row : result.rows)
        for (const auto& p : row.points) {
            if (row.status == RunStatus::cancelled) break;
            os << row.value << ',' << to_string(row.direction) << ',' << p.values.front() << ','
               << p.t;
            for (double v : p.values)
                os << ',' << v;
            os << '\n';
        }
    return os.str();
}

std::string summary_csv(const BifurcationResult& result) {
    std::ostringstream os;
    os.precision(12);
    os << "value,direction,F_m,F_m_error,period,points,status,newton_confirmed,max_multiplier,"
          "points_from_orbit,ended_elsewhere\n";
    for (const auto& row : result.rows) {
        // A cancelled diagram's rows that did not run are left out (bifurcation.json: cancelled).
        if (row.status == RunStatus::cancelled) continue;
        os << row.value << ',' << to_string(row.direction) << ',' << row.F_m << ',' << row.F_m_error
           << ',' << row.period << ',' << row.points.size() << ',' << to_string(row.status) << ','
           << (row.newton_confirmed ? 1 : 0) << ',';
        // Not confirmed: an empty field, never "nan".
        write_if_finite(os, row.max_multiplier);
        os << ',' << (row.points_from_orbit ? 1 : 0) << ',' << (row.ended_elsewhere ? 1 : 0)
           << '\n';
    }
    return os.str();
}

namespace {
/// What each column of a diagram's CSVs holds, for bifurcation.json.
json bifurcation_columns(const BifurcationOptions& o) {
    return json(
        {{"value", "the value of " + std::string(to_string(o.parameter))},
         {"point", "the section variable " + o.section.record.front().name()},
         {"period", "forcing periods per cycle of the section (the orbit's minimal "
                    "period where Newton confirmed it); 0 = not periodic"},
         {"F_m", "largest force over the orbit Newton confirmed, else over the "
                 "recorded periods"},
         {"F_m_error", "|max over the first half - max over the second half of the recorded "
                       "periods| (sampling spread), at least tolerance * F_m; on a confirmed "
                       "orbit at least |recorded maximum - orbit's|; on a periodic row left "
                       "unconfirmed, or a confirmed one the window on a finer plan did not "
                       "reach, at least twice its difference from that window"},
         {"newton_confirmed", "1: Newton on the exact scheme converged on the "
                              "row's periodic orbit"},
         {"max_multiplier", "largest |Floquet multiplier| of the confirmed orbit; "
                            "empty unless confirmed"},
         {"points_from_orbit",
          "1: the row's points in points.csv are one cycle of the confirmed orbit "
          "(exact scheme), whose minimal period was shorter than the window's"},
         {"ended_elsewhere",
          "1: the same window on a finer plan did not reach the confirmed orbit (its maximum is "
          "more than ten bars away): the start lies near a basin boundary, and F_m_error covers "
          "twice the difference"}});
}
} // namespace

std::string to_json(const BifurcationResult& r, const BifurcationOptions& o,
                    const ReducedParameters& base) {
    json j;
    j["parameter"] = to_string(o.parameter);
    j["columns"] = bifurcation_columns(o);
    // The scheme that ran: auto resolves by the row and the tolerance, and on an fc line the
    // exact propagator can refuse one end (fc = 1e9) and take the other: "rk4 to exact".
    const auto resolved = [&](double value) {
        return std::string(
            to_string(plan_step(Dynamics::paper_row(with_value(base, o.parameter, value)), o.scheme,
                                o.tolerance)
                          .scheme));
    };
    const std::string at_from = resolved(o.from), at_to = resolved(o.to);
    j["scheme"] = at_from == at_to ? at_from : at_from + " to " + at_to;
    j["scheme_requested"] = std::string(to_string(o.scheme));
    j["tolerance"] = o.tolerance;
    double largest_error = 0.0;
    for (const auto& row : r.rows)
        largest_error = std::max(largest_error, row.F_m_error);
    j["max_F_m_error"] = largest_error;
    // Whether periodic rows were confirmed by Newton (not --no-newton), and how many were.
    j["newton_confirmation"] = o.confirm_by_newton;
    j["periodic_rows"] = std::count_if(r.rows.begin(), r.rows.end(),
                                       [](const BifurcationRow& row) { return row.period > 0; });
    j["newton_confirmed_rows"] =
        std::count_if(r.rows.begin(), r.rows.end(),
                      [](const BifurcationRow& row) { return row.newton_confirmed; });
    j["points_from_orbit_rows"] =
        std::count_if(r.rows.begin(), r.rows.end(),
                      [](const BifurcationRow& row) { return row.points_from_orbit; });
    j["ended_elsewhere_rows"] =
        std::count_if(r.rows.begin(), r.rows.end(),
                      [](const BifurcationRow& row) { return row.ended_elsewhere; });
    j["from"] = o.from;
    j["to"] = o.to;
    j["steps"] = o.steps;
    j["mode"] = o.mode == SweepMode::independent ? "independent" : "continuation";
    j["transient_periods"] = o.transient_periods;
    j["record_periods"] = o.record_periods;
    j["phase"] = o.section.phase;
    j["base"] = {
        {"Nm", base.Nm}, {"fc", base.fc}, {"eps", base.eps}, {"e_r", base.e_r}, {"f_r", base.f_r}};
    j["cancelled"] = r.cancelled;
    j["rows_done"] = std::count_if(r.rows.begin(), r.rows.end(), [](const BifurcationRow& row) {
        return row.status != RunStatus::cancelled;
    });
    j["threads_used"] = r.threads_used;
    j["wall_time_s"] = r.wall_time_s;
    return j.dump(2) + "\n";
}

std::string mode_shapes_csv(const ModalResult& r, int Nm) {
    std::ostringstream os;
    os.precision(12);
    os << "body";
    for (int k : r.mode_numbers)
        os << ",mode" << k;
    os << '\n';
    for (int i = 0; i < Nm; ++i) {
        os << i + 1;
        for (const auto& shape : r.shapes)
            os << ',' << shape[i];
        os << '\n';
    }
    return os.str();
}

std::string to_json(const ModalResult& r, int Nm, double fc) {
    json j;
    j["Nm"] = Nm;
    j["fc"] = fc;
    j["mode_numbers"] = r.mode_numbers;
    j["frequencies"] = r.frequencies;
    j["approx"] = r.approx;
    j["rel_error"] = r.rel_error;
    j["residuals"] = r.residuals;
    if (!r.shapes.empty()) j["shapes"] = r.shapes;
    j["method"] = std::string(to_string(r.method));
    j["status"] = r.status == ModalStatus::converged       ? "converged"
                  : r.status == ModalStatus::not_converged ? "not_converged"
                                                           : "numerical_issue";
    j["iterations"] = r.iterations;
    j["wall_time_s"] = r.wall_time_s;
    return j.dump(2) + "\n";
}

std::string grid_csv(const ApproximationGrid& grid) {
    std::ostringstream os;
    os.precision(10);
    os << "Nm,fc,f1_error,other_error,other_mode\n";
    for (const auto& p : grid.points)
        os << p.Nm << ',' << p.fc << ',' << p.first << ',' << p.other << ',' << p.other_mode
           << '\n';
    return os.str();
}

std::string to_json(const WorkPrecision& study, const WorkPrecisionOptions& o, double target,
                    const Scene& scene) {
    json orders = json::object();
    for (const Scheme s : {Scheme::central_difference, Scheme::rk4})
        for (const bool split : {true, false})
            if (const auto q = observed_order(study, s, split))
                orders[std::string(to_string(s)) + (split ? "" : " (no split)")] = *q;
    json fastest = nullptr;
    if (const auto best = fastest_for(study, target))
        fastest = {{"scheme", to_string(best->scheme)},
                   {"tolerance", best->tolerance},
                   {"F_m_error", best->F_m_error},
                   {"wall_time_s", best->wall_time_s}};
    json j = {{"F_m_reference", study.F_m_reference},
              {"F_m_reference_error", study.F_m_reference_error},
              {"F_m_reference_scheme", "exact, half its default interval"},
              {"periods", o.periods},
              {"runs", study.points.size()},
              {"observed_order", orders},
              {"target", target},
              {"fastest_for_target", fastest},
              {"cancelled", study.cancelled},
              {"wall_time_s", study.wall_time_s}};
    add_provenance(j, scene, true);
    // The study sets its runs' length and tolerances itself: the scene's are not what ran.
    for (const char* key : {"periods", "transient_periods", "tolerance"})
        j["parameters"].erase(key);
    return j.dump(2) + "\n";
}

std::string to_json(const RowSpectrum& s, const RowSpectrumOptions& o, const Scene& scene) {
    const auto estimated = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
    json j = {{"variable", o.variable},
              {"samples_per_period", o.samples_per_period},
              {"samples", s.samples},
              {"sample_rate", s.sample_rate},
              {"segment", s.segment},
              {"segments", s.psd.segments},
              {"segment_periods", s.segment_periods},
              {"whole_periods", s.whole_periods},
              {"order", o.order},
              {"broadband_share", s.content.broadband_share},
              {"broadband_share_error", estimated(s.content.broadband_share_error)},
              {"fraction_bin_share", s.content.fraction_bin_share},
              {"aliased_share", s.aliased_share},
              {"sampled_range_share", s.sampled_range_share},
              {"peaks", s.content.peaks.size()},
              {"window", o.window == Window::hann ? "hann" : "rectangular"},
              {"status", to_string(s.outcome.status)},
              {"wall_time_s", s.wall_time_s}};
    add_provenance(j, scene, true);
    // A result read alone says how its record was made (a reviewer's probe, helper-75).
    add_scheme_and_step(j, scene, s.outcome);
    return j.dump(2) + "\n";
}

std::string to_json(const SectionSpec& spec, long points, int repeats_every,
                    const SectionAccuracy* accuracy, double wall_time_s, const Scene& scene,
                    const RunOutcome& outcome) {
    json j;
    json section = {{"kind", spec.kind == SectionSpec::Kind::event ? "event" : "stroboscopic"}};
    if (spec.kind == SectionSpec::Kind::event) {
        section["trigger"] = spec.trigger.name();
        section["level"] = spec.level;
        section["direction"] = spec.direction == CrossingDirection::up     ? "up"
                               : spec.direction == CrossingDirection::down ? "down"
                                                                           : "both";
    } else {
        section["phase"] = spec.phase;
    }
    json record = json::array();
    for (const auto& v : spec.record)
        record.push_back(v.name());
    section["record"] = record;
    j["section"] = section;
    j["points"] = points;
    j["repeats_every"] = repeats_every > 0 ? json(repeats_every) : json(nullptr);
    if (accuracy) {
        json error = json::object();
        for (std::size_t i = 0; i < spec.record.size(); ++i)
            error[spec.record[i].name()] =
                std::isnan(accuracy->error[i]) ? json(nullptr) : json(accuracy->error[i]);
        j["point_error"] = {
            {"compared", accuracy->compared},
            {"error", error},
            {"parted_at", accuracy->parted_at < 0 ? json(nullptr) : json(accuracy->parted_at)},
            {"crossings_differ", accuracy->crossings_differ},
            {"finer_repeats", accuracy->finer_repeats},
            {"comparison", accuracy->comparison},
            {"status", to_string(accuracy->status)},
            {"not_estimated",
             accuracy->not_estimated.empty() ? json(nullptr) : json(accuracy->not_estimated)}};
    } else {
        j["point_error"] = nullptr;
    }
    j["wall_time_s"] = wall_time_s;
    add_provenance(j, scene, true);
    // The error estimate's finer plan follows from them.
    add_scheme_and_step(j, scene, outcome);
    return j.dump(2) + "\n";
}

std::string to_json(const LyapunovResult& r, const Scene& scene) {
    json j;
    j["exponents"] = r.exponents;
    j["error"] = r.errors;
    // One standard error, not a bound: say so where the number is read.
    j["error_kind"] = r.drifting ? "standard error over 10 time blocks, or the block rates' "
                                   "drift over the window for an exponent whose rates drift"
                                 : "standard error over 10 time blocks";
    j["drifting"] = r.drifting;
    j["sum"] = r.sum;
    if (!std::isnan(r.expected_sum)) j["expected_sum"] = r.expected_sum;
    j["averaging_time"] = r.averaging_time;
    j["units"] = "1 / reduced time";
    j["status"] = std::string(to_string(r.status));
    j["scheme"] = std::string(to_string(r.scheme));
    j["step"] = r.step;
    j["wall_time_s"] = r.wall_time_s;
    add_provenance(j, scene, true);
    return j.dump(2) + "\n";
}

std::string branch_csv(const ContinuationResult& result) {
    std::ostringstream os;
    os.precision(15); // F_m errors reach 1e-13 F_m: the digits must show them
    os << "value,period,F_m,F_m_error,u1,stable,max_multiplier,branch,minimal_period\n";
    for (const auto& p : result.points) {
        os << p.value << ',' << p.period << ',' << p.F_m << ',';
        write_if_finite(os, p.F_m_error);
        os << ',' << p.u1 << ',' << (p.stable ? 1 : 0) << ',' << p.max_multiplier << ',' << p.branch
           << ',' << p.minimal_period << '\n';
    }
    return os.str();
}

std::string special_csv(const ContinuationResult& result) {
    std::ostringstream os;
    os.precision(15); // F_m errors reach 1e-13 F_m: the digits must show them
    os << "type,value,period,F_m,F_m_error,branch,contact,value_error,minimal_period\n";
    for (const auto& s : result.special) {
        os << to_string(s.type) << ',' << s.value << ',' << s.period << ',' << s.F_m << ',';
        write_if_finite(os, s.F_m_error);
        os << ',' << s.branch << ',' << s.contact << ',' << s.value_error << ',' << s.minimal_period
           << '\n';
    }
    return os.str();
}

std::string to_json(const ContinuationResult& r, const ContinuationOptions& o, const Scene& scene) {
    nlohmann::ordered_json j;
    j["parameter"] = std::string(to_string(o.parameter));
    j["from"] = o.from;
    j["to"] = o.to;
    j["period"] = o.period;
    j["step"] = o.step;
    j["max_step"] = o.max_step;
    j["max_points"] = o.max_points;
    j["follow_doublings"] = o.follow_doublings;
    j["max_branches"] = o.max_branches;
    j["locate_tolerance"] = o.locate_tolerance;
    j["transient_periods"] = o.transient_periods;
    j["scheme"] = std::string(to_string(o.orbit.scheme));
    j["integration_tolerance"] = o.orbit.integration_tolerance;
    j["orbit_tolerance"] = o.orbit.tolerance;
    j["orbits"] = r.points.size();
    j["branches"] = r.branch_end.size();
    j["special_points"] = r.special.size();
    j["branch_end"] = r.branch_end;
    j["unfollowed"] = r.unfollowed;
    const ForceErrorSummary errors = force_error_summary(r);
    j["max_F_m_error"] = errors.largest;
    j["F_m_errors_not_estimated"] = errors.unestimated;
    j["shootings"] = r.shootings;
    j["cancelled"] = r.cancelled;
    j["wall_time_s"] = r.wall_time_s;
    // The row's numbers as read, the continued one replaced along the branches.
    j["base"] = parameters_json(scene.reduced);
    j["scene"] = scene.source;
    return j.dump(2) + "\n";
}

namespace {

void attractor_row(std::ostream& os, const Attractor& a) {
    os << a.id << ',' << regime_label(a) << ',' << a.period << ',' << a.F_m << ',' << a.F_m_error
       << ',';
    // Not computed (an orbit Newton did not confirm): an empty field, never "nan".
    write_if_finite(os, a.lambda_max);
    os << ',';
    write_if_finite(os, a.lambda_max_error);
    os << ',' << a.basin_fraction << ',' << a.basin_fraction_error << ',' << a.samples << ','
       << a.slice_points << ',' << a.settle_median << ',' << a.settle_max << ',' << a.still_settling
       << ',' << a.F_m_runs << ',' << a.F_m_runs_error << ',' << a.members_continued << ','
       << a.left_for_orbits << '\n';
}

} // namespace

std::string attractors_csv(const AttractorSet& set) {
    std::ostringstream os;
    os.precision(15); // F_m errors reach 1e-13 F_m: the digits must show them
    os << "id,regime,period,F_m,F_m_error,lambda_max,lambda_max_error,basin_fraction,"
          "basin_fraction_error,samples,slice_points,settle_median,settle_max,still_settling,"
          "F_m_runs,F_m_runs_error,members_continued,left_for_orbits\n";
    for (const auto& a : set.attractors)
        attractor_row(os, a);
    return os.str();
}

std::string attractor_starts_csv(const AttractorSet& set,
                                 const std::vector<std::vector<double>>& starts) {
    if (starts.size() < set.sample_attractor.size())
        throw std::invalid_argument("starts: " + std::to_string(starts.size()) + " states for " +
                                    std::to_string(set.sample_attractor.size()) + " starts");
    const std::size_t bodies = starts.empty() ? 0 : starts.front().size() / 2;
    std::ostringstream os;
    os << "start,attractor,settle_period,F_m_run";
    for (const char* name : {"u", "v"})
        for (std::size_t i = 1; i <= bodies; ++i)
            os << ',' << name << i;
    os << '\n';
    // Without the states a start could not be run again (an independent review, helper-88):
    // only each attractor's first one was in attractors.json.
    for (std::size_t k = 0; k < set.sample_attractor.size(); ++k) {
        os.precision(12);
        os << k << ',' << set.sample_attractor[k] << ',' << set.sample_settle_period[k] << ','
           << set.sample_F_m[k];
        os.precision(17);
        for (const double x : starts[k])
            os << ',' << x;
        os << '\n';
    }
    return os.str();
}

namespace {

/// Each group of a search, as attractors.json lists them.
nlohmann::ordered_json attractor_list_json(const AttractorSet& set,
                                           const std::optional<PhysicalParameters>& physical) {
    auto list = nlohmann::ordered_json::array();
    for (const auto& a : set.attractors)
        list.push_back({{"id", a.id},
                        {"regime", regime_label(a)},
                        {"period", a.period},
                        {"newton_confirmed", a.newton_confirmed},
                        {"max_multiplier", a.max_multiplier},
                        {"F_m", a.F_m},
                        {"F_m_error", a.F_m_error},
                        {"lambda_max", a.lambda_max},
                        {"lambda_max_error", a.lambda_max_error},
                        {"basin_fraction", a.basin_fraction},
                        {"basin_fraction_error", a.basin_fraction_error},
                        {"samples", a.samples},
                        {"slice_points", a.slice_points},
                        {"settle_median", a.settle_median},
                        {"settle_max", a.settle_max},
                        {"still_settling", a.still_settling},
                        {"F_m_runs", a.F_m_runs},
                        {"F_m_runs_error", a.F_m_runs_error},
                        {"members_continued", a.members_continued},
                        {"left_for_orbits", a.left_for_orbits},
                        {"initial_state", a.initial_state},
                        {"state", a.state}});
    if (physical)
        for (auto& a : list)
            a["F_m_newton"] = force_in_newtons(a["F_m"].get<double>(), *physical);
    return list;
}

/// The attractors of one search, with its options and row: attractors.json, and each value of
/// fractions.json.
nlohmann::ordered_json attractor_set_json(const AttractorSet& set, const AttractorOptions& o,
                                          const ReducedParameters& p,
                                          const std::optional<PhysicalParameters>& physical) {
    nlohmann::ordered_json j;
    // No attractor (every start failed, or a cancelled search): null, where 0 read as a value.
    const bool found = set.F_m_max_id >= 0;
    j["F_m_max"] = found ? json(set.F_m_max) : json(nullptr);
    j["F_m_max_error"] = found ? json(set.F_m_max_error) : json(nullptr);
    if (physical) {
        j["F_m_max_newton"] =
            found ? json(force_in_newtons(set.F_m_max, *physical)) : json(nullptr);
        j["F_m_max_error_newton"] =
            found ? json(force_in_newtons(set.F_m_max_error, *physical)) : json(nullptr);
    }
    j["F_m_max_attractor"] = set.F_m_max_id;
    j["unsettled"] = set.unsettled;
    // An unsettled group is a transient's, not an attractor: the count is of settled ones, as
    // the tools' headline says; "attractors" lists every group.
    j["attractor_count"] = set.attractor_count();
    j["group_count"] = set.attractors.size();
    j["attractors"] = attractor_list_json(set, physical);
    j["transients"] = transients_json(set.transients);
    j["samples"] = o.samples;
    j["failed"] = set.failed;
    j["confirmation_periods"] = set.confirmation_periods;
    j["seed"] = o.seed;
    j["box"] = o.box;
    // Rest written out, so a reader need not know the default.
    j["center"] = box_center(o, p.Nm);
    j["amplitude"] = set.amplitude;
    j["section_points"] = o.section_points;
    // What a run that does not settle kept: one point a recorded period, so at most the
    // recorded periods (--section-points 100000 over 50 was written as 100000).
    const RunOptions resolved = with_transient_resolved(Dynamics::paper_row(p), o.run);
    j["section_points_kept"] =
        std::min<long>(o.section_points, resolved.periods - resolved.transient_periods);
    j["run"] = search_run_json(o.run);
    j["parameters"] = parameters_json(p);
    j["threads"] = set.threads_used;
    j["wall_time_s"] = set.wall_time_s;
    return j;
}

} // namespace

std::string to_json(const AttractorSet& set, const AttractorOptions& o, const Scene& scene) {
    return attractor_set_json(set, o, scene.reduced, scene.physical).dump(2) + "\n";
}

std::string to_json(const FractionContinuation& c, const AttractorOptions& o, const Scene& scene) {
    const ReducedParameters& base = scene.reduced;
    nlohmann::ordered_json j;
    j["parameter"] = to_string(c.parameter);
    j["values"] = c.values;
    j["label_count"] = c.label_count;
    j["base"] = parameters_json(base);
    auto points = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < c.sets.size(); ++k) {
        nlohmann::ordered_json point;
        point["value"] = c.values[k];
        point["labels"] = c.labels[k];
        point["search"] = attractor_set_json(
            c.sets[k], o, with_value(base, c.parameter, c.values[k]), scene.physical);
        points.push_back(std::move(point));
    }
    j["points"] = points;
    j["cancelled"] = c.cancelled;
    j["wall_time_s"] = c.wall_time_s;
    return j.dump(2) + "\n";
}

std::string basin_slice_csv(const AttractorSet& set) {
    std::ostringstream os;
    // Round-trip digits: a tiny box around a center far from 0 has grid steps near 1e-12 of
    // the values.
    os.precision(17);
    os << "x,y,attractor\n";
    const std::size_t nx = set.slice_first.size();
    for (std::size_t k = 0; k < set.slice_attractor.size(); ++k)
        os << set.slice_first[k % nx] << ',' << set.slice_second[k / nx] << ','
           << set.slice_attractor[k] << '\n';
    return os.str();
}

std::string fractions_csv(const FractionContinuation& c) {
    std::ostringstream os;
    os.precision(15); // F_m errors reach 1e-13 F_m: the digits must show them
    os << "value";
    for (int label = 0; label < c.label_count; ++label)
        os << ",fraction_" << label << ",fraction_error_" << label << ",F_m_" << label
           << ",F_m_error_" << label << ",period_" << label;
    os << ",transient_lifetime,transient_lifetime_error\n";
    for (std::size_t k = 0; k < c.sets.size(); ++k) {
        os << c.values[k];
        const auto& labels = c.labels[k];
        for (int label = 0; label < c.label_count; ++label) {
            const auto it = std::find(labels.begin(), labels.end(), label);
            // Absent: none of the N starts reached it, which bounds its fraction to about 1/N
            // (as basin_fraction_error's floor), not to 0; no F_m, no period.
            if (it == labels.end()) {
                os << ",0," << 1.0 / static_cast<double>(c.sets[k].sample_attractor.size())
                   << ",,,";
                continue;
            }
            const Attractor& a =
                c.sets[k].attractors[static_cast<std::size_t>(it - labels.begin())];
            os << ',' << a.basin_fraction << ',' << a.basin_fraction_error << ',' << a.F_m << ',';
            write_if_finite(os, a.F_m_error);
            os << ',' << a.period;
        }
        os << ',';
        write_if_finite(os, c.sets[k].transients.lifetime);
        os << ',';
        write_if_finite(os, c.sets[k].transients.lifetime_error);
        os << '\n';
    }
    return os.str();
}

std::string to_json(const PeriodicOrbit& orbit, const Scene& scene) {
    nlohmann::ordered_json j;
    j["status"] = std::string(to_string(orbit.status));
    if (!orbit.message.empty()) j["message"] = orbit.message;
    j["period"] = orbit.period;
    j["minimal_period"] = orbit.minimal_period;
    j["state"] = orbit.state;
    j["residual"] = orbit.residual;
    j["iterations"] = orbit.iterations;
    j["residual_history"] = orbit.residual_history;
    auto multipliers = nlohmann::ordered_json::array();
    for (const auto& mu : orbit.multipliers)
        multipliers.push_back({mu.real(), mu.imag()});
    j["multipliers"] = multipliers;
    j["max_multiplier"] = orbit.max_multiplier;
    j["max_multiplier_error"] = std::isnan(orbit.max_multiplier_error)
                                    ? nlohmann::ordered_json(nullptr)
                                    : nlohmann::ordered_json(orbit.max_multiplier_error);
    j["stable"] = orbit.stable;
    j["liouville_error"] = orbit.liouville_error;
    j["F_m"] = orbit.F_m;
    j["F_m_error"] = std::isnan(orbit.F_m_error) ? nlohmann::ordered_json(nullptr)
                                                 : nlohmann::ordered_json(orbit.F_m_error);
    if (scene.physical) {
        j["F_m_newton"] = force_in_newtons(orbit.F_m, *scene.physical);
        j["F_m_error_newton"] =
            std::isnan(orbit.F_m_error)
                ? nlohmann::ordered_json(nullptr)
                : nlohmann::ordered_json(force_in_newtons(orbit.F_m_error, *scene.physical));
    }
    auto contacts = nlohmann::ordered_json::array();
    for (std::size_t c = 0; c < orbit.per_contact.size(); ++c)
        contacts.push_back({{"contact", c},
                            {"force", orbit.per_contact[c].force},
                            {"time", orbit.per_contact[c].time},
                            {"impacts", orbit.per_contact[c].impacts},
                            {"max_gap", orbit.max_gap[c]}});
    j["per_contact"] = contacts;
    j["scheme"] = std::string(to_string(orbit.scheme));
    j["integration_tolerance"] = orbit.integration_tolerance;
    j["wall_time_s"] = orbit.wall_time_s;
    j["parameters"] = scene_parameters_json(scene);
    // The five numbers do not name a row of arrays or a scatter (its eps was not what ran).
    if (scene.row) j["chain"] = chain_json(scene);
    j["scene"] = scene.source;
    return j.dump(2) + "\n";
}

std::string history_csv(const LyapunovResult& r) {
    std::ostringstream os;
    os.precision(10);
    os << "t";
    for (std::size_t k = 0; k < r.exponents.size(); ++k)
        os << ",lambda" << k + 1;
    os << '\n';
    for (const auto& h : r.history) {
        os << h.t;
        for (double x : h.exponents)
            os << ',' << x;
        os << '\n';
    }
    return os.str();
}

namespace {
json classification_json(const Classification& c) {
    json j;
    j["regime"] = std::string(to_string(c.regime));
    j["period"] = c.period;
    j["lambda_max"] = c.lambda_max;
    j["lambda_max_error"] =
        std::isfinite(c.lambda_max_error) ? json(c.lambda_max_error) : json(nullptr);
    j["F_m"] = c.F_m;
    j["F_m_error"] = c.F_m_error;
    j["distinct_points"] = c.distinct_points;
    j["section_points"] = c.section_points;
    j["broadband_share"] = c.broadband_share;
    j["broadband_share_error"] =
        std::isfinite(c.broadband_share_error) ? json(c.broadband_share_error) : json(nullptr);
    j["stopped_at_steady_state"] = c.stopped_at_steady_state;
    j["start_up_periods"] = c.start_up_periods;
    j["start_up_in_record"] = c.start_up_in_record;
    j["settled_in_record"] = c.settled_in_record;
    j["twin_checked"] = c.twin_checked;
    j["start_dependent"] = c.twin_checked ? json(c.start_dependent) : json(nullptr);
    if (c.twin) {
        const Classification& t = *c.twin;
        j["twin"] = {{"regime", std::string(to_string(t.regime))},
                     {"period", t.period},
                     {"F_m", t.F_m},
                     {"F_m_error", t.F_m_error},
                     {"lambda_max", t.lambda_max},
                     {"lambda_max_error",
                      std::isfinite(t.lambda_max_error) ? json(t.lambda_max_error) : json(nullptr)},
                     {"newton_confirmed", t.newton_confirmed},
                     {"settled_in_record", t.settled_in_record},
                     {"status", std::string(to_string(t.status))}};
    }
    j["newton_confirmed"] = c.newton_confirmed;
    if (c.newton_confirmed) j["max_multiplier"] = c.max_multiplier;
    j["periods_run"] = c.periods_run;
    j["scheme"] = std::string(to_string(c.scheme_used));
    j["tolerance_used"] = c.tolerance_used;
    j["status"] = std::string(to_string(c.status));
    j["wall_time_s"] = c.wall_time_s;
    return j;
}
} // namespace

namespace {

/// How a point was classified: its run's lengths, scheme and accuracy, the checks it ran, and its
/// start where that is not rest (a result read alone names the start it ran).
json classify_options_json(const ClassifyOptions& o) {
    json j = {{"transient_periods", o.transient_periods},
              {"record_periods", o.record_periods},
              {"scheme", to_string(o.scheme)},
              {"tolerance", o.tolerance},
              {"max_work", o.max_work},
              {"max_period", o.max_period},
              {"confirm_by_newton", o.confirm_by_newton},
              {"twin_check", o.twin_check}};
    if (std::any_of(o.initial.begin(), o.initial.end(), [](double x) { return x != 0.0; }))
        j["initial"] = o.initial;
    return j;
}

} // namespace

std::string to_json(const Classification& c, const ClassifyOptions& o, const ReducedParameters& p) {
    json j = classification_json(c);
    j["parameters"] = parameters_json(p);
    j["options"] = classify_options_json(o);
    return j.dump(2) + "\n";
}

std::string to_json(const Classification& c, const ClassifyOptions& o, const Scene& scene,
                    const DesignValue& design, const AttractorOptions& options) {
    json j = classification_json(c);
    j["parameters"] = parameters_json(scene.reduced);
    j["options"] = classify_options_json(o);
    const LabelInSearch where = label_in_search(c, design);
    // A record of a chaotic attractor above the search's records of it is one attractor
    // sampled longer, not a second steady state.
    j["multistable"] = c.start_dependent || design.start_below ||
                       (design.run_above && where != LabelInSearch::attractor);
    j["label_in_search"] =
        where == LabelInSearch::not_applicable ? json(nullptr) : json(to_string(where));
    j["design_value"] = design_value_json(design, options, scene);
    return j.dump(2) + "\n";
}

std::string map_csv(const RegimeMap& map) {
    std::ostringstream os;
    os.precision(10);
    os << "e_r,f_r,regime,code,period,F_m,lambda_max,lambda_max_error,distinct_points,broadband_"
          "share,F_m_error,broadband_share_error,start_dependent,settled_in_record\n";
    for (std::size_t i = 0; i < map.e_r.size(); ++i)
        for (std::size_t k = 0; k < map.f_r.size(); ++k) {
            const Classification& c = map.cells[i * map.f_r.size() + k];
            // A cancelled map's cells that did not run are left out, not listed as no contact.
            if (c.status == RunStatus::cancelled) continue;
            os << map.e_r[i] << ',' << map.f_r[k] << ',' << to_string(c.regime) << ','
               << static_cast<int>(c.regime) << ',' << c.period << ',' << c.F_m << ','
               << c.lambda_max << ',';
            write_if_finite(os, c.lambda_max_error);
            os << ',' << c.distinct_points << ',' << c.broadband_share << ',' << c.F_m_error << ',';
            write_if_finite(os, c.broadband_share_error);
            os << ',';
            if (c.twin_checked) os << (c.start_dependent ? 1 : 0);
            os << ',' << (c.settled_in_record ? 1 : 0) << '\n';
        }
    return os.str();
}

std::string psd_csv(const Psd& psd, double f_r) {
    std::ostringstream os;
    os.precision(10);
    os << "f,f_over_f_r,density\n";
    for (std::size_t k = 0; k < psd.frequency.size(); ++k)
        os << psd.frequency[k] << ',' << psd.frequency[k] / f_r << ',' << psd.density[k] << '\n';
    return os.str();
}

std::string to_json(const AnalyticEstimates& a, const Scene& scene, double wall_time_s) {
    json j;
    j["parameters"] = scene_parameters_json(scene);
    j["eq20_amplitude"] = a.amplitude;
    j["impacts"] = a.impacts;
    j["eq21_wall_contact_frequency"] = a.wall_contact_frequency;
    j["f1"] = a.f1;
    j["f1_eq26"] = a.f1_approx;
    const std::pair<const char*, double> forces[] = {
        {"eq24_smooth_max_force", a.smooth_max_force},
        {"eq25_smooth_bound", a.smooth_bound},
        {"eq36_chaotic_estimate", a.chaotic_estimate_approx},
        {"eq32_34_chaotic_estimate_exact_f1", a.chaotic_estimate_exact},
        {"eq37_chaotic_bound", a.chaotic_bound}};
    for (const auto& [key, value] : forces) {
        j[key] = std::isfinite(value) ? json(value) : json(nullptr);
        if (scene.physical && std::isfinite(value))
            j[std::string(key) + "_N"] = force_in_newtons(value, *scene.physical);
    }
    j["wall_time_s"] = wall_time_s;
    return j.dump(2) + "\n";
}

std::string peaks_csv(const SpectralContent& content, double f_r) {
    std::ostringstream os;
    os.precision(10);
    // The error columns come last: scripts that read the first four keep working. An error
    // not estimated (a single segment) is an empty field.
    os << "f,f_over_f_r,power,label,f_error,power_error\n";
    for (const auto& pk : content.peaks) {
        os << pk.frequency << ',' << pk.frequency / f_r << ',' << pk.power << ',' << pk.label()
           << ',' << pk.frequency_error << ',';
        write_if_finite(os, pk.power_error);
        os << '\n';
    }
    return os.str();
}

std::string work_precision_csv(const WorkPrecision& study) {
    std::ostringstream os;
    os.precision(10);
    os << "scheme,tolerance,step,F_m,F_m_error,final_error,l2_error,seconds,evaluations\n";
    for (const auto& p : study.points)
        os << to_string(p.scheme) << (p.split ? "" : "-nosplit") << ',' << p.tolerance << ','
           << p.step << ',' << p.F_m << ',' << p.F_m_error << ',' << p.final_error << ','
           << p.l2_error << ',' << p.wall_time_s << ',' << p.evaluations << '\n';
    return os.str();
}

std::string sweep_csv_header(const Study& study) {
    std::string h = "index";
    for (const auto& a : study.axes)
        h += ",axis:" + a.key;
    h += ",Nm,fc,eps,e_r,f_r,F_m,F_m_error,status,multistable";
    // Read as the study reads its scene: a record file lies next to the study, not in the
    // working folder (which was searched, and refused a study run from elsewhere).
    const bool physical =
        parse_scene(study.scene_json, {}, study.source + " scene").physical.has_value();
    if (physical) h += ",F_m_newton,F_m_error_newton";
    if (study.attractor_starts > 0) h += ",F_m_max,F_m_max_error,attractors,unsettled";
    // Only as the last of those: a reduced study's columns stay where they were.
    if (study.attractor_starts > 0 && physical) h += ",F_m_max_newton,F_m_max_error_newton";
    if (study.keep.steady_state) h += ",steady_state_period,longer_cycle_period";
    if (study.keep.wall_time) h += ",wall_time_s";
    if (study.keep.orbit) h += ",F_m_orbit,F_m_orbit_error,maximum_in_transient";
    if (study.keep.regime)
        h += ",regime,period,lambda_max,lambda_max_error,regime_start_dependent,"
             "regime_settled_in_record";
    if (study.keep.per_body) h += ",per_body,per_body_error";
    return h;
}

namespace {
/// A sweep row's steady_state_period and longer_cycle_period cells (with their leading commas),
/// each empty where the run found none.
void write_period_cells(std::ostream& os, const SimulationResult& s) {
    os << ',';
    if (s.steady_state_period) os << *s.steady_state_period;
    os << ',';
    if (s.longer_cycle_period) os << *s.longer_cycle_period;
}

/// A sweep row's regime cells: regime,period,lambda_max,lambda_max_error,regime_start_dependent
/// (with their leading commas).
void write_regime_cells(std::ostream& os, const Classification& c) {
    os << ',' << to_string(c.regime) << ',' << c.period << ',' << c.lambda_max << ',';
    write_if_finite(os, c.lambda_max_error);
    // Empty where no twin ran (a settled label), as multistable's cell: never 0 unchecked.
    os << ',';
    if (c.twin_checked) os << (c.start_dependent ? 1 : 0);
    // As map.csv's last column: a label whose transient ended while recording is its steady
    // state's, and the sweep row said nothing of it.
    os << ',' << (c.settled_in_record ? 1 : 0);
}
} // namespace

std::string sweep_csv_row(const Study& study, const SweepPointResult& r) {
    std::ostringstream os;
    os.precision(12);
    os << r.index;
    for (double v : r.values)
        os << ',' << v;
    const ReducedParameters& p = r.parameters;
    const SimulationResult& s = r.simulation;
    os << ',' << p.Nm << ',' << p.fc << ',' << p.eps << ',' << p.e_r << ',';
    // A record has no forcing frequency: its reduced 1 read as one (as the sim JSON's null).
    if (r.harmonic) os << p.f_r;
    os << ',' << s.F_m << ',';
    if (has_error_estimate(s)) os << s.F_m_error;
    os << ',' << to_string(s.status) << ',';
    // Unknown where the check was off and no attractor search ran: empty, never 0.
    if (r.multistable || s.multistability_checked || study.attractor_starts > 0)
        os << (r.multistable ? 1 : 0);
    if (r.F_m_newton) {
        os << ',' << *r.F_m_newton << ',';
        // As F_m_error's cell: the number, inf where a comparison run went non-finite.
        if (r.F_m_error_newton) os << *r.F_m_error_newton;
    }
    if (study.attractor_starts > 0) {
        os << ',' << (r.F_m_max ? *r.F_m_max : s.F_m) << ',';
        if (r.F_m_max)
            write_if_finite(os, r.F_m_max_error);
        else if (has_error_estimate(s))
            os << s.F_m_error;
        os << ',' << r.attractors_found << ',' << r.attractors_unsettled;
        if (r.F_m_max_newton) {
            os << ',' << *r.F_m_max_newton << ',';
            write_if_finite(os, r.F_m_max_error_newton.value_or(std::nan("")));
        }
    }
    if (study.keep.steady_state) write_period_cells(os, s);
    if (study.keep.wall_time) os << ',' << s.wall_time_s;
    if (study.keep.orbit) {
        os << ',';
        // Both empty where the run settled on no orbit: there is no orbit maximum to compare
        // (a 0 there read as "the maximum was the orbit's").
        if (s.F_m_orbit) os << *s.F_m_orbit;
        os << ',';
        if (s.F_m_orbit_error) os << *s.F_m_orbit_error;
        os << ',';
        if (s.F_m_orbit) os << (s.maximum_in_transient ? 1 : 0);
    }
    if (study.keep.regime && r.regime) write_regime_cells(os, *r.regime);
    if (study.keep.per_body) {
        os << ',';
        for (std::size_t i = 0; i < s.per_body.size(); ++i)
            os << (i ? ";" : "") << s.per_body[i].left << '|' << s.per_body[i].right;
        // Empty where no comparison run estimated the per-contact errors (as F_m_error's cell).
        os << ',';
        if (!s.per_contact_error.empty())
            for (std::size_t i = 0; i < s.per_body.size(); ++i)
                os << (i ? ";" : "") << s.per_body[i].left_error << '|'
                   << s.per_body[i].right_error;
    }
    return os.str();
}

namespace {

/// FNV-1a of text, as 16 hex digits: stable across runs and builds.
std::string fnv1a_hex(const std::string& text) {
    std::uint64_t h = 1469598103934665603ULL;
    for (const unsigned char c : text) {
        h ^= c;
        h *= 1099511628211ULL;
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

/// The bytes of a record scene's excitation.file (resolved as the scene reader resolves it,
/// from the study's folder), or empty: the scene names the file, not what it holds, and a
/// resumed sweep over a changed record mixed rows of two records.
std::string record_text(const nlohmann::ordered_json& scene, const std::string& source) {
    const auto excitation = scene.find("excitation");
    if (excitation == scene.end() || !excitation->is_object() ||
        excitation->value("type", nlohmann::ordered_json("harmonic")) != "record" ||
        !excitation->contains("file") || !(*excitation)["file"].is_string())
        return {};
    try {
        return detail::read_text_file(
            detail::scene_relative_path((*excitation)["file"].get<std::string>(), source),
            "excitation.file");
    } catch (const std::exception&) {
        return {}; // the scene reader refuses it, by name
    }
}

} // namespace

std::string study_fingerprint(const Study& study, int results_version) {
    nlohmann::ordered_json j;
    j["scene"] = nlohmann::ordered_json::parse(study.scene_json);
    if (const std::string record = record_text(j["scene"], study.source); !record.empty())
        j["record"] = fnv1a_hex(record);
    for (const auto& a : study.axes)
        j["parameters"].push_back({a.key, a.values});
    j["sampling"] = {static_cast<int>(study.sampling), study.samples, study.seed};
    j["columns"] = sweep_csv_header(study);
    j["attractors"] = study.attractor_starts;
    j["results_version"] = results_version;
    return fnv1a_hex(j.dump());
}

void check_resume(const std::string& results_csv, const Study& study) {
    std::error_code ec;
    if (!std::filesystem::exists(results_csv, ec) ||
        std::filesystem::file_size(results_csv, ec) == 0)
        return;
    const std::string sidecar = results_csv + ".json";
    std::ifstream in(sidecar);
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    const std::string found =
        j.is_object() && j.contains("fingerprint") && j["fingerprint"].is_string()
            ? j["fingerprint"].get<std::string>()
            : std::string();
    if (found.empty())
        throw SceneError(results_csv + ": exists, but its sidecar " + sidecar +
                         " does not say which study started it; choose another --out or remove "
                         "both files");
    const std::string expected = study_fingerprint(study); // reads a record file: once
    if (found != expected)
        throw SceneError(
            results_csv + ": was started by another study (fingerprint " + found + ", this study " +
            expected + ", or by a build whose rows mean something else: results version " +
            std::to_string(sweep_results_version) + "); choose another --out or remove both files");
}

std::string study_json(const Study& study) {
    nlohmann::ordered_json j;
    std::error_code ec;
    const auto absolute = std::filesystem::absolute(study.source, ec);
    j["study"] = ec ? study.source : absolute.string();
    j["fingerprint"] = study_fingerprint(study);
    j["scene"] = nlohmann::ordered_json::parse(study.scene_json);
    for (const auto& a : study.axes)
        j["parameters"][a.key] = a.values;
    j["sample"] = study.sampling == Sampling::grid     ? "grid"
                  : study.sampling == Sampling::random ? "random"
                                                       : "latin_hypercube";
    j["samples"] = study.samples;
    j["seed"] = study.seed;
    j["points"] = point_count(study);
    j["columns"] = sweep_csv_header(study);
    j["results_version"] = sweep_results_version;
    j["build"] = {{"gapchain", GAPCHAIN_LIBRARY_VERSION},
                  {"compiler", __VERSION__},
                  {"built", __DATE__ " " __TIME__}};
    return j.dump(2) + "\n";
}

namespace {

std::vector<std::string> csv_fields(const std::string& line) {
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = line.find(',', start);
        fields.push_back(line.substr(start, comma - start));
        if (comma == std::string::npos) return fields;
        start = comma + 1;
    }
}

/// Whether a results row has no more columns than the header (a point without a regime leaves
/// those out), each a number or empty, but for the columns of text (status, regime) and of
/// lists (per_body, per_body_error).
bool row_matches_header(const std::string& line, const std::vector<std::string>& names) {
    const std::vector<std::string> fields = csv_fields(line);
    if (fields.size() > names.size() || fields.size() < 2) return false;
    for (std::size_t k = 0; k < fields.size(); ++k) {
        if (names[k] == "status" || names[k] == "regime" || names[k] == "per_body" ||
            names[k] == "per_body_error" || fields[k].empty())
            continue;
        char* tail = nullptr;
        std::strtod(fields[k].c_str(), &tail);
        if (tail != fields[k].c_str() + fields[k].size()) return false;
    }
    return true;
}

} // namespace

ResultLog::ResultLog(const std::string& path, const std::string& header, long index_count)
    : m_path(path), m_done(static_cast<std::size_t>(index_count), 0) {
    std::string existing;
    {
        std::ifstream in(path, std::ios::binary);
        if (in) {
            std::ostringstream text;
            text << in.rdbuf();
            existing = text.str();
        }
    }
    std::size_t keep = 0; // bytes of whole lines to keep
    if (!existing.empty()) {
        const std::size_t first = existing.find('\n');
        if (first == std::string::npos || existing.compare(0, first, header) != 0)
            throw SceneError(path + ": exists with other columns (another study?); remove it or "
                                    "choose another --out");
        keep = first + 1;
        const std::vector<std::string> names = csv_fields(header);
        std::size_t pos = keep;
        while (pos < existing.size()) {
            const std::size_t end = existing.find('\n', pos);
            if (end == std::string::npos) break; // torn last line: dropped
            const std::string line = existing.substr(pos, end - pos);
            char* tail = nullptr;
            const long index = std::strtol(line.c_str(), &tail, 10);
            if (tail == line.c_str() || *tail != ',' || index < 0 || index >= index_count ||
                !row_matches_header(line, names))
                throw SceneError(path + ": unreadable row \"" + line.substr(0, 60) + "\"");
            // A row twice means an edited or merged file: its points would count twice.
            if (m_done[index])
                throw SceneError(path + ": point " + std::to_string(index) +
                                 " has two rows (an edited or merged file?); remove one or "
                                 "choose another --out");
            m_done[index] = 1;
            ++m_rows_found;
            keep = end + 1;
            pos = end + 1;
        }
    }
    m_fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (m_fd < 0) throw SceneError(path + ": cannot open for writing: " + reason());
    // One writer at a time: a second sweep on the same file (or a leftover process of a killed
    // one) would append points twice. The kernel drops the lock when its holder dies.
    if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0)
        throw SceneError(path + ": is being written by another gapchain-sweep still running; "
                                "wait for it or stop it first");
    if (existing.empty()) {
        try {
            append(header);
        } catch (const OutputError&) {
            // A new file that cannot even take its header (disk full) is not left behind.
            ::unlink(path.c_str());
            throw;
        }
    } else if (keep < existing.size() && ::ftruncate(m_fd, static_cast<off_t>(keep)) != 0) {
        throw SceneError(path + ": cannot drop the torn last row");
    }
}

ResultLog::~ResultLog() {
    if (m_fd >= 0) ::close(m_fd);
}

void ResultLog::append(const std::string& line) {
    const std::string whole = line + "\n";
    const ssize_t written = ::write(m_fd, whole.data(), whole.size());
    if (written != static_cast<ssize_t>(whole.size()))
        throw OutputError(m_path + ": cannot append a result row: " +
                          (written < 0 ? reason() : std::string("short write (disk full?)")));
}

} // namespace gapchain
