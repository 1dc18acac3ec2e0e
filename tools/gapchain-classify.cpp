// gapchain-classify: regime of one point, or a regime map over (e_r, f_r) as Fig 2 of the paper.
#include "common/cli.hpp"
#include "common/design_search.hpp"
#include "common/plot.hpp"

#include "gapchain/classify.hpp"
#include "gapchain/design_value.hpp"
#include "gapchain/grid.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>

namespace {

using namespace gapchain;

// "from:to:count" -> count evenly spaced values, ends included, each a value the model takes for
// the parameter (refused under the flag that gave it).
std::vector<double> parse_range(const std::string& text, const std::string& flag,
                                const ReducedParameters& base, SweptParameter parameter) {
    // Each part a plain decimal (sscanf's %d wrapped 4294967298 to 2, and %lf read 1e-999 as 0).
    const auto first = text.find(':');
    const auto second = first == std::string::npos ? first : text.find(':', first + 1);
    const std::string parts[3] = {
        text.substr(0, first),
        first == std::string::npos ? "" : text.substr(first + 1, second - first - 1),
        second == std::string::npos ? "" : text.substr(second + 1)};
    const std::string form =
        flag + ": must be from:to:count with 1 <= count <= 100000, got \"" + text + "\"";
    if (second == std::string::npos) throw std::invalid_argument(form);
    for (int k = 0; k < 3; ++k)
        if (const std::string error = number_text_error(parts[k], k == 2); !error.empty())
            throw std::invalid_argument(form + ": its " +
                                        (k == 0   ? "from"
                                         : k == 1 ? "to"
                                                  : "count") +
                                        " " + error);
    const double from = std::strtod(parts[0].c_str(), nullptr);
    const double to = std::strtod(parts[1].c_str(), nullptr);
    const int count = parts[2].size() <= 6 ? std::stoi(parts[2]) : 0;
    if (count < 1 || count > 100000) throw std::invalid_argument(form);
    for (double end : {from, to})
        if (const auto error = swept_value_error(base, parameter, end))
            throw std::invalid_argument(flag + ": " + *error);
    // A map axis of several equal values had gnuplot fail after the whole map had run; one of
    // ends a few doubles apart repeated a value.
    if ((count > 1) == (from == to))
        throw std::invalid_argument(flag +
                                    ": count 1 goes with from = to and count > 1 with from " +
                                    "!= to, got \"" + text + "\"");
    try {
        require_line(from, to, count);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(flag + ": " + std::string(e.what()).substr(7) + " (from \"" +
                                    text + "\")");
    }
    return linspace(from, to, count);
}

// The twin's reading, and what it says (a verdict only where it ran its course).
void print_twin(const Classification& c) {
    if (!c.twin) return;
    const Classification& t = *c.twin;
    if (!c.twin_checked) {
        std::printf("note: the twin (start moved by 1e-8) ended %s: whether the label depends on "
                    "the start is unknown\n",
                    std::string(to_string(t.status)).c_str());
        return;
    }
    std::printf("  twin (start moved by 1e-8): %s, lambda_max = %+.4f, F_m = %.6g%s\n",
                std::string(to_string(t.regime)).c_str(), t.lambda_max, t.F_m,
                c.start_dependent ? "" : " (no start dependence detected)");
    if (c.start_dependent)
        std::printf("note: the label depends on the start: a start moved by 1e-8 reads %s with "
                    "F_m %.6g (%s); a chaotic transient that outlasts --transient, coexisting "
                    "attractors (gapchain-attractors), or a label at its rule's margin; raise "
                    "--transient and --record\n",
                    std::string(to_string(t.regime)).c_str(), t.F_m,
                    t.regime != c.regime ? "another label" : "F_m beyond three error bars");
}

// What the row's attractors say of a non-periodic label: whether the search found its motion
// as an attractor or as a transient, or did not reach it; with no search, that other starts
// were not tried.
void print_search_verdict(const Classification& c, const std::optional<DesignValue>& design,
                          long samples) {
    const std::string label(to_string(c.regime));
    if (!design) {
        if (c.regime == Regime::chaotic || c.regime == Regime::quasi_periodic)
            std::printf("note: other starts were not tried; a chaotic transient reads as chaos "
                        "until it ends (--attractors N searches the row's attractors from N "
                        "starts)\n");
        return;
    }
    switch (label_in_search(c, *design)) {
    case LabelInSearch::not_applicable: return;
    case LabelInSearch::attractor:
        std::printf("attractor: the search settled on a non-periodic attractor of this F_m\n");
        return;
    case LabelInSearch::transient:
        std::printf("transient: the %s motion read from this start is not one of the row's "
                    "attractors: the search's starts that reached it left it for orbits or were "
                    "still converging (a transient that outlasts --transient)\n",
                    label.c_str());
        return;
    case LabelInSearch::not_reached:
        std::printf("not reached: no start of the search reached the %s motion read from this "
                    "start (%ld starts miss a basin of 10 %% with odds %.0f %%): no verdict on "
                    "it; raise --attractors\n",
                    label.c_str(), samples, 100.0 * std::pow(0.9, static_cast<double>(samples)));
        return;
    }
}

// The row's attractors from the search's starts, set against c's F_m (none if not wanted).
std::optional<DesignValue> set_against_search(const Classification& c, const ReducedParameters& p,
                                              const cli::DesignSearch& search) {
    if (!search.wanted()) return std::nullopt;
    cli::Progress progress("gapchain-classify: attractors");
    DesignValue design = design_value(p, search.options(), c, progress.callback());
    cli::throw_if_interrupted();
    return design;
}

// The design value's lines, the classified run set against the attractors: a stable orbit
// the search missed is no transient, and a non-periodic motion is named as the search saw it.
void print_design(const Scene& scene, const Classification& c, const DesignValue& design,
                  const AttractorOptions& options) {
    cli::SearchedRun run;
    run.F_m = c.F_m;
    run.longer_runs = "--record";
    run.reads_max_steady_period = false;
    const LabelInSearch where = label_in_search(c, design);
    if (c.regime == Regime::periodic && c.newton_confirmed && c.max_multiplier < 1.0)
        run.above_reason = "multistable: this run ended on a stable orbit that no start of the "
                           "search reached (a small basin): it hits harder than every attractor "
                           "found";
    if (where == LabelInSearch::attractor)
        run.above_reason = "this run's record of that non-periodic attractor reached a larger "
                           "maximum than the search's runs did (the design value is this run's)";
    if (where == LabelInSearch::transient) run.reached = "a transient, not an attractor";
    if (where == LabelInSearch::not_reached)
        run.reached = "a weaker motion, which the search did not reach";
    cli::print_design(scene, run, design, options);
}

void classify_point(const Scene& scene, const ClassifyOptions& o, const std::string& out,
                    const cli::DesignSearch& search, cli::Outputs& outputs) {
    const ReducedParameters& p = scene.reduced;
    // The run asks as it goes: a signal stops it (a long --record took a minute to notice).
    const Classification c = classify(p, o, [](double) { return !cli::interrupted(); });
    cli::throw_if_interrupted();
    if (c.status == RunStatus::non_finite) throw cli::NumericalFailure("the run became non-finite");
    const std::optional<DesignValue> design = set_against_search(c, p, search);
    if (!out.empty())
        write_file_atomically(out, design ? to_json(c, o, scene, *design, search.options())
                                          : to_json(c, o, p));
    outputs.keep();
    std::printf("gapchain-classify: Nm=%d fc=%g eps=%g e_r=%g f_r=%g\n", p.Nm, p.fc, p.eps, p.e_r,
                p.f_r);
    std::printf("regime %s", std::string(to_string(c.regime)).c_str());
    if (c.regime == Regime::periodic)
        std::printf(" (period %d%s)", c.period,
                    c.period == 0 ? ": a cycle longer than max_period, or one the run was still "
                                    "approaching (raise --transient)"
                                  : "");
    if (c.newton_confirmed)
        std::printf(", confirmed by Newton: minimal period %d, largest |multiplier| %.4g", c.period,
                    c.max_multiplier);
    std::printf("\n  lambda_max = %+.4f +- %.2g, %d distinct of %d section points, "
                "broadband share %.3f %s\n",
                c.lambda_max, c.lambda_max_error, c.distinct_points, c.section_points,
                c.broadband_share, cli::plus_minus(c.broadband_share_error, "%.2g").c_str());
    std::printf("  F_m = %.6g +- %.2g, %ld periods (%s), %.3f s\n", c.F_m, c.F_m_error,
                c.periods_run, std::string(to_string(c.scheme_used)).c_str(), c.wall_time_s);
    if (c.start_up_in_record)
        std::printf("note: this row's start-up takes %s%ld periods to decay to run.tolerance, "
                    "more than the %ld discarded: the record may be the start-up's, not the "
                    "regime's; raise --transient\n",
                    c.start_up_periods >= 1'000'000'000 ? "more than " : "", c.start_up_periods,
                    o.transient_periods);
    if (c.settled_in_record)
        std::printf("note: the state settled while recording, after more than the %ld discarded "
                    "periods (%ld run): the label and F_m are the steady state's (the bar covers "
                    "the record's maximum before); a transient that outlasts --transient may "
                    "end elsewhere from other starts (gapchain-attractors)\n",
                    o.transient_periods, c.periods_run);
    print_twin(c);
    print_search_verdict(c, design, search.options().samples);
    if (design) print_design(scene, c, *design, search.options());
}

void classify_map(const ReducedParameters& p, const ClassifyOptions& o, const std::string& out,
                  const std::vector<double>& e_r, const std::vector<double>& f_r, int threads,
                  bool plot, cli::Outputs& outputs) {
    cli::Progress progress("gapchain-classify");
    const RegimeMap m = regime_map(p, e_r, f_r, o, threads, progress.callback());
    // Interrupted: the cells done are written (the others left out of map.csv), not plotted.
    const auto done = std::count_if(m.cells.begin(), m.cells.end(), [](const Classification& c) {
        return c.status != RunStatus::cancelled;
    });
    if (done == 0) cli::throw_if_interrupted();
    plot = plot && !m.cancelled && !cli::interrupted();
    outputs.create_folders();
    const std::string staged = outputs.staged(out);
    write_file_atomically(staged + "/map.csv", map_csv(m));
    int counts[4] = {0, 0, 0, 0}, twins = 0, start_dependent = 0, settled_late = 0;
    for (const auto& c : m.cells) {
        ++counts[static_cast<int>(c.regime)];
        twins += c.twin_checked;
        start_dependent += c.start_dependent;
        settled_late += c.settled_in_record;
    }
    char title[160];
    std::snprintf(title, sizeof title, "Nm=%d fc=%g eps=%g", p.Nm, p.fc, p.eps);
    // A map one cell wide or high (a line through the plane) is drawn as a strip of squares:
    // gnuplot's image needs two cells each way, and its axis a range of non-zero length.
    const bool line = e_r.size() == 1 || f_r.size() == 1;
    auto axis_end = [](const std::vector<double>& v, double side) {
        const double pad = v.size() == 1 ? side * std::max(0.05 * std::abs(v[0]), 0.01) : 0.0;
        return cli::number_text((side < 0 ? v.front() : v.back()) + pad);
    };
    if (plot)
        cli::plot_template(staged, "map",
                           {{"TITLE", title},
                            {"EPS", cli::number_text(p.eps)},
                            {"F_FROM", axis_end(f_r, -1.0)},
                            {"F_TO", axis_end(f_r, 1.0)},
                            {"E_FROM", axis_end(e_r, -1.0)},
                            {"E_TO", axis_end(e_r, 1.0)},
                            {"STYLE", line ? "with points pt 5 ps 2 lc palette" : "with image"}});
    outputs.keep();
    cli::throw_if_interrupted(std::to_string(done) + " of " + std::to_string(m.cells.size()) +
                              " cells done, in " + out + "/map.csv");
    std::printf("gapchain-classify: %zu x %zu map (e_r x f_r), %d threads, %.1f s\n", e_r.size(),
                f_r.size(), m.threads_used, m.wall_time_s);
    std::printf("  no-contact %d, periodic %d, quasi-periodic %d, chaotic %d\n", counts[0],
                counts[1], counts[2], counts[3]);
    std::printf("  start-dependent %d of %d cells with a twin (map.csv's start_dependent); "
                "%d settled while recording\n",
                start_dependent, twins, settled_late);
    std::printf("wrote %s/map.csv%s\n", out.c_str(), plot ? ", regimes.png, force.png" : "");
}

// Refuses a --set the classification would ignore: run keys it does not read, and with --map
// the scene's e_r and f_r, which the map's axes replace (a --set of them changed nothing).
void require_sets_read(const cli::SceneArguments& scene_args, bool map) {
    cli::require_sets_read(scene_args, "gapchain-classify",
                           {"run.scheme", "run.tolerance", "run.max_work"},
                           "its runs are set by --transient and --record");
    if (map)
        for (const char* axis : {"e_r", "f_r"})
            cli::require_not_set(scene_args, axis, "gapchain-classify --map",
                                 std::string("over --") + axis);
}

// The options of each point's runs: their lengths, and whether an unsettled label has a twin.
void add_point_run_options(CLI::App& app, ClassifyOptions& o, bool& no_twin) {
    app.add_option("--transient", o.transient_periods,
                   "Settling periods (ended early by a steady state)")
        ->check(cli::range(0L, 1'000'000'000L))
        ->capture_default_str();
    app.add_option("--record", o.record_periods, "Recorded periods for non-periodic motion")
        ->check(cli::range(20L, 1'000'000'000L))
        ->capture_default_str();
    app.add_flag("--no-twin", no_twin,
                 "No twin from a start moved by 1e-8 on quasi-periodic and chaotic labels "
                 "(half their cost; start_dependent then unknown)");
}

// --map and the options only it reads: its axes and --no-plot.
struct MapArguments {
    bool on = false;
    std::string e_r = "0:1.5:100", f_r = "0.1:5:100";
    bool no_plot = false;

    void add_options(CLI::App& app) {
        auto* map = app.add_flag("--map", on, "Classify a grid of (e_r, f_r)");
        app.add_option("--e_r", e_r, "Map rows: from:to:count")->needs(map)->capture_default_str();
        app.add_option("--f_r", f_r, "Map columns: from:to:count")
            ->needs(map)
            ->capture_default_str();
        app.add_flag("--no-plot", no_plot, "Write the CSV only")->needs(map);
    }
};

// --map: the axes read, then the grid classified into the output folder.
void run_map(const Scene& scene, const ClassifyOptions& o, const MapArguments& map,
             const std::string& out, int threads, cli::Outputs& outputs) {
    outputs.folder(out, "--out", {"map.csv", "map.gp", "regimes.png", "force.png"});
    const std::vector<double> e_r =
        parse_range(map.e_r, "--e_r", scene.reduced, SweptParameter::e_r);
    const std::vector<double> f_r =
        parse_range(map.f_r, "--f_r", scene.reduced, SweptParameter::f_r);
    classify_map(scene.reduced, o, out, e_r, f_r, threads, !map.no_plot, outputs);
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Classify a row as no-contact, periodic (with its period), quasi-periodic or chaotic, "
        "with the evidence (largest Lyapunov exponent and error, section points, broadband "
        "share). --map classifies a grid of (e_r, f_r), in parallel.",
        "gapchain-classify"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, true);
    ClassifyOptions o;
    std::string out;
    int threads = 0;
    app.add_option("--out", out, "JSON result (one point) or output folder (--map; default map)");
    MapArguments map;
    map.add_options(app);
    bool no_twin = false;
    add_point_run_options(app, o, no_twin);
    auto* threads_option =
        app.add_option("--threads", threads, "OpenMP threads of --map or --attractors (0: all)")
            ->check(cli::range(0, 4096))
            ->capture_default_str();
    cli::DesignSearch search("gapchain-classify --attractors");
    search.add_options(app, false);
    // A map runs no search: its refusal of --seed and --box said "add --attractors N", which a
    // map refuses too.
    for (const char* name : {"--seed", "--box"})
        app.get_option(name)->excludes(app.get_option("--map"));
    return cli::run(
        app, argc, argv,
        [&] {
            require_sets_read(scene_args, map.on);
            const Scene scene = cli::load(scene_args);
            require_paper_row(scene, "gapchain-classify");
            take_run_settings(scene, o);
            o.twin_check = !no_twin;
            // The label is set against the search's groups by their section points too.
            o.keep_section_states = search.wanted();
            validate(o);
            cli::Outputs outputs({scene_args.path});
            if (out.empty() && app.get_option("--out")->count() > 0)
                throw std::invalid_argument("--out: must name a file (or, with --map, a folder); "
                                            "leave it out to print the summary only");
            if (!map.on) {
                if (threads_option->count() > 0 && !search.wanted())
                    throw std::invalid_argument(
                        "--threads: applies to --map or --attractors N (1 .. 1e7 starts)");
                search.set_threads(threads);
                search.check(scene, classify_search_run(o));
                outputs.file(out, "--out");
                return classify_point(scene, o, out, search, outputs);
            }
            if (search.wanted())
                throw std::invalid_argument("--attractors: applies to one point; "
                                            "gapchain-attractors --param gives the attractors "
                                            "along a line");
            run_map(scene, o, map, out.empty() ? "map" : out, threads, outputs);
        },
        {{"run.periods", "--transient / --record"}});
}
