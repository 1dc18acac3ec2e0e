#include "plot.hpp"

#include "cli.hpp"

#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <regex>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace gapchain::cli {

namespace fs = std::filesystem;

namespace {

// The PNG files a script writes: its "set output '...'" lines.
std::vector<std::string> outputs_of(const std::string& script) {
    // A quote inside the name is written twice (gnuplot_quoted()): "it's.json"'s figure was
    // looked for as "it" and the run failed (helper-85).
    static const std::regex output(R"(set output '((?:[^']|'')+)')");
    std::vector<std::string> files;
    for (std::sregex_iterator it(script.begin(), script.end(), output), end; it != end; ++it)
        files.push_back(std::regex_replace((*it)[1].str(), std::regex("''"), "'"));
    return files;
}

// gnuplot ends its log with the error itself (after blank lines and the offending command).
std::string last_line_of(const std::string& path) {
    std::ifstream in(path);
    std::string line, last;
    while (std::getline(in, line))
        if (line.find_first_not_of(" \t\r^") != std::string::npos) last = line;
    return last;
}

constexpr int gnuplot_missing = -2;

// Runs gnuplot on `script` (a file name in dir) from dir, its stderr into log, without a shell:
// the folder's name is the user's and may hold any character. Returns waitpid()'s status, -1 if
// it could not be run, or gnuplot_missing.
int run_gnuplot(const fs::path& dir, const std::string& script, const std::string& log) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::string program = "gnuplot";
    std::vector<char*> argv{program.data(), const_cast<char*>(script.c_str()), nullptr};
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned == ENOENT) return gnuplot_missing;
    if (spawned != 0) return -1;
    // A SIGTERM sent to this process alone (a batch system's) does not reach gnuplot, and the
    // handler restarts waitpid(): the wait polls, and passes the signal on.
    int status = 0;
    bool passed_on = false;
    for (;;) {
        const pid_t done = ::waitpid(pid, &status, passed_on ? 0 : WNOHANG);
        if (done == pid) return status;
        if (done == -1 && errno != EINTR) return -1;
        if (!passed_on && interrupted()) {
            ::kill(pid, SIGTERM);
            passed_on = true;
        } else if (!passed_on) {
            ::usleep(10'000);
        }
    }
}

} // namespace

std::string number_text(double x, int digits) {
    char text[40];
    std::snprintf(text, sizeof text, "%.*g", digits, x);
    return text;
}

namespace {

// Removes the figures script draws and the script itself: an interrupted run has none (a
// figure of an earlier run left beside the new numbers would pass for theirs).
void remove_figure(const fs::path& dir, const std::string& script_path, const std::string& script) {
    for (const auto& png : outputs_of(script))
        std::remove((dir / png).c_str());
    std::remove(script_path.c_str());
}

} // namespace

bool plot_with_gnuplot(const std::string& script_path, const std::string& script) {
    const fs::path dir = fs::path(script_path).parent_path().empty()
                             ? fs::path(".")
                             : fs::path(script_path).parent_path();
    // A signal that came while the numbers were written: no figure is started; the numbers
    // are kept (cli::run ends the run as interrupted).
    if (interrupted()) {
        remove_figure(dir, script_path, script);
        return false;
    }
    write_file_atomically(script_path, script);
    // gnuplot's own chatter (font warnings) goes to a log that is shown only if it fails.
    const std::string log = fs::absolute(script_path + ".log." + std::to_string(::getpid()));
    for (const auto& png : outputs_of(script))
        std::remove((dir / png).c_str());
    const int status = run_gnuplot(dir, fs::path(script_path).filename().string(), log);
    const std::string reason = last_line_of(log);
    std::remove(log.c_str());
    // Ctrl-C reaches gnuplot too: the run was interrupted, the figure did not fail (nor is it
    // whole). The script goes with it, as for a run interrupted before its plot step.
    if (interrupted()) {
        remove_figure(dir, script_path, script);
        return false;
    }
    if (status == gnuplot_missing) {
        std::fprintf(stderr,
                     "note: gnuplot not found; the CSV files are complete, run "
                     "'gnuplot %s' to draw the figure\n",
                     shown_path(script_path).c_str());
        return false;
    }
    const bool ran = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
    for (const auto& png : outputs_of(script)) {
        std::error_code ec;
        const auto size = fs::file_size(dir / png, ec);
        if (!ran || ec || size == 0) {
            std::remove((dir / png).c_str());
            throw OutputError(shown_path((dir / png).string()) +
                              ": gnuplot could not write the figure" +
                              (reason.empty() ? std::string() : ": " + reason) +
                              "; --no-plot writes the CSV files without it");
        }
    }
    return true;
}

namespace {

// A template value as it goes between a template's single quotes: a quote written twice. A
// control character would end the gnuplot command and start another one from the rest (a
// newline in an --overlay or --out path ran `system(...)`, a hostile probe, helper-85): the
// tools refuse such paths up front (refuse_control_characters()), and none reaches a script.
std::string gnuplot_quoted(const std::string& value, const std::string& key) {
    std::string quoted;
    for (const char c : value) {
        if (is_control_character(c))
            throw std::invalid_argument(key + ": a control character cannot go into a gnuplot "
                                              "script");
        quoted += c == '\'' ? std::string("''") : std::string(1, c);
    }
    return quoted;
}

} // namespace

std::string plot_script(const std::string& name,
                        const std::vector<std::pair<std::string, std::string>>& values) {
    std::vector<fs::path> dirs;
    if (const char* env = std::getenv("GAPCHAIN_PLOT_DIR")) dirs.emplace_back(env);
    dirs.emplace_back(GAPCHAIN_SOURCE_PLOT_DIR);
    dirs.emplace_back(GAPCHAIN_INSTALL_PLOT_DIR);
    for (const auto& dir : dirs) {
        std::ifstream in(dir / (name + ".gp"));
        if (!in) continue;
        std::ostringstream text;
        text << in.rdbuf();
        std::string script = text.str();
        for (const auto& [key, raw] : values) {
            const std::string value = gnuplot_quoted(raw, key);
            for (auto at = script.find("@" + key + "@"); at != std::string::npos;
                 at = script.find("@" + key + "@", at + value.size()))
                script.replace(at, key.size() + 2, value);
        }
        return script;
    }
    throw std::runtime_error(name + ".gp: plot template not found (set GAPCHAIN_PLOT_DIR to the "
                                    "folder data/plot of gapchain)");
}

bool plot_template(const std::string& folder, const std::string& name,
                   const std::vector<std::pair<std::string, std::string>>& values) {
    return plot_with_gnuplot((fs::path(folder) / (name + ".gp")).string(),
                             plot_script(name, values));
}

} // namespace gapchain::cli
