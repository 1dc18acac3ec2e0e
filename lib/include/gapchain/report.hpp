#pragma once
/// \file report.hpp
/// Scene output: result structs -> JSON and CSV, and the sweep's append-only result file.

#include "gapchain/accuracy.hpp"
#include "gapchain/attractors.hpp"
#include "gapchain/basin_fractions.hpp"
#include "gapchain/bifurcation.hpp"
#include "gapchain/bounds.hpp"
#include "gapchain/classify.hpp"
#include "gapchain/continuation.hpp"
#include "gapchain/design_value.hpp"
#include "gapchain/lyapunov.hpp"
#include "gapchain/modes.hpp"
#include "gapchain/orbit.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/scene.hpp"
#include "gapchain/signal.hpp"
#include "gapchain/simulation.hpp"
#include "gapchain/spectrum.hpp"
#include "gapchain/sweep.hpp"

#include <fstream>
#include <string>

namespace gapchain {

/// "Nm=5 fc=100 eps=0.5 e_r=0.5" for a tool's first line; eps and e_r read "array" where the
/// scene's model.damping or model.clearance gives every entry instead.
std::string row_label(const Scene& scene);

/// A simulation result as JSON: F_m, F_m_error, contact, per_body, per_contact,
/// steady_state_period (null if none), wall_time_s, and the run's provenance: the reduced
/// parameters and run options, for a non-uniform row the arrays that ran ("chain": mass,
/// spring, damping, clearance, contact, contact_law, contact_damping, in Chain's units of
/// model.hpp, after any scatter) and the start ("initial", u then v, when not rest).
std::string to_json(const SimulationResult& result, const Scene& scene);

/// The same, with the run set against its row's attractors (design_value()): a "design_value"
/// object with the search's samples, seed and box, attractors found, unsettled, failed,
/// F_m_max (the design value) with F_m_max_error, from_run, start_below, run_above, the
/// search's own attractors_F_m_max with its error and that attractor (regime, period,
/// basin_fraction with its error, initial_state; null if none), transients, the run options of
/// its starts (run: periods, transient_periods, scheme, tolerance, step, accuracy_mode,
/// steady_state, steady_tolerance, max_steady_period, max_work), its wall_time_s, and for a
/// physical scene F_m_max_newton with F_m_max_error_newton (null where not estimated).
/// "multistable" is also true when start_below or run_above.
std::string to_json(const SimulationResult& result, const Scene& scene, const DesignValue& design,
                    const AttractorOptions& options);

/// The section points of a diagram as CSV: columns value,direction,point,t,<recorded names>;
/// `point` is the first recorded variable (the diagram's ordinate). Rows of status cancelled
/// (a cancelled diagram's rows that did not run) are left out, here and in summary_csv().
std::string points_csv(const BifurcationResult& result, const SectionSpec& section);

/// One row per value and direction: value,direction,F_m,period,points,status (period 0: not
/// periodic).
std::string summary_csv(const BifurcationResult& result);
/// What the CSV columns of a diagram mean (which parameter `value` is, which variable `point`
/// is) and how it was made: the JSON sidecar bifurcation.json next to them.
std::string to_json(const BifurcationResult& result, const BifurcationOptions& options,
                    const ReducedParameters& base);

/// Mode shapes as CSV: body, then one column per mode (mode<k>).
std::string mode_shapes_csv(const ModalResult& result, int Nm);

/// Modal analysis as JSON: Nm, fc, mode_numbers, frequencies, approx, rel_error, residuals,
/// shapes (if computed), method, status, iterations, wall_time_s.
std::string to_json(const ModalResult& result, int Nm, double fc);

/// The eq (26) grid as CSV: Nm,fc,f1_error,other_error,other_mode.
std::string grid_csv(const ApproximationGrid& grid);

/// A work-precision study's sidecar (accuracy.json beside work_precision.csv): F_m_reference,
/// its error F_m_reference_error and how it was made, periods, runs, observed_order (per scheme
/// with at least 3 points above 1e-12), target and fastest_for_target (scheme, tolerance,
/// F_m_error, wall_time_s; null if no run met it), cancelled, wall_time_s [s], and the run's
/// provenance.
std::string to_json(const WorkPrecision& study, const WorkPrecisionOptions& o, double target,
                    const Scene& scene);

/// A spectrum's sidecar (spectrum.json beside psd.csv and peaks.csv): variable,
/// samples_per_period, samples, sample_rate, segment, segments, segment_periods, whole_periods,
/// order, broadband_share with broadband_share_error (null where not estimated),
/// fraction_bin_share, aliased_share, sampled_range_share, peaks (how many; peaks.csv lists
/// them), window, status, wall_time_s [s], the scheme and step the run took, and the run's
/// provenance with the scheme and step asked for.
std::string to_json(const RowSpectrum& s, const RowSpectrumOptions& o, const Scene& scene);

/// A Poincare section's sidecar (section.json beside section.csv): the section (kind; phase, or
/// trigger, level and direction; record), points, repeats_every, point_error (null where not
/// estimated, else compared, error per recorded variable (null for t and an event's trigger),
/// parted_at (null: never), comparison, status and not_estimated (null where estimated), as
/// SectionAccuracy), wall_time_s [s], the scheme and step the run took (outcome), and the run's
/// provenance (parameters, the run keys a once-through run reads with the scheme and step asked
/// for, chain, initial). repeats_every: the k after which the record's last points repeat
/// (RecordTailRepeats), 0 where they do not (written as null).
std::string to_json(const SectionSpec& spec, long points, int repeats_every,
                    const SectionAccuracy* accuracy, double wall_time_s, const Scene& scene,
                    const RunOutcome& outcome);

/// Lyapunov exponents as JSON: exponents, error, sum, expected_sum (-sum of the damping
/// rates, MODEL.md §5; when all 2 Nm were computed), averaging_time, status, wall_time_s, the
/// parameters and run options, and the chain that ran where the scene gives one (arrays,
/// scatter, physical units).
std::string to_json(const LyapunovResult& result, const Scene& scene);

/// Continued orbits, one row per point: value,period,F_m,u1,stable,max_multiplier,branch,
/// minimal_period.
std::string branch_csv(const ContinuationResult& result);

/// Located special points: type,value,period,F_m,branch,contact (-1 unless grazing),
/// value_error,minimal_period.
std::string special_csv(const ContinuationResult& result);

/// A continuation's summary as JSON: the options that ran (parameter, from, to, period, steps,
/// scheme and tolerances), the counts of orbits, branches and special points, each branch's
/// end, the branches not followed, max_F_m_error (over the orbits whose error was estimated,
/// NaN ones counted in F_m_errors_not_estimated), shootings, "cancelled" (the run was
/// interrupted: branch.csv holds the orbits found until then), wall_time_s [s], the row's five
/// numbers as read ("base") and the scene.
std::string to_json(const ContinuationResult& result, const ContinuationOptions& options,
                    const Scene& scene);

/// Attractors, one row each: id,regime,period,F_m,F_m_error,lambda_max,lambda_max_error,
/// basin_fraction,basin_fraction_error,samples,slice_points,settle_median,settle_max,
/// still_settling,F_m_runs,F_m_runs_error ("nan" where a figure is undefined).
std::string attractors_csv(const AttractorSet& set);

/// The random starts, one row each: start,attractor,settle_period,F_m_run (attractor -1: the
/// run failed; settle_period -1: the run did not settle on an orbit), then the start's state
/// u1..uNm,v1..vNm (to all 17 digits: a scene's initial.u and initial.v that run it again).
/// starts: attractor_starts() of the search's parameters and options.
std::string attractor_starts_csv(const AttractorSet& set,
                                 const std::vector<std::vector<double>>& starts);

/// Attractors as JSON: F_m_max (the design value) and its attractor, each attractor with its
/// row of attractors_csv(), max_multiplier, initial_state and state, the search's options and
/// the scene's reduced parameters; a physical scene adds F_m_max_newton, F_m_max_error_newton
/// and each attractor's F_m_newton [N].
std::string to_json(const AttractorSet& set, const AttractorOptions& options, const Scene& scene);

/// The basin slice: x,y,attractor (-1: the run failed), one row per start.
std::string basin_slice_csv(const AttractorSet& set);

/// Basin fractions along a line as JSON: parameter, values, label_count, the base row (its value
/// of the varied parameter is the scene's, which the line replaces; never run), and per
/// value its labels (the global label of each of its attractors, in their order) and its whole
/// search as to_json(AttractorSet) writes it (the options, the center of the starts, the
/// attractors with their errors, wall_time_s, and the newtons of a physical scene); the line's
/// wall_time_s [s].
std::string to_json(const FractionContinuation& continuation, const AttractorOptions& options,
                    const Scene& scene);

/// Basin fractions along a line, one row per value: value, then for every label L the columns
/// fraction_L, fraction_error_L, F_m_L, period_L (period 0 for a non-periodic attractor; where
/// L is absent, fraction 0, so that a plot can stack them, with the error 1/N of N starts none
/// of which reached it, and F_m and period empty).
std::string fractions_csv(const FractionContinuation& continuation);

/// A periodic orbit as JSON: period, minimal_period, state, residual, iterations, multipliers
/// ([re, im], largest modulus first), stable, liouville_error, F_m, per_contact, status,
/// wall_time_s, and the scene's reduced parameters.
std::string to_json(const PeriodicOrbit& orbit, const Scene& scene);

/// Running estimates as CSV: t, lambda1, lambda2, ...
std::string history_csv(const LyapunovResult& result);

/// One classification as JSON: regime, period, lambda_max, lambda_max_error, F_m,
/// distinct_points, section_points, broadband_share, settled_in_record, twin_checked, twin
/// (regime, period, F_m, F_m_error, lambda_max, lambda_max_error, newton_confirmed,
/// settled_in_record, status; where one ran), start_dependent (null where no twin ran its
/// course), periods_run,
/// wall_time_s, parameters, and options (how it ran: transient_periods, record_periods, scheme,
/// tolerance, max_work, max_period, confirm_by_newton, twin_check, and initial where the start
/// is not rest).
std::string to_json(const Classification& c, const ClassifyOptions& o, const ReducedParameters& p);

/// The classification of the scene's row set against its attractors (design_value() of the
/// classification's answer): to_json(c, o, p)'s keys, then multistable (start_dependent,
/// start_below, or run_above unless the label's motion is a settled attractor of the search:
/// then one chaos sampled longer), label_in_search (label_in_search(): "attractor", "transient",
/// "not_reached", null for a periodic or no-contact label), and design_value as the
/// simulation JSON's, with the search's run options ("run").
std::string to_json(const Classification& c, const ClassifyOptions& o, const Scene& scene,
                    const DesignValue& design, const AttractorOptions& options);

/// A regime map as CSV: e_r,f_r,regime,code,period,F_m,lambda_max,lambda_max_error,
/// distinct_points,broadband_share,F_m_error,broadband_share_error,start_dependent,
/// settled_in_record (code: 0
/// no-contact, 1 periodic, 2 quasi-periodic, 3 chaotic; start_dependent 0/1 where the twin ran
/// its course,
/// else empty). Cells of a cancelled map that did not run (status cancelled) are left out.
std::string map_csv(const RegimeMap& map);

/// A PSD as CSV: f, f_over_f_r, density.
std::string psd_csv(const Psd& psd, double f_r);

/// The analytic estimates of a scene as JSON (reduced forces, and newtons for physical scenes;
/// null where an estimate does not exist).
std::string to_json(const AnalyticEstimates& estimates, const Scene& scene, double wall_time_s);

/// The labelled spectral peaks as CSV: f,f_over_f_r,power,label.
std::string peaks_csv(const SpectralContent& content, double f_r);

/// A work-precision study as CSV: scheme (with "-nosplit" when steps were not split at
/// switches), tolerance, step, F_m, F_m_error, final_error, l2_error, seconds, evaluations.
std::string work_precision_csv(const WorkPrecision& study);

/// Header line of a sweep's CSV: index, the axes, Nm,fc,eps,e_r,f_r, F_m, F_m_error, status,
/// then the kept fields (steady_state_period and longer_cycle_period, wall_time_s,
/// regime,period,lambda_max, lambda_max_error,regime_start_dependent (empty where no twin ran),
/// per_body as "left|right;left|right;...").
std::string sweep_csv_header(const Study& study);
/// One CSV line (no newline) for a finished point.
std::string sweep_csv_row(const Study& study, const SweepPointResult& result);
/// The study and the build as JSON, for the sidecar next to the results; it holds the study's
/// fingerprint, so that a resumed sweep can tell that its CSV was started by the same study.
std::string study_json(const Study& study);
/// The meaning of a sweep row's numbers, raised whenever a build changes what a column means
/// (not only its format): 2 since 2026-11-24 (a periodic point's F_m_error covers a maximum
/// that fell in the transient; steady_state_period is the minimal period), 3 since later that
/// day (an F_m_error nothing estimated is empty, not 0), 4 since 2026-11-26 (a point that never
/// settles has an F_m_error of at least its per-period maxima's tail spread; multistable is
/// empty where the check was off; "attractors" adds F_m_max_error), 5 since 2026-11-27 (the
/// F_m_error of Hertz and Hunt-Crossley rows at order 1.5, 3-7 times wider), 6 since
/// 2026-11-27 later (a quasi-periodic or chaotic regime's lambda_max_error covers its twin's
/// difference; regime_start_dependent added), 7 since 2026-11-28 (maximum_in_transient is
/// empty, not 0, where the run settled on no orbit; regime_settled_in_record added), 8 since
/// 2026-11-29 (longer_cycle_period follows steady_state_period: a run that did not settle within
/// run.max_steady_period but whose states repeat every k periods,
/// SimulationResult::longer_cycle_period), 9 since 2026-11-29 later (an F_m_error from a
/// comparison run that is not Richardson's is twice the difference; a record's f_r is empty). A
/// CSV is resumed only by a build of the same version, so that no file mixes two meanings.
inline constexpr int sweep_results_version = 9;
/// A hash (16 hex digits) of everything that decides a study's rows: the base scene, the axes
/// and their values, the sampling, what is kept and results_version (sweep_results_version
/// unless a test asks otherwise). Not the file name, nor a build of the same results version.
std::string study_fingerprint(const Study& study, int results_version = sweep_results_version);
/// Refuses (SceneError, exit 2) to resume into results_csv unless its sidecar
/// (results_csv + ".json") holds this study's fingerprint. Nothing to check if the CSV does not
/// exist yet or is empty.
void check_resume(const std::string& results_csv, const Study& study);

/// An append-only results file that survives kill -9 at any moment. Each row reaches the file in
/// one write(2) of the whole line, so a killed run leaves whole rows and at most one torn last
/// line; reopening drops that line and reports which point indices are done. The file is locked
/// (flock) while open, so two sweeps can never write it at once.
class ResultLog {
public:
    /// Opens path for appending (creating it with header). An existing file must start with
    /// the same header (else SceneError: it belongs to another study). index_count bounds the
    /// first column.
    ResultLog(const std::string& path, const std::string& header, long index_count);
    ~ResultLog();
    ResultLog(const ResultLog&) = delete;
    ResultLog& operator=(const ResultLog&) = delete;
    /// done()[i] != 0 for every index already in the file.
    [[nodiscard]] const std::vector<char>& done() const { return m_done; }
    /// Rows already in the file when it was opened.
    [[nodiscard]] long rows_found() const { return m_rows_found; }
    /// Appends line + newline in a single write; throws OutputError (file and reason) on I/O
    /// failure.
    void append(const std::string& line);

private:
    std::string m_path;
    int m_fd = -1;
    std::vector<char> m_done;
    long m_rows_found = 0;
};

} // namespace gapchain
