// gapchain-poincare: the Poincaré section of one scene: DIR/section.csv and DIR/section.png.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/output_file.hpp"
#include "gapchain/poincare.hpp"
#include "gapchain/report.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace gapchain;

// The section asked for on the command line.
struct SectionArguments {
    std::string kind = "stroboscopic", trigger = "u1", direction = "up";
    std::vector<std::string> record{"u1,v1"};
};

SectionSpec section_spec(const SectionArguments& a, SectionSpec spec, int bodies) {
    spec.kind = a.kind == "event" ? SectionSpec::Kind::event : SectionSpec::Kind::stroboscopic;
    spec.trigger = SectionVariable::parse_trigger(a.trigger, bodies, "--trigger");
    spec.direction = a.direction == "up"     ? CrossingDirection::up
                     : a.direction == "down" ? CrossingDirection::down
                                             : CrossingDirection::both;
    spec.record.clear();
    for (const auto& name : cli::list_items("--record", a.record))
        spec.record.push_back(SectionVariable::parse(name, bodies, "--record"));
    validate(spec, bodies);
    return spec;
}

// An option of the other kind of section would be ignored: refused.
void refuse_other_kind_options(const CLI::App& app, const std::string& kind) {
    const bool event = kind == "event";
    for (const char* flag : {"--trigger", "--level", "--direction"})
        if (!event && app.count(flag) > 0)
            throw std::invalid_argument(std::string(flag) + ": applies to --section event only");
    if (event && app.count("--phase") > 0)
        throw std::invalid_argument("--phase: applies to --section stroboscopic only");
}

// The CSV's columns: t first, then the recorded variables; a recorded t is that first column,
// not a second copy of it.
bool is_time(const SectionVariable& v) {
    return v.name() == "t";
}

// 1-based CSV column of a recorded variable.
int csv_column(const SectionSpec& spec, std::size_t index) {
    if (is_time(spec.record[index])) return 1;
    int column = 1;
    for (std::size_t i = 0; i <= index; ++i)
        column += is_time(spec.record[i]) ? 0 : 1;
    return column;
}

// What the section run gave: its points, the first of them kept for the error estimate.
struct TakenSection {
    long count = 0;
    int repeats_every = 0; ///< the last points repeat after this many; 0: they do not
    std::vector<SectionPoint> first;
    RunOutcome outcome;
};

// Streams the section into out_dir/section.csv.
TakenSection take_section_to_csv(const Scene& scene, const SectionSpec& spec,
                                 const std::string& out_dir) {
    OutputFile csv(out_dir + "/section.csv");
    csv.stream() << "t";
    for (const auto& v : spec.record)
        if (!is_time(v)) csv.stream() << ',' << v.name();
    csv.stream() << '\n';
    TakenSection taken;
    // Whether the record ends periodic, and on how many points: a researcher counted 100 rows
    // of one point by hand (an independent review, helper-88).
    RecordTailRepeats repeats(spec);
    cli::Progress progress("gapchain-poincare");
    taken.outcome = take_section(
        scene.dynamics(), scene.run, spec,
        [&](const SectionPoint& p) {
            csv.stream() << p.t;
            for (std::size_t i = 0; i < p.values.size(); ++i)
                if (!is_time(spec.record[i])) csv.stream() << ',' << p.values[i];
            csv.stream() << '\n';
            ++taken.count;
            if (taken.first.size() < section_error_points) taken.first.push_back(p);
            repeats.add(p);
        },
        scene.initial, progress.callback());
    cli::throw_if_interrupted();
    if (taken.outcome.status == RunStatus::non_finite)
        throw cli::NumericalFailure(taken.outcome.message);
    csv.commit();
    taken.repeats_every = repeats.period();
    return taken;
}

// The points' error estimate against a finer run. The section is done and written by then: a
// signal here cancels the estimate only (not estimated), and the run ends as interrupted once
// its outputs are kept.
SectionAccuracy estimate_point_error(const Scene& scene, const SectionSpec& spec,
                                     const std::vector<SectionPoint>& first) {
    cli::Progress progress("gapchain-poincare: error estimate");
    return section_accuracy(scene.dynamics(), scene.run, spec, scene.initial, first,
                            progress.callback());
}

void print_repeats(const TakenSection& taken) {
    if (taken.count == 0) return;
    if (taken.repeats_every > 0)
        std::printf("  the record's last points repeat every %d point%s (to %g of their size): "
                    "a periodic record\n",
                    taken.repeats_every, taken.repeats_every == 1 ? "" : "s",
                    RecordTailRepeats::repeat_tolerance);
    else
        std::printf("  the record's last points do not repeat after up to %d points (to %g of "
                    "their size): chaotic, quasi-periodic, a longer cycle, or still settling\n",
                    RecordTailRepeats::max_repeat, RecordTailRepeats::repeat_tolerance);
}

void print_crossings_differ(const SectionAccuracy& a) {
    std::printf("  from point %ld on the two runs' crossings pair wrongly (found at other times or "
                "rates): one run found a crossing the other did not, a level within a run's error "
                "of an extremum or a dip shallower than that error (not chaos); a smaller "
                "run.tolerance or run.step settles which\n",
                a.parted_at);
}

void print_point_error(const SectionSpec& spec, const SectionAccuracy& a) {
    if (!a.not_estimated.empty()) {
        std::printf("  point error not estimated: %s\n", a.not_estimated.c_str());
        if (a.crossings_differ && a.compared == 0)
            std::printf("  one run crosses the level and the other never does: a level within a "
                        "run's error of an extremum (not chaos); a smaller run.tolerance or "
                        "run.step settles which\n");
        else if (a.crossings_differ)
            print_crossings_differ(a);
        return;
    }
    std::printf(
        "  point error (%s %ld points, against a run at %s):", a.parted_at == 0 ? "all" : "first",
        a.parted_at <= 0 ? a.compared : a.parted_at, a.comparison.c_str());
    bool any = false;
    for (std::size_t i = 0; i < spec.record.size(); ++i)
        if (!std::isnan(a.error[i])) {
            std::printf(" %s %.2g", spec.record[i].name().c_str(), a.error[i]);
            any = true;
        }
    std::printf("%s\n",
                any ? "" : " none recorded (a stroboscopic t and an event's trigger carry none)");
    if (a.finer_repeats)
        std::printf("  the runs part at point %ld of %ld compared, and only the finer run's points "
                    "repeat (a periodic orbit): this run's step is too coarse to follow that "
                    "orbit, or it reached another, chaotic attractor; a smaller run.step or "
                    "run.tolerance settles which%s\n",
                    a.parted_at, a.compared,
                    a.parted_at == 0 ? "; the error covers every point" : "");
    else if (a.parted_at == 0 && !a.crossings_differ)
        std::printf("  the runs differ from the first point on and grow apart: a chaotic record "
                    "that parted before it began; the error covers every point, the "
                    "attractor's extent\n");
    if (a.crossings_differ)
        print_crossings_differ(a);
    else if (a.parted_at > 0 && !a.finer_repeats)
        std::printf(
            "  the runs part at point %ld of %ld compared (a chaotic record): beyond it the "
            "points sample the attractor, not this start's trajectory\n",
            a.parted_at, a.compared);
}

// DIR/section.gp and section.png: the first two recorded variables against each other.
void plot_section(const std::string& dir, const SectionSpec& spec, const SectionArguments& a,
                  long count) {
    cli::plot_template(dir, "section",
                       {{"X", spec.record[0].name()},
                        {"Y", spec.record[1].name()},
                        {"XCOLUMN", std::to_string(csv_column(spec, 0))},
                        {"YCOLUMN", std::to_string(csv_column(spec, 1))},
                        {"TITLE", a.kind == "event" ? "event section " + a.trigger + " = level"
                                                    : std::string("stroboscopic section")},
                        {"COUNT", std::to_string(count)}});
}

// The section's own options: its kind, where it is taken, and what it records.
void add_section_options(CLI::App& app, SectionArguments& a, SectionSpec& spec) {
    app.add_option("--section", a.kind, "stroboscopic or event")
        ->check(CLI::IsMember({"stroboscopic", "event"}))
        ->capture_default_str();
    app.add_option("--phase", spec.phase, "Stroboscopic phase in [0, 1)")->capture_default_str();
    app.add_option("--trigger", a.trigger,
                   "Event coordinate: u1..uN, v1..vN or g0..gN (a linear signal of the state)")
        ->capture_default_str();
    app.add_option("--level", spec.level, "Event level")->capture_default_str();
    app.add_option("--direction", a.direction, "Event direction: up, down or both")
        ->check(CLI::IsMember({"up", "down", "both"}))
        ->capture_default_str();
    app.add_option("--record", a.record,
                   "Recorded variables, comma-separated: t, u1.., v1.., g0.., F0..")
        ->capture_default_str();
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Poincare section of a row: stroboscopic (once per forcing period at a phase) or "
                 "event (a coordinate crossing a level). Uses the scene's run.periods and "
                 "run.transient_periods.",
                 "gapchain-poincare"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, true);
    SectionArguments a;
    std::string out_dir = "section";
    SectionSpec spec;
    add_section_options(app, a, spec);
    bool no_plot = false, no_error = false;
    app.add_option("--out", out_dir, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the CSV and JSON files only");
    app.add_flag("--no-error", no_error,
                 "No point error estimate (it reruns the transient and the first 1000 points on "
                 "a finer plan)");

    return cli::run(
        app, argc, argv,
        [&] {
            refuse_other_kind_options(app, a.kind);
            cli::require_sets_read(scene_args, "gapchain-poincare", once_through_run_keys,
                                   cli::plain_run_reason);
            const Scene scene = cli::load(scene_args);
            spec = section_spec(a, spec, scene.reduced.Nm);
            cli::Outputs outputs({scene_args.path});
            outputs.folder(out_dir, "--out",
                           {"section.csv", "section.json", "section.gp", "section.png"});
            outputs.create_folders();
            const std::string staged = outputs.staged(out_dir);
            const auto start = std::chrono::steady_clock::now();
            const TakenSection taken = take_section_to_csv(scene, spec, staged);
            std::optional<SectionAccuracy> accuracy;
            if (!no_error) accuracy = estimate_point_error(scene, spec, taken.first);
            const double wall =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            write_file_atomically(staged + "/section.json",
                                  to_json(spec, taken.count, taken.repeats_every,
                                          accuracy ? &*accuracy : nullptr, wall, scene,
                                          taken.outcome));
            // No point (an event never met, a contact that never closes): nothing to draw.
            if (taken.count == 0 && !no_plot)
                std::fprintf(stderr, "note: the section has no points: no figure\n");
            if (!no_plot && spec.record.size() >= 2 && taken.count > 0)
                plot_section(staged, spec, a, taken.count);
            outputs.keep();
            std::printf("gapchain-poincare: %ld section points in %s/section.csv (%.3f s)\n",
                        taken.count, out_dir.c_str(), wall);
            print_repeats(taken);
            if (accuracy) print_point_error(spec, *accuracy);
        },
        {{"section.phase", "--phase"},
         {"section.trigger", "--trigger"},
         {"section.level", "--level"},
         {"section.record", "--record"}});
}
