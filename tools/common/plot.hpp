#pragma once
// The optional plot step: a tool writes its CSV, then a gnuplot script next to it, and runs
// gnuplot if it is installed. The numbers never depend on it.

#include <string>

namespace gapchain::cli {

// Writes script to script_path (atomically) and runs gnuplot on it from its folder.
// Returns false, with a one-line note on stderr, if gnuplot is missing or fails.
bool plot_with_gnuplot(const std::string& script_path, const std::string& script);

} // namespace gapchain::cli
