#pragma once
// What every gapchain tool shares: the scene options, the mapping of errors to exit codes,
// and progress on stderr. Exit codes: 0 success, 2 bad input, 1 numerical or internal failure.

#include "gapchain/scene.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace gapchain::cli {

enum class ExitCode : int { success = 0, failure = 1, bad_input = 2 };

// A numerical outcome that makes the tool's answer unusable (exit 1, message on stderr).
class NumericalFailure : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The scene argument and --set overrides every scene-reading tool takes.
struct SceneArguments {
    std::string path;              // empty: the tool's built-in default scene
    std::vector<std::string> sets; // "section.key=value"
};

// Adds SCENE (positional, required unless a default exists) and --set to app.
void add_scene_arguments(CLI::App& app, SceneArguments& args, bool required);

// Loads args.path (or parses default_scene_json when the path is empty) with the overrides.
Scene load(const SceneArguments& args, const std::string& default_scene_json = "{}");

// Parses the command line and runs body, mapping every error to one line on stderr and an exit
// code: CLI11 and SceneError/std::invalid_argument -> 2, NumericalFailure and others -> 1.
int run(CLI::App& app, int argc, char** argv, const std::function<void()>& body);

// Progress with rate and ETA on stderr: redrawn in place when stderr is a terminal; when it is
// not, silent, or (lines_otherwise) a plain line every few seconds. callback() is the
// library's ProgressCallback.
class Progress {
public:
    Progress(std::string label, bool enabled = true, bool lines_otherwise = false);
    ~Progress();
    // Reports a fraction in [0, 1]; always returns true (never cancels).
    bool update(double fraction);
    std::function<bool(double)> callback() {
        return [this](double f) { return update(f); };
    }

private:
    std::string m_label;
    bool m_terminal;
    bool m_lines;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_last;
    bool m_drawn = false;
};

} // namespace gapchain::cli
