// gapchain-accuracy: work-precision study of every scheme on one scene (error against run time).
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/accuracy.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace {

using namespace gapchain;

void print_study(const WorkPrecision& study, const std::string& title, double target) {
    std::printf("gapchain-accuracy: %s; reference F_m = %.13f +- %.1e (exact)\n", title.c_str(),
                study.F_m_reference, study.F_m_reference_error);
    std::printf("%-26s %9s %10s %11s %11s %11s %10s %11s\n", "scheme", "tolerance", "step",
                "F_m error", "final err", "L2 err", "seconds", "evaluations");
    for (const auto& pt : study.points)
        std::printf("%-26s %9.0e %10.3g %11.2e %11.2e %11.2e %10.4f %11ld\n",
                    (std::string(to_string(pt.scheme)) + (pt.split ? "" : " (no split)")).c_str(),
                    pt.tolerance, pt.step, pt.F_m_error, pt.final_error, pt.l2_error,
                    pt.wall_time_s, pt.evaluations);
    std::printf("observed order of F_m error in the step:");
    bool any = false;
    for (Scheme s : {Scheme::central_difference, Scheme::rk4})
        for (bool split : {true, false})
            if (const auto q = observed_order(study, s, split)) {
                std::printf("  %s%s %.2f", std::string(to_string(s)).c_str(),
                            split ? "" : " (no split)", *q);
                any = true;
            }
    // Orders are read for the fixed-step schemes only, from 3 errors above the round-off floor.
    std::printf("%s\n", any ? ""
                            : " none (central_difference and rk4 only, each with at least 3 "
                              "tolerances whose F_m error lies above 1e-12)");
    const auto best = fastest_for(study, target);
    if (!best) {
        std::printf("no run reached a relative F_m error <= %g\n", target);
        return;
    }
    std::printf("fastest for a relative F_m error <= %g: %s at tolerance %g (%.4f s)", target,
                std::string(to_string(best->scheme)).c_str(), best->tolerance, best->wall_time_s);
    for (const auto& pt : study.points)
        if (pt.scheme == Scheme::rk4 && pt.split && pt.F_m_error <= target) {
            std::printf("; fastest rk4 meeting it: %.4f s (%.1fx)", pt.wall_time_s,
                        pt.wall_time_s / best->wall_time_s);
            break;
        }
    std::printf("\n");
}

// The schemes named on the command line, each once.
std::vector<Scheme> distinct_schemes(const std::vector<std::string>& names) {
    std::vector<Scheme> schemes;
    for (const auto& name : names) {
        const Scheme s = parse_scheme(name);
        if (std::find(schemes.begin(), schemes.end(), s) != schemes.end())
            throw std::invalid_argument("--schemes: " + name + " is listed twice");
        schemes.push_back(s);
    }
    return schemes;
}

// row_label(): a row of arrays says eps/e_r = array (row_title printed the defaults).
std::string study_title(const Scene& scene, long periods) {
    char forcing[48];
    std::snprintf(forcing, sizeof forcing, " f_r=%g", scene.reduced.f_r);
    return row_label(scene) + forcing + ", " + std::to_string(periods) + " periods";
}

/// --schemes and --no-unsplit into o.
void set_schemes(WorkPrecisionOptions& o, const std::vector<std::string>& schemes,
                 bool no_unsplit) {
    o.schemes = distinct_schemes(schemes);
    // Only rk4 and central_difference have unsplit runs: --no-unsplit without either skipped
    // nothing.
    if (no_unsplit && unsplit_schemes(o).empty())
        throw std::invalid_argument(
            "--no-unsplit: only rk4 and central_difference run without switch splitting, and "
            "--schemes holds neither; drop --no-unsplit");
    o.unsplit_too = !no_unsplit;
}

} // namespace

// Runs the study, writes its CSV (and figure), keeps them and prints the verdict; an
// interrupted study keeps the runs done.
void run_study(const Scene& scene, const WorkPrecisionOptions& o, const std::string& out,
               bool no_plot, double target, cli::Outputs& outputs) {
    cli::Progress progress("gapchain-accuracy");
    const WorkPrecision study = work_precision(scene.dynamics(), o, progress.callback());
    // Interrupted: the runs done are written, not plotted.
    if (study.points.empty()) cli::throw_if_interrupted();
    no_plot = no_plot || study.cancelled || cli::interrupted();
    outputs.create_folders();
    const std::string staged = outputs.staged(out);
    write_file_atomically(staged + "/work_precision.csv", work_precision_csv(study));
    // The reference, the observed orders, the verdict and the run time were only printed.
    write_file_atomically(staged + "/accuracy.json", to_json(study, o, target, scene));
    const std::string title = study_title(scene, o.periods);
    if (!no_plot) cli::plot_template(staged, "work_precision", {{"TITLE", title}});
    outputs.keep();
    cli::throw_if_interrupted(std::to_string(study.points.size()) + " runs done, in " + out +
                              "/work_precision.csv");
    print_study(study, title, target);
    std::printf("wrote %s/work_precision.csv, accuracy.json%s (%.1f s)\n", out.c_str(),
                no_plot ? "" : ", work_precision.png", study.wall_time_s);
}

int main(int argc, char** argv) {
    CLI::App app{"Work-precision study: each scheme over a ladder of tolerances, its F_m error and "
                 "state errors against the exact propagator, its median run time and evaluations.",
                 "gapchain-accuracy"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, true);
    WorkPrecisionOptions o;
    std::vector<std::string> schemes{"central_difference,rk4,rkf45,rk8pd,exact"};
    std::vector<std::string> tolerances{"1e-2,1e-3,1e-4,1e-5,1e-6,1e-7,1e-8"};
    double target = 1e-6;
    std::string out = "accuracy";
    bool no_plot = false, no_unsplit = false;
    app.add_option("--schemes", schemes,
                   "Schemes to compare, comma-separated: central_difference, rk4, rkf45, rk8pd, "
                   "exact")
        ->capture_default_str();
    app.add_option("--tolerances", tolerances,
                   "Tolerance ladder, comma-separated, each in [1e-12, 0.1]")
        ->capture_default_str();
    app.add_option("--periods", o.periods, "Forcing periods per run")
        ->check(cli::range(1L, 1'000'000L))
        ->capture_default_str();
    app.add_option("--repeats", o.repeats, "Timed repeats (median kept)")
        ->check(cli::range(1, 100))
        ->capture_default_str();
    app.add_option("--target", target,
                   "Relative F_m error for the recommendation, in [1e-16, 0.999]")
        ->check(cli::range(1e-16, 0.999))
        ->capture_default_str();
    app.add_flag("--no-unsplit", no_unsplit, "Skip the runs without switch splitting");
    app.add_option("--out", out, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the CSV only");
    return cli::run(app, argc, argv, [&] {
        cli::require_sets_read(scene_args, "gapchain-accuracy", {"run.max_work"},
                               "its runs are set by --schemes, --tolerances and --periods");
        const Scene scene = cli::load(scene_args);
        require_linear_harmonic(
            scene, "gapchain-accuracy",
            "every scheme is measured against the exact propagator, which needs both");
        set_schemes(o,
                    cli::list_items(
                        "--schemes", schemes,
                        CLI::IsMember({"central_difference", "rk4", "rkf45", "rk8pd", "exact"})),
                    no_unsplit);
        o.tolerances.clear();
        for (const std::string& item :
             cli::list_items("--tolerances", tolerances, cli::range(1e-12, 0.1)))
            o.tolerances.push_back(std::stod(item));
        o.max_work = scene.run.max_work;
        cli::Outputs outputs({scene_args.path});
        outputs.folder(
            out, "--out",
            {"work_precision.csv", "accuracy.json", "work_precision.gp", "work_precision.png"});
        run_study(scene, o, out, no_plot, target, outputs);
    });
}
