// gapchain-accuracy: work-precision study of every scheme on one scene (error against run time).
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/accuracy.hpp"
#include "gapchain/report.hpp"

#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
    using namespace gapchain;
    CLI::App app{"Work-precision study: each scheme over a ladder of tolerances, its F_m error and "
                 "state errors against the exact propagator, its median run time and evaluations.",
                 "gapchain-accuracy"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, true);
    WorkPrecisionOptions o;
    std::vector<std::string> schemes{"central_difference", "rk4", "rkf45", "rk8pd", "exact"};
    double target = 1e-6;
    std::string out = "accuracy";
    bool no_plot = false, no_unsplit = false;
    app.add_option("--schemes", schemes, "Schemes to compare")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--tolerances", o.tolerances, "Tolerance ladder")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--periods", o.periods, "Forcing periods per run")->capture_default_str();
    app.add_option("--repeats", o.repeats, "Timed repeats (median kept)")->capture_default_str();
    app.add_option("--target", target, "Relative F_m error for the recommendation")
        ->capture_default_str();
    app.add_flag("--no-unsplit", no_unsplit, "Skip the runs without switch splitting");
    app.add_option("--out", out, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the CSV only");
    return cli::run(app, argc, argv, [&] {
        const Scene scene = cli::load(scene_args);
        o.schemes.clear();
        for (const auto& s : schemes)
            o.schemes.push_back(parse_scheme(s));
        o.unsplit_too = !no_unsplit;
        if (!(target > 0.0 && target < 1.0))
            throw std::invalid_argument("--target: must be in (0, 1), got " +
                                        std::to_string(target));
        const WorkPrecision study = work_precision(scene.dynamics(), o);
        std::filesystem::create_directories(out);
        write_file_atomically(out + "/work_precision.csv", work_precision_csv(study));
        const ReducedParameters& p = scene.reduced;
        char title[200];
        std::snprintf(title, sizeof title, "Nm=%d fc=%g eps=%g e_r=%g f_r=%g, %ld periods", p.Nm,
                      p.fc, p.eps, p.e_r, p.f_r, o.periods);
        if (!no_plot)
            cli::plot_with_gnuplot(
                out + "/work_precision.gp",
                "# Regenerate: gnuplot work_precision.gp (in this folder)\n"
                "set terminal pngcairo size 1000,700 font 'sans,11'\nset output "
                "'work_precision.png'\n"
                "set datafile separator ','\nset logscale xy\nset grid\nset key outside right "
                "noenhanced\n"
                "set format x '10^{%L}'\nset xlabel 'relative error of F_m'\nset ylabel 'wall time "
                "[s] (median)'\n"
                "set title '" +
                    std::string(title) +
                    "'\n"
                    "atleast(x) = x < 1e-16 ? 1e-16 : x\n"
                    "plot for [s in 'central_difference rk4 rkf45 rk8pd exact "
                    "central_difference-nosplit rk4-nosplit'] "
                    "'work_precision.csv' every ::1 using (strcol(1) eq s ? atleast($5) : 1/0):8 "
                    "with linespoints "
                    "pt 7 ps 0.8 lw 1.5 title s\n");
        std::printf("gapchain-accuracy: %s; reference F_m = %.13f (exact)\n", title,
                    study.F_m_reference);
        std::printf("%-26s %9s %10s %11s %11s %11s %10s %11s\n", "scheme", "tolerance", "step",
                    "F_m error", "final err", "L2 err", "seconds", "evaluations");
        for (const auto& pt : study.points)
            std::printf(
                "%-26s %9.0e %10.3g %11.2e %11.2e %11.2e %10.4f %11ld\n",
                (std::string(to_string(pt.scheme)) + (pt.split ? "" : " (no split)")).c_str(),
                pt.tolerance, pt.step, pt.F_m_error, pt.final_error, pt.l2_error, pt.wall_time_s,
                pt.evaluations);
        std::printf("observed order of F_m error in the step:");
        for (Scheme s : {Scheme::central_difference, Scheme::rk4})
            for (bool split : {true, false})
                if (const auto q = observed_order(study, s, split))
                    std::printf("  %s%s %.2f", std::string(to_string(s)).c_str(),
                                split ? "" : " (no split)", *q);
        std::printf("\n");
        if (const auto best = fastest_for(study, target)) {
            std::printf("fastest for a relative F_m error <= %g: %s at tolerance %g (%.4f s)",
                        target, std::string(to_string(best->scheme)).c_str(), best->tolerance,
                        best->wall_time_s);
            for (const auto& pt : study.points)
                if (pt.scheme == Scheme::rk4 && pt.split && pt.F_m_error <= target) {
                    std::printf("; fastest rk4 meeting it: %.4f s (%.1fx)", pt.wall_time_s,
                                pt.wall_time_s / best->wall_time_s);
                    break;
                }
            std::printf("\n");
        } else {
            std::printf("no run reached a relative F_m error <= %g\n", target);
        }
        std::printf("wrote %s/work_precision.csv%s (%.1f s)\n", out.c_str(),
                    no_plot ? "" : ", work_precision.png", study.wall_time_s);
    });
}
