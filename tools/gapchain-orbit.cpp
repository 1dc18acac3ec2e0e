// gapchain-orbit: a periodic orbit of one scene by Newton shooting, with its Floquet multipliers.
#include "common/cli.hpp"

#include "gapchain/orbit.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <cmath>
#include <cstdio>

namespace {

using namespace gapchain;

struct OrbitArguments {
    cli::SceneArguments scene;
    OrbitOptions options;
    long transient = 200;
    std::string scheme = "exact";
    std::string out = "orbit.json";
};

void add_options(CLI::App& app, OrbitArguments& a) {
    cli::add_scene_arguments(app, a.scene, true);
    app.add_option("--period", a.options.period, "k: forcing periods of the orbit")
        ->check(cli::range(1, 1000))
        ->capture_default_str();
    app.add_option("--from-transient", a.transient,
                   "Periods run from the scene's initial state before Newton starts")
        ->check(cli::range(0L, 10'000'000L))
        ->capture_default_str();
    app.add_option("--tolerance", a.options.tolerance, "Residual |P^k(x) - x| / (1 + |x|)")
        ->check(cli::range(1e-14, 1e-3))
        ->capture_default_str();
    app.add_option("--max-iterations", a.options.max_iterations, "Newton iterations")
        ->check(cli::range(1, 1000))
        ->capture_default_str();
    app.add_option("--scheme", a.scheme,
                   "Integration of the k-period map, to 1e-12 (exact: rows of up to 64 bodies; the "
                   "scene's run.scheme, run.step and run.tolerance are not used)")
        ->check(CLI::IsMember({"exact", "rk4", "rkf45", "rk8pd"}))
        ->capture_default_str();
    app.add_option("--out", a.out, "JSON result")->capture_default_str();
}

void print_orbit(const PeriodicOrbit& orbit) {
    std::printf("gapchain-orbit: %s after %d Newton iterations, residual %.2g\n",
                std::string(to_string(orbit.status)).c_str(), orbit.iterations, orbit.residual);
    if (!orbit.message.empty()) std::printf("  %s\n", orbit.message.c_str());
    char check[96] = "Liouville check not resolved at this period";
    if (!std::isnan(orbit.liouville_error))
        std::snprintf(check, sizeof check, "Liouville check %.1e", orbit.liouville_error);
    // Over many periods a strongly damped orbit's multipliers underflow (Fig 13's, 0.35^1000).
    char modulus[96];
    if (orbit.max_multiplier == 0.0)
        std::snprintf(modulus, sizeof modulus,
                      "below 1e-308 (underflows over %d periods: a shorter --period resolves it)",
                      orbit.period);
    else
        std::snprintf(modulus, sizeof modulus, "%.6g %s", orbit.max_multiplier,
                      cli::plus_minus(orbit.max_multiplier_error, "%.2g").c_str());
    std::printf("  period %d (minimal %d), %s, largest multiplier |mu| = %s (%s)\n", orbit.period,
                orbit.minimal_period,
                orbit.stable                         ? "stable"
                : orbit.max_multiplier <= 1.0 + 1e-9 ? "neutral"
                                                     : "unstable",
                modulus, check);
    std::printf("  F_m over the orbit = %.10g %s\n  wall time %.3f s\n", orbit.F_m,
                cli::plus_minus(orbit.F_m_error, "%.2g").c_str(), orbit.wall_time_s);
}

std::string no_orbit_message(const PeriodicOrbit& orbit, const OrbitOptions& o) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "no orbit of period %d: Newton %s after %d iterations (residual %.2g, asked "
                  "%.2g)%s%s; a longer --from-transient, or another --period, may reach one",
                  o.period, std::string(to_string(orbit.status)).c_str(), orbit.iterations,
                  orbit.residual, o.tolerance, orbit.message.empty() ? "" : ": ",
                  orbit.message.c_str());
    return text;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"A periodic orbit of a row: Newton shooting on the k-period stroboscopic map "
                 "x = P^k(x), started after a transient run; Floquet multipliers from the exact "
                 "tangent flow, the minimal period, and the orbit's F_m.",
                 "gapchain-orbit"};
    OrbitArguments a;
    add_options(app, a);
    return cli::run(app, argc, argv,
                    [&] {
                        cli::require_sets_read(a.scene, "gapchain-orbit", {"run.max_work"},
                                               "its shootings integrate with --scheme to 1e-12");
                        const Scene scene = cli::load(a.scene);
                        require_linear_harmonic(
                            scene, "gapchain-orbit",
                            "the tangent flow assumes a constant Jacobian between switches");
                        const Dynamics dyn = scene.dynamics();
                        a.options.scheme = parse_scheme(a.scheme);
                        a.options.max_work = scene.run.max_work;
                        cli::Outputs outputs({a.scene.path});
                        outputs.required_file(a.out, "--out");
                        cli::Progress progress("gapchain-orbit");
                        const PeriodicOrbit orbit = find_periodic_orbit_after(
                            dyn, a.options, scene.initial, a.transient, progress.callback());
                        cli::throw_if_interrupted();
                        // Multipliers and F_m of a state that is not an orbit mean nothing.
                        if (orbit.status != OrbitStatus::converged)
                            throw cli::NumericalFailure(no_orbit_message(orbit, a.options));
                        write_file_atomically(a.out, to_json(orbit, scene));
                        outputs.keep();
                        print_orbit(orbit);
                    },
                    {{"run.periods", "--from-transient"},
                     {"transient_periods", "--from-transient"},
                     {"period", "--period"},
                     {"max_iterations", "--max-iterations"},
                     {"tolerance", "--tolerance"},
                     {"scheme", "--scheme"}});
}
