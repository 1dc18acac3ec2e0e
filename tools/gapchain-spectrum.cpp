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

// The command line of a spectrum.
struct SpectrumArguments {
    cli::SceneArguments scene;
    std::string variable = "u1", window = "hann", out = "spectrum";
    int samples_per_period = 32, segment = 4096, order = 4;
    bool no_plot = false;
};

void add_options(CLI::App& app, SpectrumArguments& a) {
    cli::add_scene_arguments(app, a.scene, true);
    app.add_option("--variable", a.variable, "u1..uN, v1..vN, g0..gN or F0..FN")
        ->capture_default_str();
    app.add_option("--samples-per-period", a.samples_per_period, "Samples per forcing period")
        ->check(cli::range(2, 100000))
        ->capture_default_str();
    app.add_option("--segment", a.segment, "Welch segment length (samples, >= 16)")
        ->check(cli::range(16, 1 << 24))
        ->capture_default_str();
    app.add_option("--window", a.window, "hann or rectangular")
        ->check(CLI::IsMember({"hann", "rectangular"}))
        ->capture_default_str();
    app.add_option("--order", a.order, "Largest subharmonic order labelled")
        ->check(cli::range(1, 64))
        ->capture_default_str();
    app.add_option("--out", a.out, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", a.no_plot, "Write the CSV files only");
}

// The variable to record: a state variable of the row.
SectionVariable recorded_variable(const SpectrumArguments& a, const Dynamics& dyn) {
    const SectionVariable var = SectionVariable::parse(a.variable, dyn.bodies(), "--variable");
    if (var.kind == SectionVariable::Kind::time)
        throw std::invalid_argument("--variable: must be a state variable (u, v, g or F), "
                                    "got t");
    return var;
}

// Refuses a segment longer than the samples the scene's run records.
void require_segment_fits(const SpectrumArguments& a, const Scene& scene, const Dynamics& dyn) {
    const long samples =
        (scene.run.periods - with_transient_resolved(dyn, scene.run).transient_periods) *
        a.samples_per_period;
    if (samples < a.segment)
        throw std::invalid_argument("--segment: must be at most the recorded samples " +
                                    std::to_string(samples) +
                                    " (run.periods - run.transient_periods) x "
                                    "--samples-per-period, got " +
                                    std::to_string(a.segment));
}

void write_outputs(const SpectrumArguments& a, const std::string& dir, const Psd& psd,
                   const SpectralContent& content, double f_r) {
    write_file_atomically(dir + "/psd.csv", psd_csv(psd, f_r));
    write_file_atomically(dir + "/peaks.csv", peaks_csv(content, f_r));
    if (!a.no_plot)
        cli::plot_template(dir, "spectrum",
                           {{"VARIABLE", a.variable},
                            {"SEGMENTS", std::to_string(psd.segments)},
                            {"SEGMENT", std::to_string(a.segment)}});
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Power spectral density (Welch, FFTW) of a variable of a row over the scene's "
                 "run.periods after run.transient_periods; peaks labelled against f_r.",
                 "gapchain-spectrum"};
    SpectrumArguments a;
    add_options(app, a);
    return cli::run(
        app, argc, argv,
        [&] {
            const Scene scene = cli::load(a.scene);
            const Dynamics dyn = scene.dynamics();
            require_harmonic(dyn, "spectrum"); // before the sample count, which needs a period
            const SectionVariable var = recorded_variable(a, dyn);
            PsdOptions po;
            po.window = parse_window(a.window);
            po.segment_length = a.segment;
            require_segment_fits(a, scene, dyn);
            cli::Outputs outputs({a.scene.path});
            outputs.folder(a.out, "--out", {"psd.csv", "peaks.csv", "spectrum.gp", "spectrum.png"});
            cli::Progress progress("gapchain-spectrum");
            RunOutcome outcome;
            const Signal signal = record_signal(dyn, scene.run, var, a.samples_per_period, outcome,
                                                scene.initial, progress.callback());
            cli::throw_if_interrupted();
            if (outcome.status == RunStatus::non_finite)
                throw cli::NumericalFailure(outcome.message);
            po.sample_rate = signal.sample_rate;
            const Psd psd = welch_psd(signal.values, po);
            const SpectralContent content = spectral_content(psd, scene.reduced.f_r, a.order);
            outputs.create_folders();
            write_outputs(a, outputs.staged(a.out), psd, content, scene.reduced.f_r);
            outputs.keep();
            print_spectrum(a.variable, signal, psd, content, a.order);
        },
        {{"segment_length", "--segment"}, {"max_order", "--order"}, {"window", "--window"}});
}
