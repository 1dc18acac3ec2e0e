// gapchain-bifurcation: a bifurcation diagram over one parameter (Fig 13 of the paper by
// default): DIR/points.csv, DIR/summary.csv and DIR/bifurcation.png.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/bifurcation.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>

namespace {

// Fig 13 of the paper: Nm = 5, fc = 60, e_r = 0.06, eps = 0.5.
constexpr const char* fig13_scene =
    R"({"model": {"Nm": 5, "fc": 60, "eps": 0.5, "e_r": 0.06}, "excitation": {"f_r": 3.0}})";

// The figure's title: the fixed parameters (the swept one is on the x axis) and the run.
std::string diagram_title(const gapchain::ReducedParameters& p, const std::string& param,
                          const std::string& mode, const gapchain::BifurcationOptions& o) {
    return gapchain::cli::row_title(p, param) + "  (" + mode + ", " +
           std::to_string(o.transient_periods) + "+" + std::to_string(o.record_periods) +
           " periods per value)";
}

// The rows that `listed` picks: how many, and the first five values, comma-separated.
std::pair<int, std::string>
first_values(const gapchain::BifurcationResult& r,
             const std::function<bool(const gapchain::BifurcationRow&)>& listed) {
    std::string values;
    int count = 0;
    for (const auto& row : r.rows)
        if (listed(row) && ++count <= 5) {
            char value[32];
            std::snprintf(value, sizeof value, "%.6g", row.value);
            values += (values.empty() ? "" : ", ") + std::string(value);
        }
    if (count > 5) values += ", ...";
    return {count, values};
}

// The periodic rows Newton did not confirm (the first few): their F_m and period are the
// window's, their bar a finer run's difference (docs/bifurcation.md).
void print_unconfirmed(const gapchain::BifurcationResult& r, const gapchain::BifurcationOptions& o,
                       const std::string& param) {
    if (!o.confirm_by_newton) return;
    const auto [count, values] = first_values(r, [](const gapchain::BifurcationRow& row) {
        return row.period > 0 && !row.newton_confirmed;
    });
    if (count > 0)
        std::printf("%d periodic row(s) not confirmed by Newton (window F_m, finer-run bar): %s = "
                    "%s\n",
                    count, param.c_str(), values.c_str());
}

// The confirmed rows whose finer window settled elsewhere (the first few): their start lies near
// a basin boundary, and the row's attractor is the scheme's pick.
void print_ended_elsewhere(const gapchain::BifurcationResult& r, const std::string& param) {
    const auto [count, values] =
        first_values(r, [](const gapchain::BifurcationRow& row) { return row.ended_elsewhere; });
    if (count > 0)
        std::printf("%d row(s) whose run on a finer plan settled elsewhere (a start near a basin "
                    "boundary: the scheme's error picks the attractor; F_m_error covers both): %s "
                    "= %s\n",
                    count, param.c_str(), values.c_str());
}

void print_summary(const gapchain::BifurcationResult& r, const gapchain::BifurcationOptions& o,
                   const std::string& param, const std::string& mode, const std::string& out,
                   bool plotted) {
    double f_max = 0.0, at = 0.0, at_error = 0.0, largest_error = 0.0;
    int periodic = 0, confirmed = 0;
    for (const auto& row : r.rows) {
        if (row.F_m > f_max) f_max = row.F_m, at = row.value, at_error = row.F_m_error;
        largest_error = std::max(largest_error, row.F_m_error);
        periodic += row.period > 0;
        confirmed += row.newton_confirmed;
    }
    std::printf("gapchain-bifurcation: %s from %g to %g, %d values (%s), %ld+%ld periods each\n",
                param.c_str(), o.from, o.to, o.steps, mode.c_str(), o.transient_periods,
                o.record_periods);
    if (f_max > 0.0)
        std::printf("max F_m = %.6g +- %.2g at %s = %g; %d of %zu rows periodic (%d confirmed "
                    "by Newton); largest F_m_error %.2g\n",
                    f_max, at_error, param.c_str(), at, periodic, r.rows.size(), confirmed,
                    largest_error);
    else
        std::printf("max F_m = 0: no contact at any value; %d of %zu rows periodic (%d confirmed "
                    "by Newton)\n",
                    periodic, r.rows.size(), confirmed);
    print_unconfirmed(r, o, param);
    print_ended_elsewhere(r, param);
    std::printf("wrote %s/points.csv, summary.csv, bifurcation.json%s  (%.2f s on %d thread(s))\n",
                out.c_str(), plotted ? ", bifurcation.png" : "", r.wall_time_s, r.threads_used);
}

// Rows that ran (a cancelled independent diagram lists the others with status cancelled).
long rows_done(const gapchain::BifurcationResult& r) {
    return std::count_if(r.rows.begin(), r.rows.end(), [](const auto& row) {
        return row.status != gapchain::RunStatus::cancelled;
    });
}

// The command line of a diagram.
struct BifurcationArguments {
    gapchain::cli::SceneArguments scene;
    gapchain::BifurcationOptions options;
    std::string param = "f_r", mode = "independent", out_dir = "fig13", variable = "u1";
    bool no_plot = false, no_newton = false;
};

// Rows of the whole diagram: each value once, or up and back down in continuation mode.
long rows_planned(const BifurcationArguments& a) {
    return a.options.mode == gapchain::SweepMode::continuation ? 2L * a.options.steps
                                                               : a.options.steps;
}

void add_options(CLI::App& app, BifurcationArguments& a) {
    using namespace gapchain;
    cli::add_scene_arguments(app, a.scene, false);
    BifurcationOptions& o = a.options;
    app.add_option("--param", a.param, "Swept parameter: f_r, e_r, fc or eps")
        ->check(CLI::IsMember({"f_r", "e_r", "fc", "eps"}))
        ->capture_default_str();
    app.add_option("--from", o.from, "First value")->capture_default_str();
    app.add_option("--to", o.to, "Last value")->capture_default_str();
    app.add_option("--steps", o.steps, "Number of values (ends included)")
        ->check(cli::range(1, 10'000'000))
        ->capture_default_str();
    app.add_option(
           "--mode", a.mode,
           "independent (parallel, each from the scene's initial state, default rest) or "
           "continuation (--from to --to and back, from it; a leg is up where the value grows)")
        ->check(CLI::IsMember({"independent", "continuation"}))
        ->capture_default_str();
    app.add_option("--transient", o.transient_periods, "Discarded periods per value")
        ->check(cli::range(0L, 1'000'000'000L))
        ->capture_default_str();
    app.add_option("--record", o.record_periods, "Recorded periods per value")
        ->check(cli::range(1L, 1'000'000'000L))
        ->capture_default_str();
    app.add_option("--variable", a.variable, "Section variable: u1..uN, v1..vN, g0..gN, F0..FN")
        ->capture_default_str();
    app.add_option("--phase", o.section.phase, "Stroboscopic phase in [0, 1)")
        ->capture_default_str();
    app.add_option("--threads", o.threads, "OpenMP threads (0: all cores)")
        ->check(cli::range(0, 4096))
        ->capture_default_str();
    app.add_option("--out", a.out_dir, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", a.no_plot, "Write the CSV files only");
    app.add_flag("--no-newton", a.no_newton,
                 "Periodic rows keep their recorded window's F_m and section period: no Newton "
                 "confirmation on the exact scheme (Fig 13's line 1.25x faster; rk4's F_m_error "
                 "is then only tolerance x F_m, which its truncation error can exceed)");
}

// Completes the options from the scene and the textual arguments, and checks them.
void resolve_options(BifurcationArguments& a, const gapchain::Scene& scene) {
    using namespace gapchain;
    BifurcationOptions& o = a.options;
    o.parameter = parse_swept_parameter(a.param);
    o.mode = parse_sweep_mode(a.mode);
    o.section.record = {SectionVariable::parse_state(a.variable, scene.reduced.Nm, "--variable")};
    take_run_settings(scene, o);
    o.confirm_by_newton = !a.no_newton;
    validate(o, scene.reduced);
}

// Writes points.csv, summary.csv, bifurcation.json and (unless --no-plot) the plot; returns
// whether the plot was made.
bool write_outputs(const gapchain::BifurcationResult& r, const BifurcationArguments& a,
                   const std::string& out_dir, const gapchain::ReducedParameters& p) {
    using namespace gapchain;
    write_file_atomically(out_dir + "/points.csv", points_csv(r, a.options.section));
    write_file_atomically(out_dir + "/summary.csv", summary_csv(r));
    write_file_atomically(out_dir + "/bifurcation.json", to_json(r, a.options, p));
    const bool independent = a.options.mode == SweepMode::independent;
    return !a.no_plot &&
           cli::plot_template(out_dir, "bifurcation",
                              {{"TITLE", diagram_title(p, a.param, a.mode, a.options)},
                               {"VARIABLE", a.variable},
                               {"PARAM", a.param},
                               // Independent runs have no sweep down: the key listed one.
                               {"UP_TITLE", independent ? "independent runs" : "sweep up"},
                               {"DOWN_TITLE", independent ? "" : "sweep down"}});
}

} // namespace

int main(int argc, char** argv) {
    using namespace gapchain;
    CLI::App app{"Bifurcation diagram of a row over one parameter: section points and F_m at "
                 "each value. Without a scene: Fig 13 of the paper (Nm=5, fc=60, e_r=0.06, "
                 "eps=0.5).",
                 "gapchain-bifurcation"};
    BifurcationArguments a;
    add_options(app, a);
    return cli::run(
        app, argc, argv,
        [&] {
            cli::require_not_set(a.scene, a.param, "gapchain-bifurcation");
            cli::require_sets_read(a.scene, "gapchain-bifurcation",
                                   {"run.scheme", "run.tolerance", "run.max_work"},
                                   "its runs are set by --transient and --record");
            const Scene scene = cli::load(a.scene, fig13_scene);
            require_paper_row(scene, "gapchain-bifurcation");
            resolve_options(a, scene);
            cli::Outputs outputs({a.scene.path});
            outputs.folder(a.out_dir, "--out",
                           {"points.csv", "summary.csv", "bifurcation.json", "bifurcation.gp",
                            "bifurcation.png"});
            cli::Progress progress("gapchain-bifurcation");
            const BifurcationResult r = bifurcation(scene.reduced, a.options, progress.callback());
            // Interrupted: the rows done are written (the others left out), not plotted.
            const long done = rows_done(r);
            if (done == 0) cli::throw_if_interrupted();
            a.no_plot = a.no_plot || r.cancelled || cli::interrupted();
            outputs.create_folders();
            const bool plotted = write_outputs(r, a, outputs.staged(a.out_dir), scene.reduced);
            outputs.keep();
            cli::throw_if_interrupted(std::to_string(done) + " of " +
                                      std::to_string(rows_planned(a)) + " rows done, in " +
                                      a.out_dir + "/points.csv, summary.csv and bifurcation.json" +
                                      (r.cancelled ? " (\"cancelled\": true)" : ""));
            print_summary(r, a.options, a.param, a.mode, a.out_dir, plotted);
        },
        {{"section.phase", "--phase"}, {"variable", "--variable"}});
}
