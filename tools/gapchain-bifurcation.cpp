// gapchain-bifurcation: a bifurcation diagram over one parameter (Fig 13 of the paper by
// default): DIR/points.csv, DIR/summary.csv and DIR/bifurcation.png.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/bifurcation.hpp"
#include "gapchain/report.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace {

// Fig 13 of the paper: Nm = 5, fc = 60, e_r = 0.06, eps = 0.5.
constexpr const char* fig13_scene =
    R"({"model": {"Nm": 5, "fc": 60, "eps": 0.5, "e_r": 0.06}, "excitation": {"f_r": 3.0}})";

// The figure's title: the fixed parameters (the swept one is on the x axis) and the run.
std::string diagram_title(const gapchain::ReducedParameters& p, const std::string& param,
                          const std::string& mode, const gapchain::BifurcationOptions& o) {
    std::string title = "Nm=" + std::to_string(p.Nm);
    const std::pair<const char*, double> fixed[] = {
        {"fc", p.fc}, {"eps", p.eps}, {"e_r", p.e_r}, {"f_r", p.f_r}};
    for (const auto& [name, value] : fixed) {
        if (param == name) continue;
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "  %s=%g", name, value);
        title += buffer;
    }
    return title + "  (" + mode + ", " + std::to_string(o.transient_periods) + "+" +
           std::to_string(o.record_periods) + " periods per value)";
}

void print_summary(const gapchain::BifurcationResult& r, const gapchain::BifurcationOptions& o,
                   const std::string& param, const std::string& mode, const std::string& out,
                   bool plotted) {
    double f_max = 0.0, at = 0.0;
    int periodic = 0;
    for (const auto& row : r.rows) {
        if (row.F_m > f_max) f_max = row.F_m, at = row.value;
        periodic += row.period > 0;
    }
    std::printf("gapchain-bifurcation: %s from %g to %g, %d values (%s), %ld+%ld periods each\n",
                param.c_str(), o.from, o.to, o.steps, mode.c_str(), o.transient_periods,
                o.record_periods);
    if (f_max > 0.0)
        std::printf("max F_m = %.6g at %s = %g; %d of %zu rows periodic\n", f_max, param.c_str(),
                    at, periodic, r.rows.size());
    else
        std::printf("max F_m = 0: no contact at any value; %d of %zu rows periodic\n", periodic,
                    r.rows.size());
    std::printf("wrote %s/points.csv, summary.csv, bifurcation.json%s  (%.2f s on %d threads)\n",
                out.c_str(), plotted ? ", bifurcation.png" : "", r.wall_time_s, r.threads_used);
}

} // namespace

int main(int argc, char** argv) {
    using namespace gapchain;
    CLI::App app{"Bifurcation diagram of a row over one parameter: section points and F_m at "
                 "each value. Without a scene: Fig 13 of the paper (Nm=5, fc=60, e_r=0.06, "
                 "eps=0.5).",
                 "gapchain-bifurcation"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, false);
    BifurcationOptions o;
    std::string param = "f_r", mode = "independent", out_dir = "fig13", variable = "u1";
    bool no_plot = false;
    app.add_option("--param", param, "Swept parameter: f_r, e_r, fc or eps")
        ->check(CLI::IsMember({"f_r", "e_r", "fc", "eps"}))
        ->capture_default_str();
    app.add_option("--from", o.from, "First value")->capture_default_str();
    app.add_option("--to", o.to, "Last value")->capture_default_str();
    app.add_option("--steps", o.steps, "Number of values (ends included)")
        ->check(CLI::Range(1, 10'000'000))
        ->capture_default_str();
    app.add_option("--mode", mode,
                   "independent (parallel, from rest) or continuation (up then down)")
        ->check(CLI::IsMember({"independent", "continuation"}))
        ->capture_default_str();
    app.add_option("--transient", o.transient_periods, "Discarded periods per value")
        ->check(CLI::Range(0L, 1'000'000'000L))
        ->capture_default_str();
    app.add_option("--record", o.record_periods, "Recorded periods per value")
        ->check(CLI::Range(1L, 1'000'000'000L))
        ->capture_default_str();
    app.add_option("--variable", variable, "Section variable: u1..uN, v1..vN, g0..gN, F0..FN")
        ->capture_default_str();
    app.add_option("--phase", o.section.phase, "Stroboscopic phase in [0, 1)")
        ->capture_default_str();
    app.add_option("--threads", o.threads, "OpenMP threads (0: all cores)")
        ->check(CLI::Range(0, 4096))
        ->capture_default_str();
    app.add_option("--out", out_dir, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the CSV files only");

    return cli::run(app, argc, argv, [&] {
        const Scene scene = cli::load(scene_args, fig13_scene);
        cli::require_paper_row(scene, "gapchain-bifurcation");
        o.parameter = parse_swept_parameter(param);
        o.mode = parse_sweep_mode(mode);
        o.section.record = {SectionVariable::parse(variable, scene.reduced.Nm, "--variable")};
        o.scheme = scene.run.scheme;
        o.tolerance = scene.run.tolerance;
        validate(o, scene.reduced);
        cli::Outputs outputs({scene_args.path});
        outputs.folder(out_dir, "--out");
        cli::Progress progress("gapchain-bifurcation");
        const BifurcationResult r = bifurcation(scene.reduced, o, progress.callback());
        cli::throw_if_interrupted();
        outputs.create_folders();
        write_file_atomically(out_dir + "/points.csv", points_csv(r, o.section));
        write_file_atomically(out_dir + "/summary.csv", summary_csv(r));
        write_file_atomically(out_dir + "/bifurcation.json", to_json(r, o, scene.reduced));
        const bool plotted =
            !no_plot && cli::plot_template(out_dir, "bifurcation",
                                           {{"TITLE", diagram_title(scene.reduced, param, mode, o)},
                                            {"VARIABLE", variable},
                                            {"PARAM", param}});
        outputs.keep();
        print_summary(r, o, param, mode, out_dir, plotted);
    });
}
