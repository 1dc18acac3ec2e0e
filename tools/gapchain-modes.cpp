// gapchain-modes: natural frequencies and mode shapes of the linear chain against the paper's
// eq (26); --grid evaluates eq (26) over a grid of (Nm, fc).
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/grid.hpp"
#include "gapchain/modes.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace {

using namespace gapchain;

// --grid: eq (26) over Nm in [1, Nm_max] and fc log-spaced in [fc_min, fc_max].
struct GridArguments {
    int fc_points = 60, Nm_max = 20;
    double fc_min = 1.0, fc_max = 2000.0;
    bool no_plot = false;
};

void grid_study(const GridArguments& a, const std::string& out, cli::Outputs& outputs) {
    for (const auto& [flag, fc] :
         {std::pair{"--grid-fc-min", a.fc_min}, {"--grid-fc-max", a.fc_max}})
        if (fc > 1e9)
            throw std::invalid_argument(std::string(flag) +
                                        ": must be at most 1e9 (model.fc's range), got " +
                                        cli::number_text(fc, 9));
    if (!(a.fc_max >= a.fc_min))
        throw std::invalid_argument(
            "--grid-fc-max: must be >= --grid-fc-min = " + cli::number_text(a.fc_min, 9) +
            ", got " + cli::number_text(a.fc_max, 9));
    // One point ran --grid-fc-min alone, and equal ends ran one fc again and again.
    if (a.fc_points == 1 && a.fc_min != a.fc_max)
        throw std::invalid_argument("--grid-fc-points: 1 point needs --grid-fc-min = "
                                    "--grid-fc-max, got " +
                                    cli::number_text(a.fc_min, 9) + " and " +
                                    cli::number_text(a.fc_max, 9));
    if (a.fc_points > 1 && a.fc_min == a.fc_max)
        throw std::invalid_argument("--grid-fc-points: --grid-fc-min = --grid-fc-max (" +
                                    cli::number_text(a.fc_min, 9) +
                                    ") is one value, 1 point, got " + std::to_string(a.fc_points));
    if (!out.empty()) outputs.folder(out, "--out", {"grid.csv", "grid.gp", "grid-f1-error.png"});
    std::vector<int> Nms;
    for (int n = 1; n <= a.Nm_max; ++n)
        Nms.push_back(n);
    cli::Progress progress("gapchain-modes");
    const ApproximationGrid g =
        approximation_grid(Nms, logspace(a.fc_min, a.fc_max, a.fc_points), progress.callback());
    cli::throw_if_interrupted();
    std::printf("eq (26) over Nm in [1, %d] and fc in [%g, %g] (%zu rows):\n", a.Nm_max, a.fc_min,
                a.fc_max, g.points.size());
    std::printf("  f_1:          max |error| %.3f %% at Nm = %d, fc = %.4g (paper: < 1 %%)\n",
                100 * std::abs(g.worst_first.first), g.worst_first.Nm, g.worst_first.fc);
    std::printf("  other modes:  max |error| %.3f %% at Nm = %d, fc = %.4g, mode %d "
                "(paper: < 3 %%)\n",
                100 * g.worst_other.other, g.worst_other.Nm, g.worst_other.fc,
                g.worst_other.other_mode);
    std::printf("  %.2f s\n", g.wall_time_s);
    if (out.empty()) return;
    outputs.create_folders();
    const std::string staged = outputs.staged(out);
    write_file_atomically(staged + "/grid.csv", grid_csv(g));
    if (!a.no_plot)
        cli::plot_template(staged, "grid",
                           {{"FC_FROM", cli::number_text(a.fc_min * 0.9)},
                            {"FC_TO", cli::number_text(a.fc_max * 1.1)},
                            {"NM_MAX", std::to_string(a.Nm_max)}});
    outputs.keep();
    std::printf("wrote %s/grid.csv%s\n", out.c_str(),
                a.no_plot ? "" : (", " + out + "/grid-f1-error.png").c_str());
}

void print_modes(const Scene& scene, const ModalResult& r) {
    std::printf("gapchain-modes: Nm=%d fc=%g, %zu modes (%s, %.3f s)\n", scene.reduced.Nm,
                scene.reduced.fc, r.frequencies.size(), std::string(to_string(r.method)).c_str(),
                r.wall_time_s);
    std::printf("%8s %20s %20s %12s %10s\n", "k", "f_k", "f_ka (eq 26)", "rel.error", "residual");
    const std::size_t shown = std::min<std::size_t>(r.frequencies.size(), 12);
    for (std::size_t m = 0; m < r.frequencies.size(); ++m) {
        if (m == shown && r.frequencies.size() > shown + 2) {
            std::printf("%8s\n", "...");
            m = r.frequencies.size() - 2;
        }
        if (std::isnan(r.approx[m]))
            std::printf("%8d %20.14f %20s %12s %10.1e\n", r.mode_numbers[m], r.frequencies[m], "-",
                        "-", r.residuals[m]);
        else
            std::printf("%8d %20.14f %20.14f %11.4f%% %10.1e\n", r.mode_numbers[m],
                        r.frequencies[m], r.approx[m], 100 * r.rel_error[m], r.residuals[m]);
    }
    if (!r.approx.empty() && std::isnan(r.approx.front()))
        std::printf("(eq (26) describes the paper's uniform row; this row's masses, springs or "
                    "contacts differ: not compared)\n");
}

// The command line: one row's modes, or with --grid eq (26) over a grid.
struct ModesArguments {
    cli::SceneArguments scene;
    int Nm = 0;
    double fc = 0.0;
    std::string method = "auto", end = "lowest", out, csv;
    bool no_shapes = false, grid = false;
    ModalOptions options;
    GridArguments grid_args;
};

void add_options(CLI::App& app, ModesArguments& a) {
    cli::add_scene_arguments(app, a.scene, false);
    ModalOptions& o = a.options;
    auto* grid_flag = app.add_flag("--grid", a.grid,
                                   "Evaluate eq (26) over fc in [min, max] (log) and Nm in 1..max");
    std::vector<CLI::Option*> single{
        app.add_option("--Nm", a.Nm, "Number of bodies (overrides the scene)")
            ->check(cli::range(1, 1'000'000)),
        // model.fc's range, named by the flag given (the scene's refusal named model.fc).
        app.add_option("--fc", a.fc, "Stiffness ratio Kc/K (overrides the scene), in (0, 1e9]")
            ->check(cli::positive_number())
            ->check(cli::number_range(0.0, 1e9, false)),
        app.add_option("--modes", o.count, "Number of modes (0: all)")
            ->check(cli::range(0, 1'000'000))
            ->capture_default_str(),
        app.add_option("--end", a.end, "lowest or highest modes")
            ->check(CLI::IsMember({"lowest", "highest"}))
            ->capture_default_str(),
        app.add_option("--method", a.method, "auto, dense or sparse")
            ->check(CLI::IsMember({"auto", "dense", "sparse"}))
            ->capture_default_str(),
        app.add_option("--max-dense", o.max_dense_bodies,
                       "Largest Nm for the dense solver (memory 8 Nm^2 bytes, time ~Nm^3)")
            ->check(cli::range(1, 1'000'000))
            ->capture_default_str(),
        app.add_flag("--no-shapes", a.no_shapes, "Do not compute the mode shapes"),
        app.add_option("--csv", a.csv, "Mode shapes as CSV (body, then one column per mode)")
            ->check(cli::non_empty_path())};
    // --csv writes the shapes: with --no-shapes one of the two was silently ignored.
    app.get_option("--no-shapes")->excludes(app.get_option("--csv"));
    // The grid is eq (26) alone: a scene or --set would be ignored.
    single.push_back(a.scene.option);
    single.push_back(app.get_option("--set"));
    for (auto* option : single)
        option->excludes(grid_flag);
    auto* out = app.add_option("--out", a.out, "JSON result file (with --grid: an output folder)")
                    ->check(cli::non_empty_path());
    GridArguments& g = a.grid_args;
    app.add_option("--grid-fc-min", g.fc_min, "Grid: smallest fc")
        ->check(cli::positive_number())
        ->needs(grid_flag)
        ->capture_default_str();
    app.add_option("--grid-fc-max", g.fc_max, "Grid: largest fc")
        ->check(cli::positive_number())
        ->needs(grid_flag)
        ->capture_default_str();
    app.add_option("--grid-fc-points", g.fc_points, "Grid: fc values (log-spaced)")
        ->check(cli::range(1, 100000))
        ->needs(grid_flag)
        ->capture_default_str();
    app.add_option("--grid-Nm-max", g.Nm_max, "Grid: largest Nm")
        ->check(cli::range(1, 2000))
        ->needs(grid_flag)
        ->capture_default_str();
    // Without --out the grid is printed only, and there is no figure to leave out.
    app.add_flag("--no-plot", g.no_plot, "Grid: write the CSV only")->needs(grid_flag)->needs(out);
}

// The scene with --Nm and --fc applied as overrides.
Scene load_row(ModesArguments& a) {
    cli::require_sets_read(a.scene, "gapchain-modes", {}, "its modes follow from the model alone");
    // Nor do the forcing, the start, the damping or the clearances: a --set of them was taken
    // and ignored.
    cli::refuse_unread_sets(a.scene, "gapchain-modes", key_unread_by_modes,
                            "the linear chain's modes follow from its masses, springs and "
                            "contact stiffnesses alone");
    // --Nm first: a scene read at its own Nm refused arrays of --Nm's length ("model.mass:
    // must have 5 entries" for --Nm 3), and then its own length as well.
    if (a.Nm != 0) a.scene.sets.push_back("model.Nm=" + std::to_string(a.Nm));
    if (a.fc != 0.0 && cli::load(a.scene).units == Units::physical)
        throw std::invalid_argument("--fc: not for a physical scene (its fc is model.Kc / "
                                    "model.K); change those with --set");
    if (a.fc != 0.0) {
        std::ostringstream s;
        s.precision(17);
        s << "model.fc=" << a.fc;
        a.scene.sets.push_back(s.str());
    }
    return cli::load(a.scene);
}

// Flags that change nothing where they were given: they ran and said nothing (a hostile
// probe, helper-85).
void refuse_unused_flags(const CLI::App& app, const ModesArguments& a, int Nm) {
    const int count = a.options.count;
    if (app.count("--end") > 0 && (count == 0 || count >= Nm))
        throw std::invalid_argument("--end: picks which --modes N of the " + std::to_string(Nm) +
                                    " to compute, N < Nm; --modes " + std::to_string(count) +
                                    " computes every mode");
    if (app.count("--max-dense") > 0 && a.method != "auto")
        throw std::invalid_argument("--max-dense: chooses the solver for --method auto only, got "
                                    "--method " +
                                    a.method);
}

void write_outputs(const ModalResult& r, const ModesArguments& a, const Scene& scene) {
    if (!a.out.empty())
        write_file_atomically(a.out, to_json(r, scene.reduced.Nm, scene.reduced.fc));
    if (!a.csv.empty()) write_file_atomically(a.csv, mode_shapes_csv(r, scene.reduced.Nm));
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Linear-chain modal analysis (paper Section 5): exact frequencies and mode shapes "
                 "against the approximation f_ka of eq (26).",
                 "gapchain-modes"};
    ModesArguments a;
    add_options(app, a);
    return cli::run(app, argc, argv,
                    [&] {
                        cli::Outputs outputs({a.scene.path});
                        if (a.grid) return grid_study(a.grid_args, a.out, outputs);
                        const Scene scene = load_row(a);
                        outputs.file(a.out, "--out");
                        outputs.file(a.csv, "--csv");
                        ModalOptions& o = a.options;
                        refuse_unused_flags(app, a, scene.reduced.Nm);
                        o.method = parse_eigen_method(a.method);
                        o.end = a.end == "lowest" ? SpectrumEnd::lowest : SpectrumEnd::highest;
                        o.shapes = !a.no_shapes || !a.csv.empty();
                        const ModalResult r = [&] {
                            const cli::Uninterruptible solving; // no progress in the solvers
                            return modal_analysis(scene.chain(), o);
                        }();
                        if (r.status != ModalStatus::converged)
                            throw cli::NumericalFailure("the eigen solver did not converge");
                        write_outputs(r, a, scene);
                        outputs.keep();
                        print_modes(scene, r);
                    },
                    {{"count", "--modes"},
                     {"max_dense_bodies", "--max-dense"},
                     {"fc_values", "--grid-fc-points"},
                     {"(fewer fc values or a smaller largest Nm)",
                      "(fewer --grid-fc-points or a smaller --grid-Nm-max)"}});
}
