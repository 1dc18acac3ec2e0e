#include "design_search.hpp"

#include "cli.hpp"

#include "gapchain/report.hpp"

#include <cstdio>

namespace gapchain::cli {

DesignSearch::DesignSearch(std::string tool) : m_tool(std::move(tool)) {
    m_options.samples = 0;
}

void DesignSearch::add_options(CLI::App& app, bool with_threads) {
    app.add_option("--attractors", m_options.samples,
                   "Also search the row's attractors from N random starts "
                   "(gapchain-attractors' search) and report the design value F_m_max over "
                   "them and this run (0: no search)")
        ->check(range(0L, 10'000'000L))
        ->capture_default_str();
    const auto [seed_option, box_option] = add_start_box(app, m_seed, m_options.box, "rest");
    m_start_options = {seed_option, box_option};
    if (with_threads)
        m_start_options.push_back(app.add_option("--threads", m_options.threads,
                                                 "OpenMP threads of the attractor search (0: all)")
                                      ->check(range(0, 4096))
                                      ->capture_default_str());
}

void DesignSearch::check(const Scene& scene, const RunOptions& run) {
    if (!wanted()) {
        for (const CLI::Option* option : m_start_options)
            if (option->count() > 0)
                throw SceneError(option->get_name() +
                                 ": applies to the attractor search only; add --attractors "
                                 "N (1 .. 1e7 starts)");
        return;
    }
    require_paper_row(scene, m_tool);
    m_options.seed = static_cast<std::uint64_t>(m_seed);
    m_options.run = run;
    validate(scene.reduced, m_options);
}

namespace {

// The attractor that gives the search's F_m_max: its label, period and basin.
void describe(const Attractor& a) {
    std::printf("%s", std::string(regime_label(a)).c_str());
    if (a.period > 0) std::printf(", period %d", a.period);
    std::printf(", basin %.3f +- %.3f", a.basin_fraction, a.basin_fraction_error);
}

} // namespace

namespace {

// The rest of the design line where the run's own F_m is the design value: above every attractor
// found (run_above), taken in the transient before its own orbit, or no attractor hits harder.
void print_run_as_design(const SearchedRun& run, const DesignValue& d, const Attractor& a) {
    const AttractorSet& set = d.search;
    if (d.run_above) {
        std::printf("this run's F_m; it is above every attractor found (the largest: F_m = %.6g "
                    "+- %.2g, ",
                    set.F_m_max, set.F_m_max_error);
        describe(a);
        if (!run.above_reason.empty())
            std::printf(")\n%s\n", run.above_reason.c_str());
        else
            std::printf(")\nmultistable: this run's F_m was taken in a transient%s, not on an "
                        "attractor\n",
                        run.relaxed ? ", or on the relaxed plan's motion, which the strict "
                                      "dynamics leave (run.accuracy_mode = \"strict\")"
                                    : "");
    } else if (run.maximum_in_transient && set.F_m_max < run.F_m) {
        // A helper's probe (helper-82): a start overlapping a contact took F_m = 1.70 at t = 0
        // where the one attractor reaches 0.39, and the line said only "no attractor found hits
        // harder".
        std::printf("this run's F_m, taken in its transient before the orbit (the largest "
                    "attractor's: F_m = %.6g +- %.2g, ",
                    set.F_m_max, set.F_m_max_error);
        describe(a);
        std::printf(")\n");
    } else {
        std::printf("this run's F_m (no attractor found hits harder)\n");
    }
}

// The rest of the design line where an attractor's F_m is the design value.
void print_attractor_as_design(const Scene& scene, const SearchedRun& run, const DesignValue& d,
                               const Attractor& a) {
    std::printf("F_m_max = %.6g +- %.2g", d.F_m_max, d.F_m_max_error);
    // Beside the run's F_m in newtons, the design value in newtons too (it was only in the
    // JSON's F_m_max_newton).
    if (scene.physical)
        std::printf("  (%.6g N +- %.2g N)", force_in_newtons(d.F_m_max, *scene.physical),
                    force_in_newtons(d.F_m_max_error, *scene.physical));
    std::printf(" (");
    describe(a);
    if (d.start_below)
        std::printf(")\nmultistable: this run's start reached %s, its F_m is %.0f %% below "
                    "the design value; gapchain-attractors shows the basins\n",
                    run.reached.c_str(), 100.0 * (d.F_m_max - run.F_m) / d.F_m_max);
    else if (!d.search.any_settled())
        std::printf("): no group settled, so this is a transient's F_m, above this run's "
                    "%.6g\n",
                    run.F_m);
    else
        std::printf("), this run's F_m within the errors\n");
}

} // namespace

void print_design(const Scene& scene, const SearchedRun& run, const DesignValue& d,
                  const AttractorOptions& o) {
    const AttractorSet& set = d.search;
    // The run starts at the scene's initial state; the search's box stays around rest.
    std::printf("design value over %s from %ld starts%s (%.2f s): ", attractor_count(set).c_str(),
                o.samples, scene.initial.empty() ? "" : " around rest", set.wall_time_s);
    if (set.F_m_max_id < 0) {
        std::printf("no attractor found (every start failed)\n");
        return;
    }
    const Attractor& a = set.attractors[static_cast<std::size_t>(set.F_m_max_id)];
    if (d.run_above || d.from_run)
        print_run_as_design(run, d, a);
    else
        print_attractor_as_design(scene, run, d, a);
    print_transients(set.transients, run.longer_runs);
    if (set.unsettled > 0) {
        std::printf("  %d group(s) were still converging when their runs ended: their F_m is a "
                    "transient's; raise %s",
                    set.unsettled, run.longer_runs.c_str());
        if (run.reads_max_steady_period)
            std::printf(", or run.max_steady_period (now %d) if their orbits may be longer",
                        o.run.max_steady_period);
        std::printf("\n");
    }
}

} // namespace gapchain::cli
