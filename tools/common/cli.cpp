#include "cli.hpp"

#include <cstdio>
#include <iostream>
#include <unistd.h>

namespace gapchain::cli {

void add_scene_arguments(CLI::App& app, SceneArguments& args, bool required) {
    auto* opt = app.add_option("scene", args.path, "Scene file (JSON); see README.md");
    if (required) opt->required();
    app.add_option("--set", args.sets, "Override a scene key: section.key=value (repeatable)")
        ->allow_extra_args(false);
}

Scene load(const SceneArguments& args, const std::string& default_scene_json) {
    if (args.path.empty()) return parse_scene(default_scene_json, args.sets, "<built-in>");
    return load_scene(args.path, args.sets);
}

int run(CLI::App& app, int argc, char** argv, const std::function<void()>& body) {
    app.set_version_flag("--version", std::string(GAPCHAIN_VERSION));
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << app.get_name() << ": " << e.what() << " (see --help)\n";
        return static_cast<int>(ExitCode::bad_input);
    }
    try {
        body();
        return static_cast<int>(ExitCode::success);
    } catch (const std::invalid_argument& e) {
        std::cerr << app.get_name() << ": " << e.what() << "\n";
        return static_cast<int>(ExitCode::bad_input);
    } catch (const std::exception& e) {
        std::cerr << app.get_name() << ": " << e.what() << "\n";
        return static_cast<int>(ExitCode::failure);
    }
}

Progress::Progress(std::string label, bool enabled, bool lines_otherwise)
    : m_label(std::move(label)), m_terminal(enabled && ::isatty(STDERR_FILENO) == 1),
      m_lines(enabled && lines_otherwise && !m_terminal), m_start(std::chrono::steady_clock::now()),
      m_last(m_start) {}

Progress::~Progress() {
    if (m_drawn) std::fputs("\n", stderr);
}

bool Progress::update(double fraction) {
    if (!m_terminal && !m_lines) return true;
    const auto now = std::chrono::steady_clock::now();
    const auto every =
        m_terminal ? std::chrono::milliseconds(250) : std::chrono::milliseconds(5000);
    if (fraction < 1.0 && now - m_last < every) return true;
    m_last = now;
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    const double rate = elapsed > 0.0 ? 100.0 * fraction / elapsed : 0.0;
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "%s%s: %5.1f %%  %.2f %%/s  elapsed %.1f s  ETA %.1f s%s",
                 m_terminal ? "\r" : "", m_label.c_str(), 100.0 * fraction, rate, elapsed, eta,
                 m_terminal ? "   " : "\n");
    m_drawn = m_terminal;
    return true;
}

} // namespace gapchain::cli
