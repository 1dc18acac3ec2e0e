// gapchain-classify: regime of one point, or a regime map over (e_r, f_r) as Fig 2 of the paper.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/classify.hpp"
#include "gapchain/report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace {

// "from:to:count" -> count values, ends included.
std::vector<double> parse_range(const std::string& text, const std::string& key) {
    double from = 0, to = 0;
    int count = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%lf:%lf:%d%c", &from, &to, &count, &extra) != 3 || count < 1 ||
        count > 100000 || !std::isfinite(from) || !std::isfinite(to))
        throw std::invalid_argument(
            key + ": must be from:to:count with 1 <= count <= 100000, got \"" + text + "\"");
    std::vector<double> v;
    for (int k = 0; k < count; ++k)
        v.push_back(count == 1 ? from : from + (to - from) * k / (count - 1));
    return v;
}

} // namespace

int main(int argc, char** argv) {
    using namespace gapchain;
    CLI::App app{
        "Classify a row as no-contact, periodic (with its period), quasi-periodic or chaotic, "
        "with the evidence (largest Lyapunov exponent and error, section points, broadband "
        "share). --map classifies a grid of (e_r, f_r), in parallel.",
        "gapchain-classify"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, true);
    ClassifyOptions o;
    std::string out, e_r_range = "0:1.5:100", f_r_range = "0.1:5:100";
    bool map = false, no_plot = false;
    int threads = 0;
    app.add_option("--out", out, "JSON result (one point) or output folder (--map)");
    app.add_flag("--map", map, "Classify a grid of (e_r, f_r)");
    app.add_option("--e_r", e_r_range, "Map rows: from:to:count")->capture_default_str();
    app.add_option("--f_r", f_r_range, "Map columns: from:to:count")->capture_default_str();
    app.add_option("--transient", o.transient_periods,
                   "Settling periods (ended early by a steady state)")
        ->capture_default_str();
    app.add_option("--record", o.record_periods, "Recorded periods for non-periodic motion")
        ->capture_default_str();
    app.add_option("--threads", threads, "OpenMP threads for --map (0: all)")
        ->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the CSV only");
    return cli::run(app, argc, argv, [&] {
        const Scene scene = cli::load(scene_args);
        if (!scene.uniform())
            throw std::invalid_argument(
                "model arrays and scatter: gapchain-classify takes the paper's uniform row only "
                "(Nm, fc, eps, e_r); non-uniform rows work in gapchain-sim, -poincare, -spectrum, "
                "-lyapunov, -modes and -accuracy");
        o.scheme = scene.run.scheme;
        o.tolerance = scene.run.tolerance;
        validate(o);
        const ReducedParameters& p = scene.reduced;
        if (!map) {
            const Classification c = classify(p, o);
            if (c.status == RunStatus::non_finite)
                throw cli::NumericalFailure("the run became non-finite");
            if (!out.empty()) write_file_atomically(out, to_json(c, p));
            std::printf("gapchain-classify: Nm=%d fc=%g eps=%g e_r=%g f_r=%g\n", p.Nm, p.fc, p.eps,
                        p.e_r, p.f_r);
            std::printf("regime %s", std::string(to_string(c.regime)).c_str());
            if (c.regime == Regime::periodic)
                std::printf(" (period %d%s)", c.period, c.period == 0 ? ": longer than max" : "");
            std::printf("\n  lambda_max = %+.4f +- %.2g, %d distinct of %d section points, "
                        "broadband share %.3f\n",
                        c.lambda_max, c.lambda_max_error, c.distinct_points, c.section_points,
                        c.broadband_share);
            std::printf("  F_m = %.6g, %ld periods, %.3f s\n", c.F_m, c.periods_run, c.wall_time_s);
            return;
        }
        const std::vector<double> e_r = parse_range(e_r_range, "--e_r");
        const std::vector<double> f_r = parse_range(f_r_range, "--f_r");
        if (out.empty()) out = "map";
        cli::Progress progress("gapchain-classify");
        const RegimeMap m = regime_map(p, e_r, f_r, o, threads, progress.callback());
        std::filesystem::create_directories(out);
        write_file_atomically(out + "/map.csv", map_csv(m));
        int counts[4] = {0, 0, 0, 0};
        for (const auto& c : m.cells)
            ++counts[static_cast<int>(c.regime)];
        if (!no_plot) {
            char boundary[160];
            std::snprintf(boundary, sizeof boundary,
                          "1/sqrt((1-x**2)**2+4*%.17g**2*x**2) with lines lw 2 lc rgb 'black' "
                          "title 'eq (20): no impact above'",
                          p.eps);
            std::string white = boundary;
            white.replace(white.find("'black'"), 7, "'white'");
            char title[160];
            std::snprintf(title, sizeof title, "Nm=%d fc=%g eps=%g", p.Nm, p.fc, p.eps);
            const std::string head =
                "set terminal pngcairo size 1000,750 font 'sans,11'\nset datafile separator ','\n"
                "set xlabel 'f_r'\nset ylabel 'e_r'\nset xrange [" +
                std::to_string(f_r.front()) + ":" + std::to_string(f_r.back()) + "]\nset yrange [" +
                std::to_string(e_r.front()) + ":" + std::to_string(e_r.back()) +
                "]\nset key top right opaque\n";
            cli::plot_with_gnuplot(
                out + "/map.gp",
                "# Regenerate: gnuplot map.gp (in this folder)\n" + head +
                    "set output 'regimes.png'\nset title 'Regimes, " + std::string(title) +
                    "'\n"
                    "set palette maxcolors 4\nset palette defined (0 '#e8e8e8', 1 '#4c9be8', 2 "
                    "'#f2b134', 3 '#d62728')\n"
                    "set cbrange [-0.5:3.5]\nset cbtics ('no contact' 0, 'periodic' 1, "
                    "'quasi-periodic' 2, 'chaotic' 3)\n"
                    "plot 'map.csv' every ::1 using 2:1:4 with image notitle, " +
                    boundary +
                    "\n"
                    "set output 'force.png'\nset title 'F_m, " +
                    std::string(title) +
                    "'\n"
                    "set palette maxcolors 0\nset palette rgbformulae 21,22,23\nset cbrange "
                    "[*:*]\nset cbtics auto\n"
                    "set cblabel 'F_m'\nplot 'map.csv' every ::1 using 2:1:6 with image notitle, " +
                    white + "\n");
        }
        std::printf("gapchain-classify: %zu x %zu map (e_r x f_r), %d threads, %.1f s\n",
                    e_r.size(), f_r.size(), m.threads_used, m.wall_time_s);
        std::printf("  no-contact %d, periodic %d, quasi-periodic %d, chaotic %d\n", counts[0],
                    counts[1], counts[2], counts[3]);
        std::printf("wrote %s/map.csv%s\n", out.c_str(), no_plot ? "" : ", regimes.png, force.png");
    });
}
