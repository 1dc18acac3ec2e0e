#include "cli.hpp"

#include "gapchain/report.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <regex>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace gapchain::cli {

namespace {

std::atomic<int> g_signal{0};
// Set while a library call that cannot be cancelled runs (Uninterruptible).
std::atomic<bool> g_uninterruptible{false};

// Installs handler for SIGINT and SIGTERM, each blocking the other while it runs (so that the
// two arriving together are a first and a second, not two firsts). Async-signal-safe.
void handle_signals(void (*handler)(int)) {
    struct sigaction action {};
    action.sa_handler = handler;
    sigemptyset(&action.sa_mask);
    sigaddset(&action.sa_mask, SIGINT);
    sigaddset(&action.sa_mask, SIGTERM);
    action.sa_flags = SA_RESTART;
    ::sigaction(SIGINT, &action, nullptr);
    ::sigaction(SIGTERM, &action, nullptr);
}

// A second signal ends the process at once, its temporaries removed and the files it set aside
// put back (unlink, rename, sigaction and raise are async-signal-safe). A staging folder may
// stay, as after SIGKILL; the next run into its folder removes it.
extern "C" void on_second_signal(int signal) {
    abandon_unfinished_outputs();
    handle_signals(SIG_DFL);
    std::raise(signal);
}

// The first signal cancels through the progress callbacks, and leaves the files being written
// alone: a finished run may be in the middle of writing its outputs, and removing a temporary
// there made the rename fail and lost the run. An OutputFile left uncommitted by the
// cancellation removes its own temporary.
extern "C" void on_signal(int signal) {
    g_signal.store(signal);
    // A call that asks no progress callback would hold the first signal until it is done (a
    // 111 s dense solve, a sparse one of many minutes): it ends the process at once instead.
    if (g_uninterruptible.load()) return on_second_signal(signal);
    handle_signals(on_second_signal);
}

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
    // Made absolute first: weakly_canonical() leaves a path none of whose parts exists relative,
    // so "r.json" and "./r.json" (or a relative and an absolute spelling) compared unequal.
    return fs::weakly_canonical(fs::absolute(a, ec), ec) ==
           fs::weakly_canonical(fs::absolute(b, ec), ec);
}

// The nearest existing ancestor of path must be a directory a file can be created in: tried
// for real with a probe file (access(2) says yes to root everywhere, even in /proc). Messages
// name `shown`, the path the user gave.
void check_writable_parent(const std::string& path, const std::string& flag,
                           const std::string& shown) {
    fs::path dir = fs::absolute(path).parent_path();
    std::error_code ec;
    while (!dir.empty() && !fs::exists(dir, ec) && dir != dir.parent_path())
        dir = dir.parent_path();
    if (!fs::is_directory(dir, ec))
        throw std::invalid_argument(flag + ": " + shown + ": " + dir.string() +
                                    " is not a directory");
    const fs::path probe = dir / (".gapchain-probe." + std::to_string(::getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0)
        throw std::invalid_argument(flag + ": " + shown + ": cannot create files in " +
                                    dir.string() + ": " + std::strerror(errno));
    ::close(fd);
    ::unlink(probe.c_str());
}

} // namespace

Interrupted::Interrupted(int sig, std::string kept_part)
    : std::runtime_error(std::string("interrupted by ") + (sig == SIGTERM ? "SIGTERM" : "SIGINT")),
      signal(sig), kept(std::move(kept_part)) {}

bool interrupted() {
    return g_signal.load() != 0;
}

Uninterruptible::Uninterruptible() {
    // The flag first: a signal between a check and the flag would be held to the solve's end.
    g_uninterruptible.store(true);
    if (interrupted()) {
        g_uninterruptible.store(false);
        throw_if_interrupted();
    }
}

Uninterruptible::~Uninterruptible() {
    g_uninterruptible.store(false);
}

void throw_if_interrupted(const std::string& kept) {
    if (interrupted()) throw Interrupted(g_signal.load(), kept);
}

std::string shown_path(const std::string& text) {
    static const std::regex staging("/\\.gapchain-staging\\.[0-9]+");
    return std::regex_replace(text, staging, "");
}

namespace {

// The staging folders a killed run (kill -9, a crash) left in folder: those whose process is
// gone. A live one belongs to a run still writing there.
void remove_dead_staging(const std::string& folder) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(staging_prefix, 0) != 0) continue;
        const std::string digits = name.substr(staging_prefix.size());
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos ||
            digits.size() > 9)
            continue;
        const auto pid = static_cast<pid_t>(std::stol(digits));
        if (::kill(pid, 0) == -1 && errno == ESRCH) fs::remove_all(entry.path(), ec);
    }
}

} // namespace

Outputs::Outputs(std::vector<std::string> inputs) : m_inputs(std::move(inputs)) {}

namespace {

// Removes the empty folders of the tree at p, then p if it is empty; false if anything is left
// (a file another run wrote into a folder this run created is never removed).
bool remove_empty_tree(const fs::path& p) {
    std::error_code ec;
    if (fs::is_symlink(p, ec) || !fs::is_directory(p, ec)) return false;
    bool empty = true;
    for (const auto& entry : fs::directory_iterator(p, ec))
        empty = remove_empty_tree(entry.path()) && empty;
    return empty && fs::remove(p, ec);
}

} // namespace

Outputs::~Outputs() {
    if (m_kept) return;
    m_replaced.clear(); // each puts its previous file back
    std::error_code ec;
    for (const auto& f : m_folders)
        if (!f.staging.empty()) fs::remove_all(f.staging, ec);
    for (auto it = m_created.rbegin(); it != m_created.rend(); ++it)
        remove_empty_tree(*it);
}

void Outputs::check_distinct(const std::string& path, const std::string& flag) {
    for (const auto& input : m_inputs)
        if (!input.empty() && same_file(path, input))
            throw std::invalid_argument(flag + ": " + path +
                                        " is an input of this run; choose "
                                        "another output path");
    for (const auto& [other, other_flag] : m_paths)
        if (same_file(path, other))
            throw std::invalid_argument(flag + ": " + path + " is also the output of " +
                                        other_flag + "; give each output its own path");
}

void refuse_control_characters(const std::string& path, const std::string& flag) {
    for (const char c : path)
        if (is_control_character(c))
            throw std::invalid_argument(flag + ": the path holds a control character (code " +
                                        std::to_string(static_cast<int>(c)) +
                                        "); give a path of printable characters");
}

void Outputs::file(const std::string& path, const std::string& flag) {
    if (path.empty()) return;
    refuse_control_characters(path, flag);
    std::error_code ec;
    if (fs::is_directory(path, ec))
        throw std::invalid_argument(flag + ": " + path + " is a directory; give a file name");
    if (fs::is_symlink(path, ec))
        throw std::invalid_argument(flag + ": " + path + " is a symbolic link (to " +
                                    fs::read_symlink(path, ec).string() +
                                    "), which the write would replace; give the file itself");
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
        throw std::invalid_argument(flag + ": " + path +
                                    " exists and is not a regular file (a device, pipe or "
                                    "socket), which the write would replace; give a file name");
    const fs::path folder = fs::absolute(path).parent_path();
    if (!fs::is_directory(folder, ec))
        throw std::invalid_argument(flag + ": " + path + ": " +
                                    (fs::exists(folder, ec)
                                         ? folder.string() + " is not a directory"
                                         : "the folder " + folder.string() + " does not exist"));
    check_distinct(path, flag);
    check_writable_parent(path, flag, path);
    m_paths.emplace_back(path, flag);
}

void Outputs::required_file(const std::string& path, const std::string& flag) {
    if (path.empty()) throw std::invalid_argument(flag + ": must name a file");
    file(path, flag);
}

void Outputs::folder(const std::string& path, const std::string& flag,
                     std::vector<std::string> owned) {
    if (path.empty()) throw std::invalid_argument(flag + ": must name a folder");
    refuse_control_characters(path, flag);
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_directory(path, ec))
        throw std::invalid_argument(flag + ": " + path + " exists and is not a folder");
    if (fs::is_symlink(path, ec) && !fs::exists(path, ec))
        throw std::invalid_argument(flag + ": " + path + " is a symbolic link to nothing");
    check_distinct(path, flag);
    // A scene kept in the output folder under a name the tool writes would be replaced or
    // removed by keep().
    for (const auto& name : owned)
        for (const auto& input : m_inputs)
            if (!input.empty() && same_file((fs::path(path) / name).string(), input))
                throw std::invalid_argument(flag + ": " + (fs::path(path) / name).string() +
                                            " is an input of this run and a file this tool "
                                            "writes there; choose another output folder");
    // A folder where the tool writes a file would fail the run only once its work is done.
    for (const auto& name : owned)
        if (fs::is_directory(fs::symlink_status(fs::path(path) / name, ec)))
            throw std::invalid_argument(flag + ": " + (fs::path(path) / name).string() +
                                        " is a folder named like a file this tool may write "
                                        "there; move it or choose another output folder");
    // An existing folder must take new files itself: a file in it is checked.
    check_writable_parent(fs::is_directory(path, ec) ? (fs::path(path) / "x").string() : path, flag,
                          path);
    m_paths.emplace_back(path, flag);
    m_folders.push_back({path, flag, std::move(owned), {}});
}

void Outputs::create_folders() {
    for (auto& folder : m_folders) {
        // Remember the outermost folder this run creates, so that a failure removes it all.
        fs::path first_new;
        for (fs::path p = fs::absolute(folder.path); !p.empty() && p != p.parent_path();
             p = p.parent_path()) {
            std::error_code ec;
            if (fs::exists(p, ec)) break;
            first_new = p;
        }
        std::error_code ec;
        fs::create_directories(folder.path, ec);
        if (ec)
            throw OutputError(folder.flag + ": " + folder.path +
                              ": cannot create the folder: " + ec.message());
        if (!first_new.empty()) m_created.push_back(first_new.string());
        remove_dead_staging(folder.path);
        // Inside the folder, so that keep()'s renames stay on one file system.
        folder.staging =
            (fs::path(folder.path) / (std::string(staging_prefix) + std::to_string(::getpid())))
                .string();
        fs::create_directories(folder.staging, ec);
        if (ec)
            throw OutputError(folder.flag + ": " + folder.path +
                              ": cannot write in the folder: " + ec.message());
    }
}

std::string Outputs::staged(const std::string& path) const {
    for (const auto& f : m_folders)
        if (f.path == path && !f.staging.empty()) return f.staging;
    throw std::logic_error("Outputs::staged: " + path + " is not a created output folder");
}

namespace {

// Moves the staged files of one folder into place, all or nothing: the files they replace are
// set aside first, and put back if a step fails (or a second signal ends the run) before the
// returned SetAsideFiles are kept.
std::vector<SetAsideFile> commit_staged(const fs::path& folder, const fs::path& staging) {
    std::error_code ec;
    std::vector<fs::path> staged;
    for (const auto& entry : fs::directory_iterator(staging, ec))
        staged.push_back(entry.path().filename());
    std::vector<SetAsideFile> replaced;
    for (const auto& name : staged) {
        const fs::path target = folder / name;
        if (fs::is_directory(fs::symlink_status(target, ec)))
            throw OutputError(target.string() +
                              ": cannot write: a folder of that name is in the way");
        replaced.emplace_back(target.string());
    }
    for (const auto& name : staged) {
        fs::rename(staging / name, folder / name, ec);
        if (ec) throw OutputError((folder / name).string() + ": cannot write: " + ec.message());
    }
    return replaced;
}

} // namespace

void Outputs::replacing(const std::string& path) {
    m_replaced.emplace_back(path);
}

namespace {

// The names a run placed in an output folder, listed in it (one per line) so that the next run
// removes only files a run wrote, never a user's file that happens to bear an output's name.
constexpr const char* written_list = ".gapchain-outputs";

std::vector<fs::path> read_written_list(const fs::path& folder) {
    std::vector<fs::path> names;
    std::ifstream in(folder / written_list);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) names.emplace_back(line);
    return names;
}

bool listed(const std::vector<fs::path>& names, const fs::path& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

// The owned files an earlier run wrote into folder that this run does not write (staged holds
// what it does): not this run's, to be removed once its files are in place.
std::vector<fs::path> stale_outputs(const fs::path& folder, const fs::path& staging,
                                    const std::vector<std::string>& owned) {
    const std::vector<fs::path> earlier = read_written_list(folder);
    std::vector<fs::path> stale;
    std::error_code ec;
    for (const auto& name : owned)
        if (listed(earlier, name) && !fs::exists(staging / name, ec)) stale.emplace_back(name);
    return stale;
}

// Adds to staging the list of what the folder will hold from runs: the files staged, and those
// an earlier run listed that are still there and not stale (another tool's, into the same
// folder), to be placed with them.
void stage_written_list(const fs::path& folder, const fs::path& staging,
                        const std::vector<fs::path>& stale) {
    std::vector<fs::path> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(staging, ec))
        names.push_back(entry.path().filename());
    for (const auto& name : read_written_list(folder))
        if (!listed(names, name) && !listed(stale, name) && fs::exists(folder / name, ec))
            names.push_back(name);
    std::ofstream out(staging / written_list);
    for (const auto& name : names)
        if (name != written_list) out << name.string() << '\n';
    if (!out.flush()) throw OutputError((staging / written_list).string() + ": cannot write");
}

} // namespace

void Outputs::keep() {
    // Every list is staged before any folder is committed, so that a list that cannot be
    // written leaves every folder as it was.
    std::vector<std::vector<fs::path>> stale(m_folders.size());
    for (std::size_t k = 0; k < m_folders.size(); ++k) {
        const FolderOutput& f = m_folders[k];
        if (f.staging.empty()) continue;
        stale[k] = stale_outputs(f.path, f.staging, f.owned);
        stage_written_list(f.path, f.staging, stale[k]);
    }
    // Every folder is committed before any replaced file is dropped, so that a folder that
    // cannot be written puts the others back too.
    std::vector<SetAsideFile> replaced;
    for (const FolderOutput& f : m_folders)
        if (!f.staging.empty())
            for (auto& file : commit_staged(f.path, f.staging))
                replaced.push_back(std::move(file));
    // Stale files are set aside too, not removed: a second signal before the end puts the
    // whole folder back as it was.
    for (std::size_t k = 0; k < m_folders.size(); ++k)
        for (const auto& name : stale[k])
            replaced.emplace_back((fs::path(m_folders[k].path) / name).string());
    for (FolderOutput& f : m_folders) {
        if (f.staging.empty()) continue;
        std::error_code ec;
        fs::remove_all(f.staging, ec);
        f.staging.clear();
    }
    for (auto& file : replaced)
        file.keep();
    for (auto& file : m_replaced)
        file.keep();
    m_kept = true;
}

void add_scene_arguments(CLI::App& app, SceneArguments& args, bool required) {
    args.option = app.add_option("scene", args.path, "Scene file (JSON); see README.md");
    if (required) args.option->required();
    app.add_option("--set", args.sets, "Override a scene key: section.key=value (repeatable)")
        ->allow_extra_args(false);
}

Scene load(const SceneArguments& args, const std::string& default_scene_json) {
    if (args.path.empty() && args.option && args.option->count() > 0)
        throw SceneError("SCENE: an empty path; give a scene file" +
                         std::string(args.option->get_required()
                                         ? ""
                                         : ", or leave it out for the built-in scene"));
    if (args.path.empty()) return parse_scene(default_scene_json, args.sets, "<built-in>");
    return load_scene(args.path, args.sets);
}

CLI::Validator non_empty_path() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            return text.empty() ? "must be a file path, got an empty one" : std::string{};
        },
        "PATH");
}

CLI::Validator positive_number() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(text.c_str(), &end);
            if (end == text.c_str() || *end != '\0' || !std::isfinite(x) || !(x > 0.0))
                return "must be a finite number > 0, got " + text;
            return {};
        },
        "> 0");
}

CLI::Validator number_range(double lo, double hi, bool integer) {
    char bounds[64];
    std::snprintf(bounds, sizeof bounds, integer ? "%.0f to %.0f" : "%g to %g", lo, hi);
    const std::string range = bounds;
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            // Integers are read as CLI11 stores them (base 0: 0x1e is 30, 017 is 15), so the
            // value checked is the value the option gets.
            char* end = nullptr;
            errno = 0;
            const bool negative = text.find('-') != std::string::npos;
            // long double holds every 64-bit integer exactly (x86-64): as a double, 2^62 + 1
            // rounded to 2^62 and passed a bound of 2^62.
            const long double x =
                integer
                    ? (negative ? static_cast<long double>(std::strtoll(text.c_str(), &end, 0))
                                : static_cast<long double>(std::strtoull(text.c_str(), &end, 0)))
                    : static_cast<long double>(std::strtod(text.c_str(), &end));
            const bool number =
                end != text.c_str() && *end == '\0' && errno != ERANGE && std::isfinite(x);
            if (!number)
                return std::string(integer ? "must be an integer" : "must be a finite number") +
                       " in " + range + ", got \"" + text + "\"";
            if (!(x >= static_cast<long double>(lo) && x <= static_cast<long double>(hi)))
                return "must be in " + range + ", got " + text;
            return {};
        },
        "[" + range + "]");
}

std::vector<std::string> list_items(const std::string& flag, const std::vector<std::string>& values,
                                    CLI::Validator check) {
    std::vector<std::string> items;
    for (const std::string& value : values) {
        std::size_t begin = 0;
        for (int number = 1;; ++number) {
            const std::size_t comma = value.find(',', begin);
            std::string item = value.substr(begin, comma - begin);
            if (item.empty())
                throw std::invalid_argument(flag + ": item " + std::to_string(number) + " of \"" +
                                            value + "\" is empty");
            if (const std::string refusal = check(item); !refusal.empty())
                throw std::invalid_argument(flag + ": " + refusal);
            items.push_back(std::move(item));
            if (comma == std::string::npos) break;
            begin = comma + 1;
        }
    }
    return items;
}

std::string row_title(const ReducedParameters& p, const std::string& swept) {
    std::string title = "Nm=" + std::to_string(p.Nm);
    const std::pair<const char*, double> fields[] = {
        {"fc", p.fc}, {"eps", p.eps}, {"e_r", p.e_r}, {"f_r", p.f_r}};
    for (const auto& [name, value] : fields) {
        if (swept == name) continue;
        char field[64];
        std::snprintf(field, sizeof field, " %s=%g", name, value);
        title += field;
    }
    return title;
}

std::string attractor_count(const AttractorSet& set) {
    // Counting unsettled groups as attractors told a user that a contact-free row at eps = 100
    // (one attractor, its runs too short to reach it) had twelve.
    std::string text = std::to_string(set.attractor_count()) + " attractor(s)";
    if (set.unsettled > 0) text += " and " + std::to_string(set.unsettled) + " unsettled group(s)";
    return text;
}

void print_transients(const TransientLifetime& t, const std::string& longer_runs) {
    if (std::isnan(t.lifetime)) {
        // Saying nothing here read as "no long transients" where most were still going.
        if (!std::isnan(t.from_period) && t.censored > 0)
            std::printf("transients: half last beyond %.0f periods; beyond, %ld ended and %ld were "
                        "still going when their runs ended: too few endings to measure a "
                        "lifetime (raise %s, or the starts)\n",
                        t.from_period, t.ended, t.censored, longer_runs.c_str());
        return;
    }
    std::printf("transients: half last beyond %.0f periods; beyond, lifetime %.3g +- %.2g periods "
                "(%ld ended, %ld still going); ",
                t.from_period, t.lifetime, t.lifetime_error, t.ended, t.censored);
    if (t.constant_rate == ConstantRate::untested) {
        std::printf("too few endings to test whether their rate is constant\n");
        return;
    }
    std::printf("their rate %s (later half over earlier %.2f +- %.2f)\n",
                t.constant_rate == ConstantRate::consistent
                    ? "is consistent with a constant one, as for an escape from a saddle"
                    : "is not constant: no single exponential escape",
                t.rate_ratio, t.rate_ratio_error);
    if (t.constant_rate == ConstantRate::consistent)
        std::printf("  1 %% of starts are still in their transient after about %.0f periods: a run "
                    "discarding that many (run.transient_periods) reports an attractor's F_m\n",
                    t.periods_until(0.01));
}

std::string plus_minus(double error, const char* format) {
    if (std::isnan(error)) return "(error not estimated)";
    char number[64];
    std::snprintf(number, sizeof number, format, error);
    return std::string("+- ") + number;
}

std::pair<CLI::Option*, CLI::Option*> add_start_box(CLI::App& app, long long& seed, double& box,
                                                    const std::string& center) {
    CLI::Option* s = app.add_option("--seed", seed, "Seed of the random starts")
                         ->check(range(0LL, 1LL << 62))
                         ->capture_default_str();
    CLI::Option* b = app.add_option("--box", box,
                                    "Half-width of the box of starts around " + center +
                                        ", in units of the contact-free amplitude A of eq (20) "
                                        "(u within box A of it, v within box 2 pi f_r A)")
                         ->check(range(1e-9, 100.0))
                         ->capture_default_str();
    return {s, b};
}

void require_not_set(const SceneArguments& args, const std::string& param, const std::string& tool,
                     const std::string& over) {
    for (const std::string& key : keys_replaced_by(parse_swept_parameter(param)))
        for (const std::string& set : args.sets)
            if (set.rfind(key + "=", 0) == 0)
                throw SceneError("--set " + key + ": " + tool + " varies " + param + " itself, " +
                                 over + "; drop the --set");
}

namespace {

// "a", "a and b", "a, b and c".
std::string join_words(const std::vector<std::string>& words) {
    std::string joined;
    for (std::size_t k = 0; k < words.size(); ++k)
        joined += (k == 0 ? "" : k + 1 == words.size() ? " and " : ", ") + words[k];
    return joined;
}

} // namespace

void require_sets_read(const SceneArguments& args, const std::string& tool,
                       const std::vector<std::string>& read, const std::string& instead,
                       const std::vector<std::string>& unread) {
    for (const std::string& set : args.sets) {
        const std::string key = set.substr(0, set.find('='));
        if (key.rfind("run.", 0) != 0 && key.rfind("output.", 0) != 0) continue;
        const bool is_read = std::find(unread.begin(), unread.end(), key) == unread.end() &&
                             std::any_of(read.begin(), read.end(), [&](const std::string& r) {
                                 return r.back() == '.' ? key.rfind(r, 0) == 0 : key == r;
                             });
        if (is_read) continue;
        std::vector<std::string> named;
        for (const std::string& r : read)
            named.push_back(r != "run."      ? r
                            : unread.empty() ? std::string("the run section")
                                             : "the run section except " + join_words(unread));
        const std::string reads = join_words(named);
        throw SceneError(
            "--set " + key + ": " + tool + " does not read it (" +
            (reads.empty() ? std::string("it reads no run or output key") : "it reads " + reads) +
            "; " + instead + "); drop the --set");
    }
}

void refuse_unread_sets(const SceneArguments& args, const std::string& tool,
                        const std::function<bool(const std::string&)>& unread,
                        const std::string& why) {
    const auto refuse = [&](const std::string& key) {
        if (unread(key))
            throw SceneError("--set " + key + ": " + tool + " does not read it (" + why +
                             "); drop the --set");
    };
    for (const std::string& set : args.sets) {
        const std::size_t eq = set.find('=');
        const std::string key = set.substr(0, eq);
        refuse(key);
        // An object sets its members: 'model.scatter={"clearance":0.5}' was taken and ignored
        // where model.scatter.clearance=0.5 is refused (a hostile probe, helper-85).
        if (eq == std::string::npos) continue;
        const auto value = nlohmann::json::parse(set.substr(eq + 1), nullptr, false);
        if (value.is_object())
            for (const auto& member : value.items())
                refuse(key + "." + member.key());
    }
}

namespace {

// The library's option fields and the flags most tools give them; a tool's own list wins.
const FlagNames common_flag_names = {
    {"steps", "--steps"},
    {"transient_periods", "--transient"},
    {"record_periods", "--record"},
    {"max_period", "--max-period"},
    {"period_tolerance", "--period-tolerance"},
    {"threads", "--threads"},
    {"tolerance", "--tolerance"},
    {"count", "--count"},
    {"method", "--method"},
    {"window", "--window"},
    {"periods", "--periods"},
    {"repeats", "--repeats"},
    {"tolerances", "--tolerances"},
    {"schemes", "--schemes"},
    {"shard_count", "--shard"},
    {"shard", "--shard"},
    {"from", "--from"},
    {"to", "--to"},
};

std::string with_flag_names(std::string message, const FlagNames& names) {
    // A field in parentheses is advice on what to change ("fewer periods (run.periods)"):
    // gapchain-orbit, whose runs take their periods from --from-transient, advised run.periods,
    // a key it does not read.
    // An entry written in parentheses itself is replaced as written.
    for (const auto& [field, flag] : names) {
        const bool literal = field.front() == '(';
        const std::string from = literal ? field : '(' + field + ')';
        const std::string to = literal ? flag : '(' + flag + ')';
        for (auto at = message.find(from); at != std::string::npos;
             at = message.find(from, at + to.size()))
            message.replace(at, from.size(), to);
    }
    for (const FlagNames* list : {&names, &common_flag_names})
        for (const auto& [field, flag] : *list)
            if (message.rfind(field + ":", 0) == 0) return flag + message.substr(field.size());
    return message;
}

} // namespace

namespace {

/// A message as one readable line: a 50,000-digit --seed was echoed whole (50 KB of stderr).
std::string readable(const std::string& message) {
    static const std::regex flag_value("^(\\S+) was given a disallowed flag override$");
    std::smatch flag;
    if (std::regex_match(message, flag, flag_value))
        return "--" + flag[1].str() + ": a flag takes no value (give --" + flag[1].str() +
               " alone, or leave it out)";
    // CLI11's words for an option given more often than it takes ("--from: At Most 1 required
    // but received 2", a reviewer's probe, helper-75).
    static const std::regex repeated("^(\\S+): At Most (\\d+) required but received (\\d+)$");
    std::smatch times;
    if (std::regex_match(message, times, repeated))
        return times[1].str() + ": given " + times[3].str() + " times, at most " + times[2].str() +
               " allowed";
    // A newline in a user's text (a file name, a --variable) split the message over lines. Each
    // piece is one escape or one whole UTF-8 character, so that shortening a long message cuts
    // between pieces, never inside "\\x1b" or a multi-byte letter.
    std::vector<std::string> pieces;
    for (const char c : message) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '\n')
            pieces.emplace_back("\\n");
        else if (c == '\r')
            pieces.emplace_back("\\r");
        else if (c == '\t')
            pieces.emplace_back("\\t");
        else if (is_control_character(c)) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
            pieces.emplace_back(escaped);
        } else if ((byte & 0xc0) == 0x80 && !pieces.empty())
            pieces.back() += c;
        else
            pieces.emplace_back(1, c);
    }
    const auto joined = [&pieces](std::size_t first, std::size_t last) {
        std::string text;
        for (std::size_t i = first; i < last; ++i)
            text += pieces[i];
        return text;
    };
    const std::string line = joined(0, pieces.size());
    // Long enough for a work refusal with its study point (a sweep's, 430 characters, lost its
    // limit and remedy at 400).
    if (line.size() <= 1000) return line;
    std::size_t head = 0, head_size = 0;
    while (head < pieces.size() && head_size + pieces[head].size() <= 700)
        head_size += pieces[head++].size();
    std::size_t tail = pieces.size(), tail_size = 0;
    while (tail > head && tail_size + pieces[tail - 1].size() <= 200)
        tail_size += pieces[--tail].size();
    return joined(0, head) + " ... " + joined(tail, pieces.size());
}

/// Every number option of app and its subcommands must be written in plain decimal. CLI11 reads
/// integers in base 0 (--samples 0100 ran 64 starts, --seed 010 was seed 8), floats in hex
/// (--from 0x10 was 16), an empty text as 0 (--from '' started a line at 0), and 1e-999 as 0.
void require_decimal_numbers(CLI::App& app) {
    for (CLI::Option* option : app.get_options()) {
        const std::string type = option->get_type_name();
        const bool integer = type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0;
        if (!integer && type.rfind("FLOAT", 0) != 0) continue;
        // nan and inf pass as CLI11 reads them: the range checks name the accepted range.
        option->check(CLI::Validator(
            [integer](std::string& text) {
                return !integer && spells_non_finite(text) ? std::string()
                                                           : number_text_error(text, integer);
            },
            ""));
        // "-0" is 0: kept, it was written "-0" in the CSVs and -0.0 in the JSON. (A transform:
        // a check may not change the text.)
        option->transform(CLI::Validator(
            [integer](std::string& text) {
                if (!text.empty() && text[0] == '-' && number_text_error(text, integer).empty() &&
                    std::strtod(text.c_str(), nullptr) == 0.0)
                    text.erase(0, 1);
                return std::string();
            },
            ""));
    }
    for (CLI::App* sub : app.get_subcommands({}))
        require_decimal_numbers(*sub);
}

// A flag takes no value: CLI11 reads "--no-plot=0" as off and "--no-plot=7" as on (a helper's
// probe, 2026-11-27). Only "=true", the flag's own meaning, stays accepted.
void refuse_flag_values(CLI::App& app) {
    for (CLI::Option* option : app.get_options())
        if (option->get_expected_max() == 0) option->disable_flag_override();
    for (CLI::App* sub : app.get_subcommands({}))
        refuse_flag_values(*sub);
}

/// The message for an argument "--name=" with nothing after the "=", if any: CLI11 reads it as
/// the bare flag ("--no-plot=" ran as --no-plot), and an option then takes the next argument as
/// its value ("--transient= 50" ran with 50, "--out= e.json" wrote e.json). Searched in app and
/// its subcommands.
std::optional<std::string> empty_value_message(CLI::App& app, int argc, char** argv) {
    std::vector<CLI::App*> apps{&app};
    for (CLI::App* sub : app.get_subcommands({}))
        apps.push_back(sub);
    for (int i = 1; i < argc; ++i) {
        const std::string argument = argv[i];
        if (argument == "--") break;
        if (argument.rfind("--", 0) != 0 || argument.empty() || argument.back() != '=') continue;
        const std::string name = argument.substr(0, argument.size() - 1);
        for (CLI::App* a : apps) {
            const CLI::Option* option = a->get_option_no_throw(name);
            if (option == nullptr) continue;
            if (option->get_expected_max() == 0)
                return readable(name.substr(2) + " was given a disallowed flag override");
            return readable(name + ": an empty value (\"" + argument +
                            "\"); give the value after the =, or drop the option");
        }
    }
    return std::nullopt;
}

} // namespace

int run(CLI::App& app, int argc, char** argv, const std::function<void()>& body,
        const FlagNames& flag_names) {
    app.set_version_flag("--version", std::string(GAPCHAIN_VERSION));
    require_decimal_numbers(app);
    refuse_flag_values(app);
    handle_signals(on_signal);
    if (const auto message = empty_value_message(app, argc, argv)) {
        std::cerr << app.get_name() << ": " << *message << " (see --help)\n";
        return static_cast<int>(ExitCode::bad_input);
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << app.get_name() << ": " << readable(e.what()) << " (see --help)\n";
        return static_cast<int>(ExitCode::bad_input);
    }
    try {
        body();
        // Without --out, stdout is a tool's only output: a write that failed (a full disk) is
        // a failed run, not a success with nothing printed.
        std::cout.flush();
        if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
            std::cerr << app.get_name()
                      << ": cannot write to standard output: " << std::strerror(errno) << "\n";
            return static_cast<int>(ExitCode::failure);
        }
        // The run was done when the signal came (it landed while the outputs were written, or
        // the tool had nothing left to cancel): they are whole, and kept; no figure was drawn
        // after it.
        if (interrupted()) {
            std::cerr << app.get_name() << ": " << Interrupted(g_signal.load()).what()
                      << " once the run was done: its outputs were kept (a figure not drawn "
                         "by then was left out)\n";
            return 128 + g_signal.load();
        }
        return static_cast<int>(ExitCode::success);
    } catch (const Interrupted& e) {
        std::cerr << app.get_name() << ": " << e.what()
                  << (e.kept.empty() ? "; outputs not finished were removed"
                                     : "; kept what was done: " + shown_path(e.kept))
                  << "\n";
        return 128 + e.signal;
    } catch (const std::bad_alloc&) {
        std::cerr << app.get_name() << ": out of memory: the run is too large for this machine\n";
        return static_cast<int>(ExitCode::failure);
    } catch (const std::invalid_argument& e) {
        std::cerr << app.get_name() << ": " << readable(with_flag_names(e.what(), flag_names))
                  << "\n";
        return static_cast<int>(ExitCode::bad_input);
    } catch (const std::exception& e) {
        // A write that failed in a staging folder is named by the folder the user gave.
        std::cerr << app.get_name() << ": " << readable(shown_path(e.what())) << "\n";
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

void Progress::note(const std::string& line) {
    // On a terminal the progress line is cleared first (ANSI erase line) and redrawn below at
    // the next update.
    std::fprintf(stderr, "%s%s\n", m_drawn ? "\r\033[2K" : "", line.c_str());
    m_drawn = false;
    m_end_drawn = false;
    m_last = m_start;
}

bool Progress::update(double fraction) {
    if (interrupted()) return false;
    if (!m_terminal && !m_lines) return true;
    const auto now = std::chrono::steady_clock::now();
    const auto every =
        m_terminal ? std::chrono::milliseconds(250) : std::chrono::milliseconds(5000);
    // The first report of the end is drawn at once; the checks that may follow it report the
    // end again, drawn at the usual pace.
    if ((fraction < 1.0 || m_end_drawn) && now - m_last < every) return true;
    m_last = now;
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    const double rate = elapsed > 0.0 ? 100.0 * fraction / elapsed : 0.0;
    // Nothing done yet gives no rate to extrapolate: the ETA is unknown, not 0. At the end the
    // checks (error estimate, twin, a strict rerun) take a time nothing predicts.
    char eta[32] = "ETA unknown";
    if (fraction >= 1.0)
        std::snprintf(eta, sizeof eta, "%s", m_end_drawn ? "finishing checks" : "ETA 0.0 s");
    else if (fraction > 0.0)
        std::snprintf(eta, sizeof eta, "ETA %.1f s", elapsed * (1.0 - fraction) / fraction);
    m_end_drawn = fraction >= 1.0;
    std::fprintf(stderr, "%s%s: %5.1f %%  %.2f %%/s  elapsed %.1f s  %s%s", m_terminal ? "\r" : "",
                 m_label.c_str(), 100.0 * fraction, rate, elapsed, eta, m_terminal ? "   " : "\n");
    m_drawn = m_terminal;
    return true;
}

} // namespace gapchain::cli
