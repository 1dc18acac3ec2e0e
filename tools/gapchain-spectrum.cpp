// gapchain-spectrum: power spectral density of one variable of a scene's run.
#include "common/cli.hpp"
#include "common/plot.hpp"

#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"
#include "gapchain/signal.hpp"
#include "gapchain/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <string>

namespace {

using namespace gapchain;

std::string short_number(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2g", x);
    return text;
}

// Where a longer segment is the cure: the periods it needs (each m/n f_r, n <= order, in
// [0, f_r) takes three bins, and they should leave well over half the bins), and whether the record
// holds them.
std::string longer_segment_advice(const RowSpectrumOptions& o, const RowSpectrum& s) {
    long fractions = 1; // 0 f_r, then the reduced m/n in (0, 1)
    for (int n = 2; n <= o.order; ++n)
        for (int m = 1; m < n; ++m)
            fractions += std::gcd(m, n) == 1 ? 1 : 0;
    const long unit = whole_period_unit(o.order);
    const long periods = (8 * fractions + unit - 1) / unit * unit;
    const double samples = static_cast<double>(periods) * o.samples_per_period;
    if (samples > static_cast<double>(1 << 24))
        return "a lower --order (" + std::to_string(periods) +
               " periods a segment would be needed)";
    const std::string segment = "--segment " + std::to_string(static_cast<long>(samples)) + " (" +
                                std::to_string(periods) + " periods)";
    if (samples > static_cast<double>(s.samples))
        return segment + ", with a longer record (run.periods)";
    return segment;
}

void print_spectrum(const RowSpectrumOptions& o, const RowSpectrum& s) {
    std::printf("gapchain-spectrum: %s, %ld samples at %g per unit time, %d segment%s of %g "
                "periods\n",
                o.variable.c_str(), s.samples, s.sample_rate, s.psd.segments,
                s.psd.segments == 1 ? "" : "s", s.segment_periods);
    if (!s.whole_periods)
        std::printf("note: a segment of %g periods puts m/n f_r (n <= %d) between bins, where "
                    "the lines leak; the errors include how far the readings move on whole "
                    "periods (--segment a multiple of %d)\n",
                    s.segment_periods, o.order, whole_period_unit(o.order) * o.samples_per_period);
    if (s.content.fraction_bin_share > 0.5)
        std::printf("warning: a segment of %g periods resolves f_r / %g: %.0f %% of the bins lie "
                    "next to some m/n f_r and the broadband share reads the rest only; "
                    "%s\n",
                    s.segment_periods, s.segment_periods, 100.0 * s.content.fraction_bin_share,
                    longer_segment_advice(o, s).c_str());
    // Three significant digits, not four decimals: 7.3e-5 +- 2.2e-5 was printed 0.0001.
    std::printf("broadband share %.3g %s (power away from m/n f_r, n <= %d)\n",
                s.content.broadband_share,
                cli::plus_minus(s.content.broadband_share_error, "%.2g").c_str(), o.order);
    // The Nyquist frequency in forcing harmonics is half the samples per period.
    std::printf("aliased share %.2g (power between %g f_r and twice that, measured at twice the "
                "rate)%s\n",
                s.aliased_share, o.samples_per_period / 2.0,
                s.aliased_share > 1e-3 ? ": the spectrum is aliased, raise --samples-per-period"
                                       : "");
    if (s.sampled_range_share < 0.5)
        std::printf("warning: the samples miss %s's peaks: their range is %.2g of its range at "
                    "the run's steps; raise --samples-per-period\n",
                    o.variable.c_str(), s.sampled_range_share);
    for (std::size_t i = 0; i < std::min<std::size_t>(8, s.content.peaks.size()); ++i) {
        const SpectralPeak& p = s.content.peaks[i];
        const std::string error =
            std::isfinite(p.power_error) ? " +- " + short_number(p.power_error)
            : s.psd.segments < 2         ? std::string(" (error: one segment, not estimated)")
                                         : std::string(" (error not estimated: the lines' leakage "
                                                               "is not measured)");
        std::printf("  peak %-10s f = %.5f +- %.2g  power %.3g%s\n", p.label().c_str(), p.frequency,
                    p.frequency_error, p.power, error.c_str());
    }
    std::printf("wall time %.3f s\n", s.wall_time_s);
}

// The command line of a spectrum.
struct SpectrumArguments {
    cli::SceneArguments scene;
    RowSpectrumOptions spectrum;
    std::string window = "hann", out = "spectrum";
    bool no_plot = false;
};

void add_options(CLI::App& app, SpectrumArguments& a) {
    cli::add_scene_arguments(app, a.scene, true);
    app.add_option("--variable", a.spectrum.variable, "u1..uN, v1..vN, g0..gN or F0..FN")
        ->capture_default_str();
    app.add_option("--samples-per-period", a.spectrum.samples_per_period,
                   "Samples per forcing period")
        ->check(cli::range(2, 100000))
        ->capture_default_str();
    app.add_option("--segment", a.spectrum.segment,
                   "Welch segment length (samples, >= 16; 0: whole forcing periods, a multiple "
                   "of 12 (lcm(1..order) up to 60), up to 128, that the record holds twice)")
        ->check(cli::range(0, 1 << 24))
        ->capture_default_str();
    app.add_option("--window", a.window, "hann or rectangular")
        ->check(CLI::IsMember({"hann", "rectangular"}))
        ->capture_default_str();
    app.add_option("--order", a.spectrum.order, "Largest subharmonic order labelled")
        ->check(cli::range(1, 64))
        ->capture_default_str();
    app.add_option("--out", a.out, "Output folder")->capture_default_str();
    app.add_flag("--no-plot", a.no_plot, "Write the CSV files only");
}

void write_outputs(const SpectrumArguments& a, const std::string& dir, const RowSpectrum& s,
                   const Scene& scene) {
    const double f_r = scene.reduced.f_r;
    write_file_atomically(dir + "/psd.csv", psd_csv(s.psd, f_r));
    write_file_atomically(dir + "/peaks.csv", peaks_csv(s.content, f_r));
    // The readings printed (broadband share and its error, aliasing, run time) were in no file.
    write_file_atomically(dir + "/spectrum.json", to_json(s, a.spectrum, scene));
    // A variable that never moves (a contact that never closes) has no power to draw on the
    // figure's log scale: its CSV files say so, and there is no figure.
    const bool flat =
        std::none_of(s.psd.density.begin(), s.psd.density.end(), [](double d) { return d > 0.0; });
    if (flat && !a.no_plot)
        std::fprintf(stderr,
                     "note: %s has no power at any frequency (it is constant over the "
                     "recorded periods): no figure\n",
                     a.spectrum.variable.c_str());
    if (!a.no_plot && !flat)
        cli::plot_template(dir, "spectrum",
                           {{"VARIABLE", a.spectrum.variable},
                            {"SEGMENTS", std::to_string(s.psd.segments)},
                            {"SEGMENT", std::to_string(s.segment)}});
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Power spectral density (Welch, FFTW) of a variable of a row over the scene's "
                 "run.periods after run.transient_periods; peaks labelled against f_r.",
                 "gapchain-spectrum"};
    SpectrumArguments a;
    add_options(app, a);
    return cli::run(app, argc, argv,
                    [&] {
                        cli::require_sets_read(a.scene, "gapchain-spectrum", once_through_run_keys,
                                               cli::plain_run_reason);
                        const Scene scene = cli::load(a.scene);
                        const Dynamics dyn = scene.dynamics();
                        a.spectrum.window = parse_window(a.window);
                        validate(a.spectrum, dyn, scene.run);
                        cli::Outputs outputs({a.scene.path});
                        outputs.folder(a.out, "--out",
                                       {"psd.csv", "peaks.csv", "spectrum.json", "spectrum.gp",
                                        "spectrum.png"});
                        cli::Progress progress("gapchain-spectrum");
                        const RowSpectrum s = row_spectrum(dyn, scene.run, a.spectrum,
                                                           scene.initial, progress.callback());
                        cli::throw_if_interrupted();
                        if (s.outcome.status == RunStatus::non_finite)
                            throw cli::NumericalFailure(s.outcome.message);
                        outputs.create_folders();
                        write_outputs(a, outputs.staged(a.out), s, scene);
                        outputs.keep();
                        print_spectrum(a.spectrum, s);
                    },
                    {{"segment", "--segment"},
                     {"order", "--order"},
                     {"samples_per_period", "--samples-per-period"},
                     {"variable", "--variable"},
                     {"window", "--window"}});
}
