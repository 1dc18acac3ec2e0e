// gapchain-poincare: the Poincaré section of one scene: DIR/section.csv and DIR/section.png.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/output_file.hpp"
#include "gapchain/poincare.hpp"
#include "gapchain/report.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
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
    std::vector<std::string> record{"u1", "v1"};
};

SectionSpec section_spec(const SectionArguments& a, SectionSpec spec, int bodies) {
    spec.kind = a.kind == "event" ? SectionSpec::Kind::event : SectionSpec::Kind::stroboscopic;
    spec.trigger = SectionVariable::parse(a.trigger, bodies, "--trigger");
    spec.direction = a.direction == "up"     ? CrossingDirection::up
                     : a.direction == "down" ? CrossingDirection::down
                                             : CrossingDirection::both;
    spec.record.clear();
    for (const auto& name : a.record)
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

// Streams the section into out_dir/section.csv; returns the number of points and the run
// time [s].
std::pair<long, double> take_section_to_csv(const Scene& scene, const SectionSpec& spec,
                                            const std::string& out_dir) {
    const auto start = std::chrono::steady_clock::now();
    OutputFile csv(out_dir + "/section.csv");
    csv.stream() << "t";
    for (const auto& v : spec.record)
        if (!is_time(v)) csv.stream() << ',' << v.name();
    csv.stream() << '\n';
    long count = 0;
    cli::Progress progress("gapchain-poincare");
    const RunOutcome outcome = take_section(
        scene.dynamics(), scene.run, spec,
        [&](const SectionPoint& p) {
            csv.stream() << p.t;
            for (std::size_t i = 0; i < p.values.size(); ++i)
                if (!is_time(spec.record[i])) csv.stream() << ',' << p.values[i];
            csv.stream() << '\n';
            ++count;
        },
        scene.initial, progress.callback());
    cli::throw_if_interrupted();
    if (outcome.status == RunStatus::non_finite) throw cli::NumericalFailure(outcome.message);
    csv.commit();
    return {count, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
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
    bool no_plot = false;
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
    app.add_option("--record", a.record, "Recorded variables: t, u1.., v1.., g0.., F0..")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--out", out_dir, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the CSV file only");

    return cli::run(
        app, argc, argv,
        [&] {
            refuse_other_kind_options(app, a.kind);
            cli::require_sets_read(scene_args, "gapchain-poincare", once_through_run_keys,
                                   cli::plain_run_reason);
            const Scene scene = cli::load(scene_args);
            spec = section_spec(a, spec, scene.reduced.Nm);
            cli::Outputs outputs({scene_args.path});
            outputs.folder(out_dir, "--out", {"section.csv", "section.gp", "section.png"});
            outputs.create_folders();
            const std::string staged = outputs.staged(out_dir);
            const auto [count, wall] = take_section_to_csv(scene, spec, staged);
            // No point (an event never met, a contact that never closes): nothing to draw.
            if (count == 0 && !no_plot)
                std::fprintf(stderr, "note: the section has no points: no figure\n");
            if (!no_plot && spec.record.size() >= 2 && count > 0)
                plot_section(staged, spec, a, count);
            outputs.keep();
            std::printf("gapchain-poincare: %ld section points in %s/section.csv (%.3f s)\n", count,
                        out_dir.c_str(), wall);
        },
        {{"section.phase", "--phase"},
         {"section.trigger", "--trigger"},
         {"section.level", "--level"},
         {"section.record", "--record"}});
}
