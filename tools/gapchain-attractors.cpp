// gapchain-attractors: the coexisting attractors of a row from many starts, with F_m, regime and
// basin fraction of each and the design value F_m_max: DIR/attractors.csv, attractors.json,
// and optionally a basin slice (basins.csv, basins.png) or basin fractions along a parameter
// (fractions.csv, fractions.json, fractions.png).
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/attractors.hpp"
#include "gapchain/basin_fractions.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace {

using namespace gapchain;

struct AttractorArguments {
    cli::SceneArguments scene;
    AttractorOptions options;
    long long seed = 1;
    std::string grid; // "u1,v1": the slice's two state variables
    int resolution = 50;
    std::string param; // basin fractions along this parameter
    double from = 0.0;
    double to = 0.0;
    int steps = 0;
    std::string out_dir = "attractors";
    bool no_plot = false;
};

void add_options(CLI::App& app, AttractorArguments& a) {
    AttractorOptions& o = a.options;
    cli::add_scene_arguments(app, a.scene, true);
    app.add_option("--samples", o.samples, "Random starts (basin fractions)")
        ->check(cli::range(1L, 10'000'000L))
        ->capture_default_str();
    cli::add_start_box(app, a.seed, o.box, "the scene's initial state (rest if it gives none)");
    app.add_option("--grid", a.grid,
                   "Basin slice over two state variables, e.g. u1,v1 (the others at the scene's "
                   "initial state, rest if it gives none)");
    app.add_option("--resolution", a.resolution, "Slice grid points per axis")
        ->check(cli::range(2, 2000))
        ->capture_default_str();
    app.add_option("--section-points", o.section_points,
                   "Stroboscopic points kept of a run that does not settle (at most one per "
                   "recorded period: run.periods - run.transient_periods)")
        ->check(cli::range(20, 100000))
        ->capture_default_str();
    app.add_option("--param", a.param, "Basin fractions along this parameter")
        ->check(CLI::IsMember({"f_r", "e_r", "fc", "eps"}));
    app.add_option("--from", a.from, "First value of --param");
    app.add_option("--to", a.to, "Last value of --param");
    app.add_option("--steps", a.steps, "Values of --param")->check(cli::range(1, 10000));
    app.add_option("--threads", o.threads, "OpenMP threads (0: all)")
        ->check(cli::range(0, 4096))
        ->capture_default_str();
    app.add_option("--out", a.out_dir, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", a.no_plot, "Write the CSV and JSON files only");
}

std::optional<BasinSlice> parse_slice(const AttractorArguments& a, int Nm) {
    if (a.grid.empty()) return std::nullopt;
    const auto comma = a.grid.find(',');
    if (comma == std::string::npos || a.grid.find(',', comma + 1) != std::string::npos)
        throw std::invalid_argument(
            "--grid: expected two state variables separated by a comma (e.g. u1,v1), got \"" +
            a.grid + "\"");
    return basin_slice(std::string_view(a.grid).substr(0, comma),
                       std::string_view(a.grid).substr(comma + 1), Nm, a.resolution);
}

/// --param needs --from, --to and --steps, and excludes --grid.
void check_line(const CLI::App& app, const AttractorArguments& a) {
    const bool line = !a.param.empty();
    for (const char* flag : {"--from", "--to", "--steps"})
        if (line != (app.count(flag) > 0))
            throw std::invalid_argument(line ? std::string(flag) + ": required with --param"
                                             : std::string(flag) + ": applies only with --param");
    if (app.count("--grid") > 0 && a.grid.empty())
        throw std::invalid_argument(
            "--grid: expected two state variables separated by a comma (e.g. u1,v1), got \"\"");
    if (line && !a.grid.empty())
        throw std::invalid_argument("--grid: not with --param (a slice is drawn at one point)");
    if (app.count("--resolution") > 0 && a.grid.empty())
        throw std::invalid_argument("--resolution: applies only with --grid");
}

/// How long the starts of a periodic attractor took to reach it, and what their runs reported
/// on the way when that exceeds the attractor's F_m by more than ten times the accuracy asked.
void print_settling(const Attractor& a, const AttractorOptions& o) {
    if (a.period == 0 || a.samples == 0) return;
    // settle_max covers the starts that settled only; the median counts the others as longer.
    if (std::isnan(a.settle_median))
        std::printf("     most of its starts still settling when their runs ended, at %ld periods "
                    "or after a continuation (%ld of %ld)",
                    o.run.periods, a.still_settling, a.samples);
    else
        std::printf("     transients end after %.0f periods (median)", a.settle_median);
    if (!std::isnan(a.settle_max))
        std::printf(a.still_settling > 0 ? ", %.0f at most among those that settled"
                                         : ", %.0f at most",
                    a.settle_max);
    if (a.still_settling > 0 && !std::isnan(a.settle_median))
        std::printf(
            ", %ld start(s) still settling when their runs ended (%ld periods, or continued)",
            a.still_settling, o.run.periods);
    std::printf("\n");
    // Beyond ten times the accuracy asked (a run's own F_m is off the orbit's by about that;
    // its F_m_error covers the transient's gap, so it is no yardstick here): a transient's.
    if (a.F_m_runs - a.F_m > 10.0 * o.run.tolerance * a.F_m + a.F_m_error)
        std::printf("     runs from these starts report F_m up to %.6g: their transients outlast "
                    "the discarded periods\n",
                    a.F_m_runs);
}

/// How long a non-periodic attractor was seen to last: no finite run tells a chaotic set from a
/// chaotic transient that outlasts it (Fig 13's row at f_r = 3.2 with 600-period runs lists
/// a chaotic group that 5000-period runs see land on a period-15 orbit, docs/attractors.md).
void print_lasting(const Attractor& a, const AttractorSet& s, const AttractorOptions& o) {
    if (a.period != 0) return;
    if (a.left_for_orbits > 0) {
        const long members = a.samples + a.slice_points;
        const long not_continued = a.left_for_orbits + members - a.members_continued;
        std::printf("     a chaotic transient, not an attractor: continued %ld more periods, "
                    "%ld of %ld continued starts left it for orbits; %ld still in it",
                    s.confirmation_periods, a.left_for_orbits, a.members_continued, members);
        if (not_continued > 0)
            std::printf(", %ld of them not continued (beyond run.max_work, or the continuation "
                        "failed)",
                        not_continued);
        std::printf("\n");
    } else if (a.settled)
        std::printf("     non-periodic through its starts' %ld periods and %ld more on %ld of "
                    "them; a transient longer than that is not ruled out\n",
                    o.run.periods, s.confirmation_periods, a.members_continued);
}

// Why a group is unsettled (Attractor::settled), for the warnings of both modes. A group still
// converging may also be an orbit longer than the steady-state watch looks for.
std::string unsettled_reason(const AttractorOptions& o) {
    return " (chaotic transients some of whose starts left for orbits when continued, or runs "
           "that ended still converging: lambda_max more than three errors below 0, or "
           "neither chaos nor a torus after a tangent run 64 times as long, no contact, or "
           "shorter than four decay times of the row; their F_m is a transient's); raise "
           "run.periods, or "
           "run.max_steady_period (now " +
           std::to_string(o.run.max_steady_period) + ") if their orbits may be longer";
}

// Where the starts were drawn, when not around rest (fractions.json's center; the CSV has no
// place for it).
void print_center(const AttractorOptions& o) {
    if (!o.center.empty())
        std::printf("starts in a box of %g A around the scene's initial state\n", o.box);
}

void print_set(const AttractorSet& s, const AttractorOptions& o) {
    std::printf("%s from %ld starts (%ld failed), %.2f s on %d thread(s)\n",
                cli::attractor_count(s).c_str(), o.samples, s.failed, s.wall_time_s,
                s.threads_used);
    print_center(o);
    for (const auto& a : s.attractors) {
        std::printf("  #%d %-14s", a.id, std::string(regime_label(a)).c_str());
        if (a.period > 0)
            std::printf(" period %-3d", a.period);
        else
            std::printf("           ");
        std::printf(" F_m = %.6g +- %.2g  ", a.F_m, a.F_m_error);
        if (std::isfinite(a.lambda_max))
            std::printf("lambda_max = %+.3g", a.lambda_max);
        else
            std::printf("lambda_max not computed (orbit not confirmed by Newton)");
        std::printf("  basin %.3f +- %.3f\n", a.basin_fraction, a.basin_fraction_error);
        print_settling(a, o);
        print_lasting(a, s, o);
    }
    cli::print_transients(s.transients);
    if (s.F_m_max_id >= 0)
        std::printf(
            "design value F_m_max = %.6g (%s #%d)\n", s.F_m_max,
            s.any_settled() ? "attractor" : "unsettled group, nothing settled:", s.F_m_max_id);
    if (s.unsettled > 0)
        std::printf("warning: %d group(s) unsettled%s\n", s.unsettled, unsettled_reason(o).c_str());
}

void run_point(const Scene& scene, AttractorArguments& a, cli::Outputs& outputs) {
    cli::Progress progress("gapchain-attractors");
    const AttractorSet set = find_attractors(scene.reduced, a.options, progress.callback());
    // Cancelled, nothing was grouped; a search that finished is kept even if a signal came.
    if (set.cancelled) cli::throw_if_interrupted();
    outputs.create_folders();
    const std::string dir = outputs.staged(a.out_dir);
    write_file_atomically(dir + "/attractors.csv", attractors_csv(set));
    write_file_atomically(dir + "/attractors.json", to_json(set, a.options, scene));
    write_file_atomically(dir + "/starts.csv",
                          attractor_starts_csv(set, attractor_starts(scene.reduced, a.options)));
    if (a.options.slice) {
        write_file_atomically(dir + "/basins.csv", basin_slice_csv(set));
        const auto comma = a.grid.find(',');
        if (!a.no_plot && !cli::interrupted())
            cli::plot_template(dir, "basins",
                               {{"TITLE", "Basins: " + cli::row_title(scene.reduced)},
                                {"XLABEL", a.grid.substr(0, comma)},
                                {"YLABEL", a.grid.substr(comma + 1)},
                                {"COUNT", std::to_string(set.attractors.size())}});
    }
    outputs.keep();
    cli::throw_if_interrupted("the whole search, in " + a.out_dir +
                              (a.options.slice && !a.no_plot ? " (no figure)" : ""));
    std::printf("gapchain-attractors: %s\n", cli::row_title(scene.reduced).c_str());
    print_set(set, a.options);
    std::printf("wrote %s/attractors.csv, attractors.json, starts.csv%s\n", a.out_dir.c_str(),
                !a.options.slice ? ""
                : a.no_plot      ? ", basins.csv"
                                 : ", basins.csv, basins.png");
}

// One line on stderr per value done, as it is done: a long line shows what it has found, and
// what it showed is kept if the line is interrupted. (Not stdout: a reader that stops early,
// as `| head`, would end the run by SIGPIPE with nothing kept.)
void print_value_done(const FractionContinuation& line, const AttractorArguments& a,
                      cli::Progress& progress) {
    const AttractorSet& set = line.sets.back();
    std::string text = a.param + " = " + cli::number_text(line.values.back(), 6) + " (" +
                       std::to_string(line.values.size()) + " of " + std::to_string(a.steps) + "):";
    char cell[160];
    for (std::size_t i = 0; i < set.attractors.size(); ++i) {
        const Attractor& at = set.attractors[i];
        text +=
            " label " + std::to_string(line.labels.back()[i]) + " " + std::string(regime_label(at));
        if (at.period > 0) text += " period " + std::to_string(at.period);
        std::snprintf(cell, sizeof cell, " F_m %.6g basin %.3f;", at.F_m, at.basin_fraction);
        text += cell;
    }
    progress.note(text + " " + std::to_string(set.failed) + " failed");
}

void run_line(const Scene& scene, AttractorArguments& a, cli::Outputs& outputs) {
    cli::Progress progress("gapchain-attractors");
    const FractionContinuation c = continue_basin_fractions(
        scene.reduced, parse_swept_parameter(a.param),
        fraction_line_values(scene.reduced, parse_swept_parameter(a.param), a.from, a.to, a.steps),
        a.options, progress.callback(),
        [&](const FractionContinuation& line) { print_value_done(line, a, progress); });
    if (c.values.empty()) cli::throw_if_interrupted();
    // Interrupted after some values: those are written (fractions.json says "cancelled"), not
    // plotted, and the run still ends as interrupted.
    const bool cut = c.cancelled || cli::interrupted();
    outputs.create_folders();
    const std::string dir = outputs.staged(a.out_dir);
    write_file_atomically(dir + "/fractions.csv", fractions_csv(c));
    write_file_atomically(dir + "/fractions.json", to_json(c, a.options, scene));
    const bool plotted =
        !a.no_plot && !cut &&
        cli::plot_template(dir, "fractions",
                           {{"TITLE", "Basin fractions: " + cli::row_title(scene.reduced, a.param)},
                            {"PARAM", a.param},
                            {"COUNT", std::to_string(c.label_count)}});
    outputs.keep();
    const std::string files = a.out_dir + "/fractions.csv and fractions.json";
    cli::throw_if_interrupted(
        c.cancelled ? "the " + std::to_string(c.values.size()) + " of " + std::to_string(a.steps) +
                          " values done, in " + files + " (\"cancelled\": true)"
                    : "all " + std::to_string(a.steps) + " values, in " + files);
    std::printf("gapchain-attractors: %s from %g to %g (%d values): %d attractor labels, %.2f s\n",
                a.param.c_str(), a.from, a.to, a.steps, c.label_count, c.wall_time_s);
    print_center(a.options);
    int unsettled = 0;
    for (const auto& set : c.sets)
        unsettled += set.unsettled;
    if (unsettled > 0)
        std::printf("warning: %d group(s) unsettled along the line, counted once per value%s\n",
                    unsettled, unsettled_reason(a.options).c_str());
    std::printf("wrote %s/fractions.csv, fractions.json%s\n", a.out_dir.c_str(),
                plotted ? ", fractions.gp, fractions.png" : "");
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Find the coexisting attractors of a row from many starts: F_m, regime, period "
                 "and basin fraction of each, and the design value F_m_max.",
                 "gapchain-attractors"};
    AttractorArguments a;
    add_options(app, a);
    return cli::run(app, argc, argv,
                    [&] {
                        if (!a.param.empty())
                            cli::require_not_set(a.scene, a.param, "gapchain-attractors --param");
                        // Every start estimates its error and runs no twin, whatever
                        // the scene says (a --set of them changed nothing).
                        cli::require_sets_read(
                            a.scene, "gapchain-attractors", {"run."},
                            "every start estimates its error and runs no twin; it writes no "
                            "trajectory",
                            {"run.estimate_error", "run.multistability_check"});
                        const Scene scene = cli::load(a.scene);
                        require_paper_row(scene, "gapchain-attractors");
                        check_line(app, a);
                        a.options.run = scene.run;
                        a.options.center = scene.initial;
                        a.options.seed = static_cast<std::uint64_t>(a.seed);
                        a.options.slice = parse_slice(a, scene.reduced.Nm);
                        validate(a.options, scene.reduced.Nm);
                        cli::Outputs outputs({a.scene.path});
                        outputs.folder(a.out_dir, "--out",
                                       {"attractors.csv", "attractors.json", "starts.csv",
                                        "basins.csv", "basins.gp", "basins.png", "fractions.csv",
                                        "fractions.json", "fractions.gp", "fractions.png"});
                        if (a.param.empty())
                            run_point(scene, a, outputs);
                        else
                            run_line(scene, a, outputs);
                    },
                    {{"samples", "--samples"},
                     {"box", "--box"},
                     {"section_points", "--section-points"},
                     {"threads", "--threads"},
                     {"slice.resolution", "--resolution"},
                     {"grid", "--grid"},
                     {"steps", "--steps"}});
}
