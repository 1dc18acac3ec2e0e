// gapchain-modes: natural frequencies and mode shapes of the linear chain against the paper's
// eq (26); --grid evaluates eq (26) over a grid of (Nm, fc).
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/modes.hpp"
#include "gapchain/report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

int main(int argc, char** argv) {
    using namespace gapchain;
    CLI::App app{"Linear-chain modal analysis (paper Section 5): exact frequencies and mode shapes "
                 "against the approximation f_ka of eq (26).",
                 "gapchain-modes"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, false);
    int Nm = 0, count = 0, grid_fc_points = 60, grid_Nm_max = 20;
    double fc = 0.0, grid_fc_min = 1.0, grid_fc_max = 2000.0;
    std::string method = "auto", end = "lowest", out, csv;
    bool no_shapes = false, grid = false;
    app.add_option("--Nm", Nm, "Number of bodies (overrides the scene)");
    app.add_option("--fc", fc, "Stiffness ratio Kc/K (overrides the scene)");
    app.add_option("--modes", count, "Number of modes (0: all)")->capture_default_str();
    app.add_option("--end", end, "lowest or highest modes")->capture_default_str();
    app.add_option("--method", method, "auto, dense or sparse")->capture_default_str();
    app.add_flag("--no-shapes", no_shapes, "Do not compute the mode shapes");
    app.add_option("--out", out, "JSON result file (with --grid: an output folder)");
    app.add_option("--csv", csv, "Mode shapes as CSV (body, then one column per mode)");
    app.add_flag("--grid", grid, "Evaluate eq (26) over fc in [min, max] (log) and Nm in 1..max");
    app.add_option("--grid-fc-min", grid_fc_min, "Grid: smallest fc")->capture_default_str();
    app.add_option("--grid-fc-max", grid_fc_max, "Grid: largest fc")->capture_default_str();
    app.add_option("--grid-fc-points", grid_fc_points, "Grid: fc values (log-spaced)")
        ->capture_default_str();
    app.add_option("--grid-Nm-max", grid_Nm_max, "Grid: largest Nm")->capture_default_str();

    return cli::run(app, argc, argv, [&] {
        if (grid) {
            if (!(grid_fc_min > 0 && grid_fc_max >= grid_fc_min && std::isfinite(grid_fc_max)))
                throw std::invalid_argument(
                    "--grid-fc-min, --grid-fc-max: need 0 < min <= max, got " +
                    std::to_string(grid_fc_min) + ", " + std::to_string(grid_fc_max));
            if (grid_fc_points < 1 || grid_fc_points > 100000)
                throw std::invalid_argument("--grid-fc-points: must be in [1, 100000], got " +
                                            std::to_string(grid_fc_points));
            if (grid_Nm_max < 1 || grid_Nm_max > 2000)
                throw std::invalid_argument("--grid-Nm-max: must be in [1, 2000], got " +
                                            std::to_string(grid_Nm_max));
            std::vector<int> Nms;
            for (int n = 1; n <= grid_Nm_max; ++n)
                Nms.push_back(n);
            std::vector<double> fcs;
            for (int k = 0; k < grid_fc_points; ++k)
                fcs.push_back(grid_fc_points == 1
                                  ? grid_fc_min
                                  : grid_fc_min *
                                        std::pow(grid_fc_max / grid_fc_min,
                                                 static_cast<double>(k) / (grid_fc_points - 1)));
            const ApproximationGrid g = approximation_grid(Nms, fcs);
            std::printf("eq (26) over Nm in [1, %d] and fc in [%g, %g] (%zu rows):\n", grid_Nm_max,
                        grid_fc_min, grid_fc_max, g.points.size());
            std::printf(
                "  f_1:          max |error| %.3f %% at Nm = %d, fc = %.4g (paper: < 1 %%)\n",
                100 * std::abs(g.worst_first.first), g.worst_first.Nm, g.worst_first.fc);
            std::printf("  other modes:  max |error| %.3f %% at Nm = %d, fc = %.4g, mode %d "
                        "(paper: < 3 %%)\n",
                        100 * g.worst_other.other, g.worst_other.Nm, g.worst_other.fc,
                        g.worst_other.other_mode);
            std::printf("  %.2f s\n", g.wall_time_s);
            if (!out.empty()) {
                std::filesystem::create_directories(out);
                write_file_atomically(out + "/grid.csv", grid_csv(g));
                const std::string script =
                    "# Regenerate: gnuplot grid.gp (in this folder)\n"
                    "set terminal pngcairo size 1000,700 font 'sans,11'\nset output "
                    "'grid-f1-error.png'\n"
                    "set datafile separator ','\nset logscale x\nset xrange [" +
                    std::to_string(grid_fc_min * 0.9) + ":" + std::to_string(grid_fc_max * 1.1) +
                    "]\nset xlabel 'fc'\nset ylabel 'Nm'\n"
                    "set cblabel 'relative error of f_{1a}, eq (26)  [%]'\nset palette defined "
                    "(-1.5 'blue', 0 'white', 1.5 'red')\n"
                    "set cbrange [-1.5:1.5]\nset yrange [0.5:" +
                    std::to_string(grid_Nm_max) +
                    ".5]\nset key off\n"
                    "set title 'eq (26) against the exact first frequency of the linear chain'\n"
                    "plot 'grid.csv' every ::1 using 2:1:(100*$3) with points pt 5 ps 2.2 "
                    "palette\n";
                cli::plot_with_gnuplot(out + "/grid.gp", script);
                std::printf("wrote %s/grid.csv, %s/grid-f1-error.png\n", out.c_str(), out.c_str());
            }
            return;
        }
        if (Nm != 0) scene_args.sets.push_back("model.Nm=" + std::to_string(Nm));
        if (fc != 0.0) {
            std::ostringstream s;
            s.precision(17);
            s << "model.fc=" << fc;
            scene_args.sets.push_back(s.str());
        }
        const Scene scene = cli::load(scene_args);
        ModalOptions o;
        o.count = count;
        o.method = parse_eigen_method(method);
        if (end != "lowest" && end != "highest")
            throw std::invalid_argument("--end: must be lowest or highest, got \"" + end + "\"");
        o.end = end == "lowest" ? SpectrumEnd::lowest : SpectrumEnd::highest;
        o.shapes = !no_shapes || !csv.empty();
        const ModalResult r = modal_analysis(scene.chain(), o);
        if (r.status != ModalStatus::converged)
            throw cli::NumericalFailure("the eigen solver did not converge");
        if (!out.empty())
            write_file_atomically(out, to_json(r, scene.reduced.Nm, scene.reduced.fc));
        if (!csv.empty()) {
            std::ostringstream os;
            os.precision(12);
            os << "body";
            for (int k : r.mode_numbers)
                os << ",mode" << k;
            os << '\n';
            for (int i = 0; i < scene.reduced.Nm; ++i) {
                os << i + 1;
                for (const auto& shape : r.shapes)
                    os << ',' << shape[i];
                os << '\n';
            }
            write_file_atomically(csv, os.str());
        }
        std::printf("gapchain-modes: Nm=%d fc=%g, %zu modes (%s, %.3f s)\n", scene.reduced.Nm,
                    scene.reduced.fc, r.frequencies.size(),
                    std::string(to_string(r.method)).c_str(), r.wall_time_s);
        std::printf("%8s %20s %20s %12s %10s\n", "k", "f_k", "f_ka (eq 26)", "rel.error",
                    "residual");
        const std::size_t shown = std::min<std::size_t>(r.frequencies.size(), 12);
        for (std::size_t m = 0; m < r.frequencies.size(); ++m) {
            if (m == shown && r.frequencies.size() > shown + 2) {
                std::printf("%8s\n", "...");
                m = r.frequencies.size() - 2;
            }
            std::printf("%8d %20.14f %20.14f %11.4f%% %10.1e\n", r.mode_numbers[m],
                        r.frequencies[m], r.approx[m], 100 * r.rel_error[m], r.residuals[m]);
        }
    });
}
