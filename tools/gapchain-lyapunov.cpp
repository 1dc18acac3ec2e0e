// gapchain-lyapunov: Lyapunov exponents of one scene (Benettin / QR on the tangent dynamics).
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/lyapunov.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

namespace {

using namespace gapchain;

void print_exponents(const Scene& scene, const LyapunovResult& r, int k) {
    const ReducedParameters& p = scene.reduced;
    std::printf("gapchain-lyapunov: %s f_r=%g, averaged over %.4g time units (+- one standard "
                "error over 10 blocks: two runs can differ by twice it)\n",
                row_label(scene).c_str(), p.f_r, r.averaging_time);
    bool unestimated = false;
    for (int i = 0; i < k; ++i) {
        unestimated = unestimated || !std::isfinite(r.errors[i]);
        std::printf("  lambda_%-3d = %+.6f %s\n", i + 1, r.exponents[i],
                    std::isfinite(r.errors[i]) ? cli::plus_minus(r.errors[i], "%.2g").c_str()
                                               : "(error not estimated)");
    }
    if (unestimated)
        std::printf("  fewer than 20 periods averaged: no error estimate, and finite-time "
                    "exponents need not come out in order (raise run.periods)\n");
    if (r.drifting)
        std::printf("  the block rates drift (the run has not reached its attractor, or nears it "
                    "slowly): an exponent whose rates drift has that drift as its error; raise "
                    "run.transient_periods\n");
    // A researcher's probe (helper-81): Nm 3, fc 100, eps 0.2, e_r 0.1 at f_r = 1.5 read
    // lambda_1 = +1.49 with no word that gapchain-attractors finds one attractor there, a
    // period-3 orbit, and the chaos a transient.
    // Beyond its error where it has one: a torus's +1e-5 +- 1e-3 is no sign of chaos.
    if (k > 0 && r.exponents[0] > (std::isfinite(r.errors[0]) ? r.errors[0] : 0.0))
        std::printf("  note: a positive lambda_1 is also what a chaotic transient gives until it "
                    "ends; other starts and longer runs were not tried (gapchain-attractors, or "
                    "gapchain-classify --attractors N, tells a transient from an attractor)\n");
    std::printf("  sum = %.10f", r.sum);
    if (!std::isnan(r.expected_sum))
        std::printf(scene.uniform() ? "  (exact: -4 pi eps Nm = %.10f)"
                                    : "  (exact: the trace, -sum of the damping rates = %.10f)",
                    r.expected_sum);
    std::printf("\n  wall time %.3f s\n", r.wall_time_s);
}

} // namespace

// The JSON, the history CSV and (unless no_plot) its figure, written in place: the plot reads
// them, so a failed plot puts the previous files back (Outputs::replacing). With no_plot an
// earlier run's figure (a plain file at the figure's paths, which were not checked as
// outputs) is set aside too, and dropped with the run kept: it stayed beside the new numbers.
void write_results(cli::Outputs& outputs, const LyapunovResult& r, const Scene& scene, int k,
                   const std::string& out, const std::string& stem, bool no_plot) {
    outputs.replacing(out);
    outputs.replacing(stem + "_history.csv");
    for (const char* figure : {"_convergence.gp", "_convergence.png"})
        if (!no_plot ||
            std::filesystem::is_regular_file(std::filesystem::symlink_status(stem + figure)))
            outputs.replacing(stem + figure);
    write_file_atomically(out, to_json(r, scene));
    write_file_atomically(stem + "_history.csv", history_csv(r));
    if (!no_plot) {
        auto name = [](const std::string& path) {
            return std::filesystem::path(path).filename().string();
        };
        cli::plot_with_gnuplot(
            stem + "_convergence.gp",
            cli::plot_script("lyapunov", {{"PNG", name(stem + "_convergence.png")},
                                          {"CSV", name(stem + "_history.csv")},
                                          {"LAST", std::to_string(1 + std::min(k, 8))}}));
    }
}

int main(int argc, char** argv) {
    CLI::App app{
        "Lyapunov exponents of a row (Benettin with QR re-orthonormalisation every forcing "
        "period) over the scene's run.periods, averaged after run.transient_periods.",
        "gapchain-lyapunov"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, true);
    int count = 0;
    std::string out = "lyapunov.json";
    bool no_plot = false;
    app.add_option("--count", count, "Exponents wanted (0: all 2 Nm)")
        ->check(cli::range(0, 2'000'000))
        ->capture_default_str();
    app.add_option("--out", out, "JSON result; the history goes next to it (_history.csv, .png)")
        ->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the JSON and CSV only");
    return cli::run(app, argc, argv,
                    [&] {
                        cli::require_sets_read(scene_args, "gapchain-lyapunov",
                                               once_through_run_keys, cli::plain_run_reason);
                        const Scene scene = cli::load(scene_args);
                        const Dynamics dyn = scene.dynamics();
                        const int k = count == 0 ? dyn.dimension() : count;
                        if (k > dyn.dimension())
                            throw std::invalid_argument("--count: must be in [0, 2 Nm = " +
                                                        std::to_string(dyn.dimension()) +
                                                        "], got " + std::to_string(count));
                        const std::string stem = out.size() > 5 && out.ends_with(".json")
                                                     ? out.substr(0, out.size() - 5)
                                                     : out;
                        cli::Outputs outputs({scene_args.path});
                        outputs.required_file(out, "--out");
                        outputs.file(stem + "_history.csv", "--out (its _history.csv)");
                        if (!no_plot) {
                            outputs.file(stem + "_convergence.gp", "--out (its _convergence.gp)");
                            outputs.file(stem + "_convergence.png", "--out (its _convergence.png)");
                        }
                        cli::Progress progress("gapchain-lyapunov");
                        const LyapunovResult r =
                            chain_lyapunov(dyn, scene.run, k, scene.initial, progress.callback());
                        cli::throw_if_interrupted();
                        if (r.status == RunStatus::non_finite)
                            throw cli::NumericalFailure(r.message);
                        write_results(outputs, r, scene, k, out, stem, no_plot);
                        outputs.keep();
                        print_exponents(scene, r, k);
                    },
                    // The work refusal's advice named the library's "(count)" (helper-85).
                    {{"count", "--count"}});
}
