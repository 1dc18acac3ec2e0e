#pragma once
// The optional plot step: a tool writes its CSV, then a gnuplot script next to it, and runs
// gnuplot if it is installed. The numbers never depend on it.

#include <string>
#include <utility>
#include <vector>

namespace gapchain::cli {

// Writes script to script_path (atomically) and runs gnuplot on it from its folder.
// Returns false, with a one-line note on stderr, if gnuplot is missing; throws OutputError
// (exit 1) if it fails or leaves an empty figure, which is then removed. Its warnings are shown
// only when it fails. Interrupted (SIGINT, SIGTERM) before or while it runs: returns false and
// leaves no figure and no script (the run's numbers are done and kept; cli::run ends it as
// interrupted).
bool plot_with_gnuplot(const std::string& script_path, const std::string& script);

// The gnuplot template data/plot/<name>.gp with every @KEY@ replaced by its value. Templates
// are looked up in $GAPCHAIN_PLOT_DIR, then the source tree the tool was built from, then the
// install prefix (share/gapchain/plot). Throws std::runtime_error if none is found.
std::string plot_script(const std::string& name,
                        const std::vector<std::pair<std::string, std::string>>& values);

// x with `digits` significant digits (17: reads back as the same double), for template values
// and messages: std::to_string's six decimals wrote 1e-8 as 0.000000.
std::string number_text(double x, int digits = 17);

// Fills template `name` and plots it into folder (the script is kept there as name.gp).
bool plot_template(const std::string& folder, const std::string& name,
                   const std::vector<std::pair<std::string, std::string>>& values);

} // namespace gapchain::cli
