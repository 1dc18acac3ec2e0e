#include "plot.hpp"

#include "gapchain/report.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace gapchain::cli {

bool plot_with_gnuplot(const std::string& script_path, const std::string& script) {
    write_file_atomically(script_path, script);
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
        std::fprintf(stderr,
                     "note: gnuplot not found; the CSV files are complete, run "
                     "'gnuplot %s' to draw the figure\n",
                     script_path.c_str());
        return false;
    }
    const auto dir = std::filesystem::path(script_path).parent_path();
    const std::string command = "cd '" + (dir.empty() ? std::string(".") : dir.string()) +
                                "' && gnuplot '" +
                                std::filesystem::path(script_path).filename().string() + "'";
    if (std::system(command.c_str()) != 0) {
        std::fprintf(stderr, "note: gnuplot failed on %s; the CSV files are complete\n",
                     script_path.c_str());
        return false;
    }
    return true;
}

} // namespace gapchain::cli
