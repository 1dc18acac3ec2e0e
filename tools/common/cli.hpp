#pragma once
// What every gapchain tool shares: the scene options, the mapping of errors to exit codes,
// and progress on stderr. Exit codes: 0 success, 2 bad input, 1 numerical or internal failure.

#include "gapchain/attractors.hpp"
#include "gapchain/output_file.hpp"
#include "gapchain/scene.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace gapchain::cli {

enum class ExitCode : int { success = 0, failure = 1, bad_input = 2 };

// A numerical outcome that makes the tool's answer unusable (exit 1, message on stderr).
class NumericalFailure : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// SIGINT or SIGTERM arrived: the run was cancelled cleanly (exit 128 + signal). kept: what the
// run had finished and kept in its outputs before it stopped, for the message (empty: nothing).
class Interrupted : public std::runtime_error {
public:
    explicit Interrupted(int signal, std::string kept = "");
    int signal;
    std::string kept;
};

// Whether SIGINT or SIGTERM has arrived (cli::run installs the handlers; the first signal sets
// this flag so that long runs cancel through their progress callback and clean up; a second
// one ends the process at once).
bool interrupted();
// Throws Interrupted if a signal has arrived; kept says what the run finished and kept in its
// outputs before it (an interrupted line or diagram keeps the values it has done).
void throw_if_interrupted(const std::string& kept = "");

// While one lives, the first SIGINT or SIGTERM ends the process at once, as a second one does
// (its temporaries removed, no output kept): for a library call that takes no progress
// callback and so cannot be cancelled (an eigensolver), before the run has written anything.
// Throws Interrupted if a signal came before.
class Uninterruptible {
public:
    Uninterruptible();
    ~Uninterruptible();
    Uninterruptible(const Uninterruptible&) = delete;
    Uninterruptible& operator=(const Uninterruptible&) = delete;
};

// The output paths of one tool run. Every path is checked when it is added, before anything
// runs: its folder must exist (or be creatable) and be writable, it must not be an input file
// or another output. Folders are created by create_folders(), each with a staging folder the
// run writes into (staged()); keep() moves the staged files into place. If the run does not
// reach keep(), the staging folders and the folders it created are removed again, and a folder
// that existed keeps its previous content.
// The name of the staging folders Outputs makes inside an output folder (then a process id).
inline constexpr std::string_view staging_prefix = ".gapchain-staging.";

// A path, or a message naming paths, as the user knows them: staging folder components dropped.
std::string shown_path(const std::string& text);

// A byte below 0x20 or DEL: a newline, a tab, an escape (the one test of the messages, the
// paths and the plot scripts).
inline bool is_control_character(char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
}

// Throws std::invalid_argument naming flag where path holds a control character (a newline,
// a tab, ...): such a path cannot be written into the gnuplot scripts the tools run, and is
// refused before any work.
void refuse_control_characters(const std::string& path, const std::string& flag);

class Outputs {
public:
    // inputs: the files the run reads (scene, study), never to be overwritten.
    explicit Outputs(std::vector<std::string> inputs);
    ~Outputs();
    Outputs(const Outputs&) = delete;
    Outputs& operator=(const Outputs&) = delete;
    // A file output given by flag (for messages); empty paths are ignored. Refused: a folder, a
    // path whose folder does not exist, and anything but a regular file at the path (a device,
    // a pipe, a symbolic link: the atomic write would replace it by a file).
    void file(const std::string& path, const std::string& flag);
    // The same for an output the tool always writes: an empty path is refused too.
    void required_file(const std::string& path, const std::string& flag);
    // A file output about to be written in place before the run is over (a plot reads it):
    // whatever is at the path is set aside, and put back (the new file removed) if the run then
    // fails or a second signal ends it, so that the path is left as it was; keep() drops what
    // was set aside (SetAsideFile).
    void replacing(const std::string& path);
    // A folder output given by flag. owned: every file name the tool may write there, in any
    // of its modes; keep() removes those this run did not write that an earlier run wrote (it
    // lists what it placed in the folder's .gapchain-outputs), so that no file of an earlier run
    // (a basin slice next to a new attractor list) passes for this run's, and a user's own file
    // of such a name is left alone.
    void folder(const std::string& path, const std::string& flag, std::vector<std::string> owned);
    // Creates the folders not there yet (remembered for removal on failure) and their staging
    // folders.
    void create_folders();
    // The folder a run writes folder `path`'s files into (after create_folders()).
    [[nodiscard]] std::string staged(const std::string& path) const;
    // The run succeeded: staged files replace the folders' ones, owned files an earlier run
    // wrote and this one did not are removed, nothing else is. Throws OutputError if a file
    // cannot be moved.
    void keep();

private:
    struct FolderOutput {
        std::string path;
        std::string flag;
        std::vector<std::string> owned;
        std::string staging; // empty until create_folders()
    };
    void check_distinct(const std::string& path, const std::string& flag);
    std::vector<std::string> m_inputs;
    std::vector<std::pair<std::string, std::string>> m_paths; // path, flag
    std::vector<FolderOutput> m_folders;
    std::vector<std::string> m_created;
    std::vector<SetAsideFile> m_replaced;
    bool m_kept = false;
};

// The scene argument and --set overrides every scene-reading tool takes.
struct SceneArguments {
    std::string path;              // empty: the tool's built-in default scene
    std::vector<std::string> sets; // "section.key=value"
    CLI::Option* option = nullptr; // the SCENE option, to tell "" from absent
};

// Adds SCENE (positional, required unless a default exists) and --set to app.
void add_scene_arguments(CLI::App& app, SceneArguments& args, bool required);

// Loads args.path (or parses default_scene_json when the path is empty) with the overrides.
Scene load(const SceneArguments& args, const std::string& default_scene_json = "{}");

// CLI11 check: a finite number > 0 (CLI::PositiveNumber prints the whole double range).
CLI::Validator positive_number();
// An output path that is not empty: "" would write nothing, and say so nowhere.
CLI::Validator non_empty_path();

// CLI11 check: a number (an integer when `integer`) in [lo, hi], the bounds written as %g
// (CLI::Range writes 1e-9 as 0.000000) and a non-number called one.
CLI::Validator number_range(double lo, double hi, bool integer);

// number_range for the option's type: range(1, 100) takes integers, range(1e-9, 100.0) reals.
template <class T>
CLI::Validator range(T lo, T hi) {
    return number_range(static_cast<double>(lo), static_cast<double>(hi), std::is_integral_v<T>);
}

// The items of a comma-separated list option (each value given, split at its commas), each
// passing `check` (none: any). CLI11's own delimiter dropped empty items: "--schemes rk4," ran
// rk4 alone and "--tolerances 1e-4,,1e-5" two tolerances, without a word. An empty item is
// refused, naming the flag.
std::vector<std::string> list_items(const std::string& flag, const std::vector<std::string>& values,
                                    CLI::Validator check = {});

// --seed and --box of an attractor search's random starts (gapchain-attractors, and
// gapchain-sim --attractors), the box around `center` (what its help calls the center);
// returns the two options.
std::pair<CLI::Option*, CLI::Option*> add_start_box(CLI::App& app, long long& seed, double& box,
                                                    const std::string& center);

// Tools that vary one reduced number themselves (bifurcation, continue, attractors --param)
// refuse a --set of it, or of the physical key behind it alone (excitation.f, model.e, model.Kc,
// model.C), which their --from ... --to would silently replace. param: f_r, e_r, fc or eps;
// over: how the tool varies it (classify --map: "over --e_r").
void require_not_set(const SceneArguments& args, const std::string& param, const std::string& tool,
                     const std::string& over = "from --from to --to");
// Why a once-through tool (gapchain::once_through_run_keys) reads no other run key.
inline const std::string plain_run_reason =
    "it runs every period strict, with no steady-state stop, error estimate or start check, "
    "and writes no trajectory";
// Refuses a --set of a run.* or output.* key that the tool does not read, which it would
// silently ignore: read lists the keys it does read ("run." for every run key), unread the
// keys under such a prefix that it sets itself, instead says how the tool runs ("its runs are
// set by --transient and --record").
void require_sets_read(const SceneArguments& args, const std::string& tool,
                       const std::vector<std::string>& read, const std::string& instead,
                       const std::vector<std::string>& unread = {});

// Refuses a --set of a scene key outside the run and output sections that tool does not read
// (unread(dotted key) true): SceneError "--set KEY: TOOL does not read it (WHY); drop the --set".
void refuse_unread_sets(const SceneArguments& args, const std::string& tool,
                        const std::function<bool(const std::string&)>& unread,
                        const std::string& why);

// How long the transients before the periodic attractors last (gapchain-attractors and
// gapchain-sim --attractors), and what a run must discard for the attractors' F_m; nothing
// where fewer than 10 end beyond the median. longer_runs: what the user raises to lengthen the
// runs where too few transients ended ("run.periods", classify's "--record").
void print_transients(const TransientLifetime& t, const std::string& longer_runs = "run.periods");

// "2 attractor(s)", or "0 attractor(s) and 12 unsettled group(s)": an unsettled group is a
// transient's, not an attractor (gapchain-attractors and gapchain-sim --attractors).
std::string attractor_count(const AttractorSet& set);

// The row's reduced numbers for a figure's title ("Nm=5 fc=60 eps=0.5 e_r=0.06 f_r=3"), without
// the swept one (its values are on the x axis).
std::string row_title(const ReducedParameters& p, const std::string& swept = "");

/// "+- <error>" in printf format (e.g. "%.2g"), or "(error not estimated)" for a NaN error.
std::string plus_minus(double error, const char* format);

// The library names its own fields in messages ("segment_length: ..."); a tool lists, for
// each, the flag the user wrote ({"segment_length", "--segment"}) so that messages name it.
// Fields most tools share ("transient_periods" -> "--transient", "tolerance", "threads", ...)
// are translated by cli::run without a list. A listed field in parentheses anywhere in a
// message, advice on what to change ("fewer periods (run.periods)"), is translated too; an
// entry written in parentheses ({"(excitation.f_r)", "(--from)"}) is replaced only there.
using FlagNames = std::vector<std::pair<std::string, std::string>>;

// Parses the command line and runs body, mapping every error to one line on stderr and an exit
// code: CLI11 and SceneError/std::invalid_argument -> 2, NumericalFailure, OutputError and
// others -> 1, SIGINT/SIGTERM -> 130/143. A message that starts with a library field of
// flag_names starts with its flag instead.
int run(CLI::App& app, int argc, char** argv, const std::function<void()>& body,
        const FlagNames& flag_names = {});

// Progress with rate and ETA on stderr: redrawn in place when stderr is a terminal; when it is
// not, silent, or (lines_otherwise) a plain line every few seconds. callback() is the
// library's ProgressCallback.
class Progress {
public:
    Progress(std::string label, bool enabled = true, bool lines_otherwise = false);
    ~Progress();
    // Reports a fraction in [0, 1]; returns false (cancel) once SIGINT or SIGTERM arrived.
    bool update(double fraction);
    std::function<bool(double)> callback() {
        return [this](double f) { return update(f); };
    }
    // A line on stderr that stays (a part of the run done, as it is done), drawn above the
    // progress line on a terminal, written at once whatever stderr is.
    void note(const std::string& line);

private:
    std::string m_label;
    bool m_terminal;
    bool m_lines;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_last;
    bool m_drawn = false;
    bool m_end_drawn = false; ///< the last line drawn was at fraction 1
};

} // namespace gapchain::cli
