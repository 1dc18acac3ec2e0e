// gapchain-poincare: the Poincaré section of one scene: DIR/section.csv and DIR/section.png.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/poincare.hpp"
#include "gapchain/report.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>

int main(int argc, char** argv) {
    using namespace gapchain;
    CLI::App app{"Poincare section of a row: stroboscopic (once per forcing period at a phase) or "
                 "event (a coordinate crossing a level). Uses the scene's run.periods and "
                 "run.transient_periods.",
                 "gapchain-poincare"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, true);
    std::string kind = "stroboscopic", trigger = "u1", direction = "up", out_dir = "section";
    std::vector<std::string> record{"u1", "v1"};
    SectionSpec spec;
    bool no_plot = false;
    app.add_option("--section", kind, "stroboscopic or event")->capture_default_str();
    app.add_option("--phase", spec.phase, "Stroboscopic phase in [0, 1)")->capture_default_str();
    app.add_option("--trigger", trigger, "Event coordinate: u1..uN, v1..vN, or g0..gN (gap)")
        ->capture_default_str();
    app.add_option("--level", spec.level, "Event level")->capture_default_str();
    app.add_option("--direction", direction, "Event direction: up, down or both")
        ->capture_default_str();
    app.add_option("--record", record, "Recorded variables: t, u1.., v1.., g0.., F0..")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--out", out_dir, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the CSV file only");

    return cli::run(app, argc, argv, [&] {
        const Scene scene = cli::load(scene_args);
        const int n = scene.reduced.Nm;
        if (kind != "stroboscopic" && kind != "event")
            throw std::invalid_argument("--section: must be stroboscopic or event, got \"" + kind +
                                        "\"");
        spec.kind = kind == "event" ? SectionSpec::Kind::event : SectionSpec::Kind::stroboscopic;
        spec.trigger = SectionVariable::parse(trigger, n, "--trigger");
        if (direction == "up")
            spec.direction = CrossingDirection::up;
        else if (direction == "down")
            spec.direction = CrossingDirection::down;
        else if (direction == "both")
            spec.direction = CrossingDirection::both;
        else
            throw std::invalid_argument("--direction: must be up, down or both, got \"" +
                                        direction + "\"");
        spec.record.clear();
        for (const auto& name : record)
            spec.record.push_back(SectionVariable::parse(name, n, "--record"));
        validate(spec, n);

        std::filesystem::create_directories(out_dir);
        OutputFile csv(out_dir + "/section.csv");
        csv.stream() << "t";
        for (const auto& v : spec.record)
            csv.stream() << ',' << v.name();
        csv.stream() << '\n';
        long count = 0;
        cli::Progress progress("gapchain-poincare");
        const RunOutcome outcome = take_section(
            scene.dynamics(), scene.run, spec,
            [&](const SectionPoint& p) {
                csv.stream() << p.t;
                for (double v : p.values)
                    csv.stream() << ',' << v;
                csv.stream() << '\n';
                ++count;
            },
            scene.initial, progress.callback());
        if (outcome.status == RunStatus::non_finite) throw cli::NumericalFailure(outcome.message);
        csv.commit();
        if (!no_plot && spec.record.size() >= 2) {
            std::ostringstream gp;
            gp << "# Regenerate: gnuplot section.gp (in this folder)\n"
               << "set terminal pngcairo size 900,800 font 'sans,11'\nset output 'section.png'\n"
               << "set datafile separator ','\nset grid\nset key off\n"
               << "set xlabel '" << spec.record[0].name() << "'\nset ylabel '"
               << spec.record[1].name() << "'\n"
               << "set title '"
               << (kind == "event" ? "event section " + trigger + " = level"
                                   : std::string("stroboscopic section"))
               << " (" << count << " points)'\n"
               << "plot 'section.csv' every ::1 using 2:3 with points pt 7 ps 0.4 lc rgb "
                  "'#1f4e9c'\n";
            cli::plot_with_gnuplot(out_dir + "/section.gp", gp.str());
        }
        std::printf("gapchain-poincare: %ld section points in %s/section.csv\n", count,
                    out_dir.c_str());
    });
}
