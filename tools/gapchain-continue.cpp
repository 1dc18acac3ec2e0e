// gapchain-continue: pseudo-arclength continuation of periodic orbits in one reduced parameter,
// with folds, period doublings, Neimark-Sacker and grazing points located on the way:
// DIR/branch.csv, DIR/special.csv and DIR/branch.png.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/continuation.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace {

using namespace gapchain;

struct ContinueArguments {
    cli::SceneArguments scene;
    ContinuationOptions options;
    std::string param = "f_r";
    std::string overlay; // a gapchain-bifurcation summary.csv drawn underneath
    std::string scheme = "exact";
    std::string out_dir = "continuation";
    bool no_plot = false;
};

// The overlay must be what gapchain-bifurcation writes: gnuplot would draw anything else as
// nothing, or as garbage, without a word.
void check_overlay(const std::string& path) {
    cli::refuse_control_characters(path, "--overlay");
    std::ifstream in(path);
    std::string line;
    const std::string expected = "value,direction,F_m,";
    if (!in || !std::getline(in, line) || line.rfind(expected, 0) != 0)
        throw std::invalid_argument("--overlay: expected a gapchain-bifurcation summary.csv "
                                    "(header value,direction,F_m,...), got \"" +
                                    path + "\"");
    // Every row as the header has it: a row cut short, one with extra fields or a direction
    // other than up and down was drawn as it came (a helper's probe, 2026-11-27).
    const auto fields = [](const std::string& text) {
        return static_cast<long>(std::count(text.begin(), text.end(), ',')) + 1;
    };
    const long header_fields = fields(line);
    long rows = 0;
    for (long row = 2; std::getline(in, line); ++row) {
        if (line.empty()) continue;
        ++rows;
        const auto first = line.find(','), second = line.find(',', first + 1);
        const auto third = line.find(',', second + 1);
        // The whole field must be the number: stod reads "2.9x" as 2.9.
        const auto number = [](const std::string& field) {
            std::size_t used = 0;
            try {
                const double x = std::stod(field, &used);
                return used == field.size() ? x : NAN;
            } catch (const std::exception&) {
                return static_cast<double>(NAN);
            }
        };
        const double value = number(line.substr(0, first));
        const double force = number(line.substr(second + 1, third - second - 1));
        const std::string direction =
            first == std::string::npos ? "" : line.substr(first + 1, second - first - 1);
        if (fields(line) != header_fields || (direction != "up" && direction != "down") ||
            !std::isfinite(value) || !std::isfinite(force) || force < 0.0)
            throw std::invalid_argument(
                "--overlay: row " + std::to_string(row) + " of " + path + " needs " +
                std::to_string(header_fields) +
                " fields as its header, a finite value, a direction up or down and a finite F_m "
                ">= 0, got \"" +
                line + "\"");
    }
    if (rows == 0) throw std::invalid_argument("--overlay: " + path + " has a header but no rows");
}

// The bifurcation.json gapchain-bifurcation writes beside summary.csv names the parameter and
// the base row: an overlay of another line (another parameter or row) would be drawn on this
// one's axis under its title.
void check_overlay_line(const std::string& path, const std::string& param,
                        const ReducedParameters& base) {
    const std::filesystem::path sidecar =
        std::filesystem::absolute(path).parent_path() / "bifurcation.json";
    std::ifstream in(sidecar);
    nlohmann::json line;
    try {
        line = nlohmann::json::parse(in);
    } catch (const std::exception&) {
        throw std::invalid_argument("--overlay: needs the bifurcation.json gapchain-bifurcation "
                                    "wrote beside it, to check it is this line; cannot read " +
                                    sidecar.string());
    }
    const auto parameter = line.value("parameter", std::string());
    if (parameter != param)
        throw std::invalid_argument("--overlay: " + path + " sweeps " + parameter +
                                    ", this continuation " + param);
    const nlohmann::json& b = line.value("base", nlohmann::json::object());
    const std::pair<const char*, double> row[] = {
        {"Nm", base.Nm}, {"fc", base.fc}, {"eps", base.eps}, {"e_r", base.e_r}, {"f_r", base.f_r}};
    for (const auto& [key, value] : row) {
        if (key == param) continue;
        const double theirs = b.value(key, std::nan(""));
        if (!(std::abs(theirs - value) <= 1e-9 * std::abs(value)))
            throw std::invalid_argument("--overlay: " + path + " is another row: its " + key +
                                        " is " + cli::number_text(theirs, 12) + ", this scene's " +
                                        cli::number_text(value, 12));
    }
}

void add_options(CLI::App& app, ContinueArguments& a) {
    ContinuationOptions& o = a.options;
    cli::add_scene_arguments(app, a.scene, true);
    app.add_option("--param", a.param, "Continued parameter")
        ->check(CLI::IsMember({"f_r", "e_r", "fc", "eps"}))
        ->capture_default_str();
    app.add_option("--from", o.from, "Start value (the first orbit is found there)")->required();
    app.add_option("--to", o.to, "End value")->required();
    app.add_option("--period", o.period, "k: forcing periods of the first orbit")
        ->check(cli::range(1, 1000))
        ->capture_default_str();
    app.add_option("--step", o.step, "First arclength step")
        ->check(cli::range(1e-6, 1.0))
        ->capture_default_str();
    app.add_option("--max-step", o.max_step, "Largest arclength step")
        ->check(cli::range(1e-6, 1.0))
        ->capture_default_str();
    app.add_option("--max-points", o.max_points, "Points per branch")
        ->check(cli::range(1, 1'000'000))
        ->capture_default_str();
    app.add_flag("--follow-doublings", o.follow_doublings,
                 "At each period doubling (and each non-smooth loss of stability next to -1), "
                 "switch to the doubled branch and follow it");
    app.add_option("--max-branches", o.max_branches,
                   "Branches followed in all: restarts beyond a point where a branch ended, and "
                   "with --follow-doublings the doubled branches")
        ->check(cli::range(1, 64))
        ->capture_default_str();
    app.add_option("--transient", o.transient_periods,
                   "Periods run from the scene's initial state before the first Newton search")
        ->check(cli::range(0L, 10'000'000L))
        ->capture_default_str();
    app.add_option("--scheme", a.scheme,
                   "Integration of the k-period map, to 1e-12 (exact: rows of up to 64 bodies; the "
                   "scene's run.scheme, run.step and run.tolerance are not used)")
        ->check(CLI::IsMember({"exact", "rk4", "rkf45", "rk8pd"}))
        ->capture_default_str();
    auto* overlay =
        app.add_option("--overlay", a.overlay,
                       "A gapchain-bifurcation summary.csv of the same line, drawn underneath")
            ->check(CLI::ExistingFile);
    app.add_option("--out", a.out_dir, "Output folder")->capture_default_str();
    // The overlay is only drawn: without a plot it was checked, then ignored.
    app.add_flag("--no-plot", a.no_plot, "Write the CSV files only")->excludes(overlay);
}

void print_summary(const ContinuationResult& r, const ContinueArguments& a) {
    std::printf("gapchain-continue: %s from %g to %g: %zu orbits on %zu branches, %ld shootings, "
                "%.2f s\n",
                a.param.c_str(), a.options.from, a.options.to, r.points.size(), r.branch_end.size(),
                r.shootings, r.wall_time_s);
    const ForceErrorSummary errors = force_error_summary(r);
    if (errors.unestimated == errors.orbits)
        std::printf("  F_m errors not estimated (the independent scheme's check did not run)");
    else
        std::printf("  F_m errors up to %.2g (against an independent scheme)", errors.largest);
    if (errors.unestimated > 0 && errors.unestimated < errors.orbits)
        std::printf("; %ld of %ld orbits not estimated", errors.unestimated, errors.orbits);
    std::printf("\n");
    for (std::size_t b = 0; b < r.branch_end.size(); ++b)
        std::printf("  branch %zu ended: %s\n", b, r.branch_end[b].c_str());
    if (!r.unfollowed.empty()) {
        std::printf("  %zu branch(es) found and not followed (--max-branches %d reached):",
                    r.unfollowed.size(), a.options.max_branches);
        for (std::size_t i = 0; i < r.unfollowed.size(); ++i)
            std::printf("%s %s", i == 0 ? "" : ";", r.unfollowed[i].c_str());
        std::printf("\n");
    }
    for (const auto& s : r.special) {
        std::printf("  %-16s %s = %.8f +- %.1e  (period %d, F_m %.5g %s, branch %d",
                    std::string(to_string(s.type)).c_str(), a.param.c_str(), s.value, s.value_error,
                    s.period, s.F_m, cli::plus_minus(s.F_m_error, "%.1g").c_str(), s.branch);
        if (s.contact >= 0) std::printf(", contact %d", s.contact);
        std::printf(")\n");
    }
    std::printf("wrote %s/branch.csv, special.csv, continuation.json%s\n", a.out_dir.c_str(),
                a.no_plot ? "" : ", branch.png");
}

bool write_outputs(const ContinuationResult& r, const ContinueArguments& a,
                   const std::string& out_dir, const Scene& scene) {
    write_file_atomically(out_dir + "/branch.csv", branch_csv(r));
    write_file_atomically(out_dir + "/special.csv", special_csv(r));
    write_file_atomically(out_dir + "/continuation.json", to_json(r, a.options, scene));
    const std::string overlay =
        a.overlay.empty() ? "" : std::filesystem::absolute(a.overlay).string();
    const std::string title = "Periodic orbits: " + cli::row_title(scene.reduced, a.param);
    return !a.no_plot &&
           cli::plot_template(out_dir, "branch",
                              {{"TITLE", title}, {"PARAM", a.param}, {"OVERLAY", overlay}});
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Continue the periodic orbits of a row in one reduced parameter (pseudo-"
                 "arclength, Newton shooting with the exact monodromy), locating folds, period "
                 "doublings, Neimark-Sacker and grazing points.",
                 "gapchain-continue"};
    ContinueArguments a;
    add_options(app, a);
    return cli::run(app, argc, argv,
                    [&] {
                        cli::require_not_set(a.scene, a.param, "gapchain-continue");
                        cli::require_sets_read(a.scene, "gapchain-continue", {"run.max_work"},
                                               "its shootings integrate with --scheme to 1e-12");
                        const Scene scene = cli::load(a.scene);
                        require_paper_row(scene, "gapchain-continue");
                        a.options.parameter = parse_swept_parameter(a.param);
                        a.options.orbit.scheme = parse_scheme(a.scheme);
                        a.options.orbit.max_work = scene.run.max_work;
                        validate(a.options);
                        if (!a.overlay.empty()) {
                            check_overlay(a.overlay);
                            check_overlay_line(a.overlay, a.param, scene.reduced);
                        }
                        cli::Outputs outputs({a.scene.path, a.overlay});
                        outputs.folder(a.out_dir, "--out",
                                       {"branch.csv", "special.csv", "continuation.json",
                                        "branch.gp", "branch.png"});
                        cli::Progress progress("gapchain-continue");
                        const ContinuationResult r = continue_orbits(
                            scene.reduced, a.options, scene.initial, progress.callback());
                        // Interrupted after some orbits: they are written, not plotted.
                        if (r.points.empty()) cli::throw_if_interrupted();
                        a.no_plot = a.no_plot || r.cancelled || cli::interrupted();
                        if (r.points.empty())
                            throw cli::NumericalFailure(
                                r.branch_end.empty() ? "no orbit found" : r.branch_end.front());
                        outputs.create_folders();
                        write_outputs(r, a, outputs.staged(a.out_dir), scene);
                        outputs.keep();
                        cli::throw_if_interrupted(std::to_string(r.points.size()) + " orbits and " +
                                                  std::to_string(r.special.size()) +
                                                  " special points found, in " + a.out_dir +
                                                  "/branch.csv, special.csv and "
                                                  "continuation.json" +
                                                  (r.cancelled ? " (\"cancelled\": true)" : ""));
                        print_summary(r, a);
                    },
                    {{"run.periods", "--transient"},
                     {"(excitation.f_r)", "(excitation.f_r, or --from / --to with --param f_r)"},
                     {"transient_periods", "--transient"},
                     {"scheme", "--scheme"},
                     {"max_points", "--max-points"},
                     {"max_branches", "--max-branches"},
                     {"(a larger max_step, fewer max_points or max_branches)",
                      "(a larger --max-step, fewer --max-points or --max-branches)"},
                     {"step", "--step"},
                     {"max_step", "--max-step"},
                     {"from", "--from"},
                     {"to", "--to"},
                     {"period", "--period"}});
}
