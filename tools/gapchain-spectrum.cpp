// gapchain-spectrum: power spectral density of one variable of a scene's run.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/report.hpp"
#include "gapchain/signal.hpp"
#include "gapchain/spectrum.hpp"

#include <cstdio>
#include <filesystem>

namespace {

using namespace gapchain;

void print_spectrum(const std::string& variable, const Signal& signal, const Psd& psd,
                    const SpectralContent& content, int order) {
    std::printf("gapchain-spectrum: %s, %zu samples at %g per unit time, %d segments\n",
                variable.c_str(), signal.values.size(), signal.sample_rate, psd.segments);
    std::printf("broadband share %.4f (power away from m/n f_r, n <= %d)\n",
                content.broadband_share, order);
    for (std::size_t i = 0; i < std::min<std::size_t>(8, content.peaks.size()); ++i)
        std::printf("  peak %-10s f = %.5f  power %.3g\n", content.peaks[i].label().c_str(),
                    content.peaks[i].frequency, content.peaks[i].power);
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Power spectral density (Welch, FFTW) of a variable of a row over the scene's "
                 "run.periods after run.transient_periods; peaks labelled against f_r.",
                 "gapchain-spectrum"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, true);
    std::string variable = "u1", window = "hann", out = "spectrum";
    int samples_per_period = 32, segment = 4096, order = 4;
    bool no_plot = false;
    app.add_option("--variable", variable, "u1..uN, v1..vN, g0..gN or F0..FN")
        ->capture_default_str();
    app.add_option("--samples-per-period", samples_per_period, "Samples per forcing period")
        ->check(CLI::Range(2, 100000))
        ->capture_default_str();
    app.add_option("--segment", segment, "Welch segment length (samples, >= 16)")
        ->check(CLI::Range(16, 1 << 24))
        ->capture_default_str();
    app.add_option("--window", window, "hann or rectangular")
        ->check(CLI::IsMember({"hann", "rectangular"}))
        ->capture_default_str();
    app.add_option("--order", order, "Largest subharmonic order labelled")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    app.add_option("--out", out, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", no_plot, "Write the CSV files only");
    return cli::run(
        app, argc, argv,
        [&] {
            const Scene scene = cli::load(scene_args);
            const Dynamics dyn = scene.dynamics();
            require_harmonic(dyn, "spectrum"); // before the sample count, which needs a period
            const SectionVariable var =
                SectionVariable::parse(variable, dyn.bodies(), "--variable");
            if (var.kind == SectionVariable::Kind::time)
                throw std::invalid_argument("--variable: must be a state variable (u, v, g or F), "
                                            "got t");
            PsdOptions po;
            po.window = parse_window(window);
            po.segment_length = segment;
            const long samples =
                (scene.run.periods - with_transient_resolved(dyn, scene.run).transient_periods) *
                samples_per_period;
            if (samples < segment)
                throw std::invalid_argument("--segment: must be at most the recorded samples " +
                                            std::to_string(samples) +
                                            " (run.periods - run.transient_periods) x "
                                            "--samples-per-period, got " +
                                            std::to_string(segment));
            cli::Outputs outputs({scene_args.path});
            outputs.folder(out, "--out");
            cli::Progress progress("gapchain-spectrum");
            RunOutcome outcome;
            const Signal signal = record_signal(dyn, scene.run, var, samples_per_period, outcome,
                                                scene.initial, progress.callback());
            cli::throw_if_interrupted();
            if (outcome.status == RunStatus::non_finite)
                throw cli::NumericalFailure(outcome.message);
            po.sample_rate = signal.sample_rate;
            const Psd psd = welch_psd(signal.values, po);
            const SpectralContent content = spectral_content(psd, scene.reduced.f_r, order);
            outputs.create_folders();
            write_file_atomically(out + "/psd.csv", psd_csv(psd, scene.reduced.f_r));
            write_file_atomically(out + "/peaks.csv", peaks_csv(content, scene.reduced.f_r));
            if (!no_plot)
                cli::plot_template(out, "spectrum",
                                   {{"VARIABLE", variable},
                                    {"SEGMENTS", std::to_string(psd.segments)},
                                    {"SEGMENT", std::to_string(segment)}});
            outputs.keep();
            print_spectrum(variable, signal, psd, content, order);
        },
        {{"segment_length", "--segment"}, {"max_order", "--order"}, {"window", "--window"}});
}
