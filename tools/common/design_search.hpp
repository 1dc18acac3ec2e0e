#pragma once
// The design-value search a one-point tool adds with --attractors N (gapchain-sim,
// gapchain-classify): its options (--seed, --box, --threads) and its printout, the row's
// attractors set against the one run's F_m.

#include "gapchain/design_value.hpp"
#include "gapchain/scene.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace gapchain::cli {

// --attractors N with its --seed, --box and (unless the tool has its own) --threads.
class DesignSearch {
public:
    // tool names the search in messages ("gapchain-sim --attractors").
    explicit DesignSearch(std::string tool);
    // Adds the options; with_threads false where the tool's own --threads is passed on by
    // set_threads().
    void add_options(CLI::App& app, bool with_threads = true);
    [[nodiscard]] bool wanted() const { return m_options.samples > 0; }
    // Before anything runs: --seed, --box and --threads need --attractors, and the scene must be
    // one the search takes (the paper's uniform row). run: each start's run.
    void check(const Scene& scene, const RunOptions& run);
    // The search's --threads, where the tool's own option gave it (0: all).
    void set_threads(int threads) { m_options.threads = threads; }
    // The options the search runs with (valid once check() has passed).
    [[nodiscard]] const AttractorOptions& options() const { return m_options; }

private:
    std::string m_tool;
    AttractorOptions m_options;
    long long m_seed = 1;
    std::vector<CLI::Option*> m_start_options; // --seed, --box, and --threads if added
};

// The one run the search is set against, for the printout.
struct SearchedRun {
    double F_m = 0.0; // its F_m [reduced force]
    // It finished on the relaxed plan: a run above every attractor may be that plan's motion.
    bool relaxed = false;
    // Its F_m fell before the orbit it settled on (SimulationResult::maximum_in_transient), and
    // its F_m_error already covers the orbit's: above every attractor, but not run_above.
    bool maximum_in_transient = false;
    // What its start reached, for "this run's start reached ..." where an attractor hits
    // harder: a classification whose non-periodic motion the search saw only as a transient,
    // or did not reach, says so.
    std::string reached = "a weaker attractor";
    // Why the run is above every attractor found, where that is not a transient (a stable
    // orbit the search missed); empty: "taken in a transient".
    std::string above_reason;
    // What the tool's user raises to lengthen the runs, the search's starts' too:
    // gapchain-sim's run.periods, gapchain-classify's --record.
    std::string longer_runs = "run.periods";
    // Whether the tool reads run.max_steady_period for the search (gapchain-classify's search
    // tries cycles up to its own max_period, 16).
    bool reads_max_steady_period = true;
};

// The design value's lines: what the search found and how the run's F_m compares.
void print_design(const Scene& scene, const SearchedRun& run, const DesignValue& d,
                  const AttractorOptions& o);

} // namespace gapchain::cli
