#include "gapchain/spectrum.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>

using namespace gapchain;
using std::numbers::pi;

TEST_CASE("Parseval: one rectangular segment integrates to the mean square exactly") {
    std::mt19937 gen(7);
    std::normal_distribution<double> noise(0.0, 1.3);
    std::vector<double> x(1024);
    for (auto& v : x)
        v = noise(gen);
    double mean = 0.0;
    for (double v : x)
        mean += v;
    mean /= x.size();
    double ms = 0.0;
    for (double v : x)
        ms += (v - mean) * (v - mean);
    ms /= x.size();
    PsdOptions o;
    o.sample_rate = 20.0;
    o.segment_length = 1024;
    o.window = Window::rectangular;
    const Psd psd = welch_psd(x, o);
    double integral = 0.0;
    for (double d : psd.density)
        integral += d * psd.df;
    CHECK(psd.segments == 1);
    CHECK(integral == doctest::Approx(ms).epsilon(1e-12));
}

TEST_CASE("Parseval holds on average for Welch with a Hann window") {
    std::mt19937 gen(11);
    std::normal_distribution<double> noise(0.0, 2.0);
    std::vector<double> x(1 << 16);
    for (auto& v : x)
        v = noise(gen);
    PsdOptions o;
    o.sample_rate = 1.0;
    o.segment_length = 1024;
    const Psd psd = welch_psd(x, o);
    double integral = 0.0;
    for (double d : psd.density)
        integral += d * psd.df;
    CHECK(psd.segments == 127);
    CHECK(integral == doctest::Approx(4.0).epsilon(0.03));
}

TEST_CASE("a pure sine's peak lands on its frequency and is labelled") {
    const double fs = 64.0, f_r = 2.5;
    std::vector<double> x(8192);
    for (std::size_t i = 0; i < x.size(); ++i)
        x[i] = 0.7 * std::sin(2 * pi * f_r * i / fs) +
               0.2 * std::sin(2 * pi * 0.5 * f_r * i / fs + 1.0);
    PsdOptions o;
    o.sample_rate = fs;
    o.segment_length = 2048;
    const Psd psd = welch_psd(x, o);
    const SpectralContent c = spectral_content(psd, f_r);
    REQUIRE(c.peaks.size() >= 2);
    CHECK(c.peaks[0].frequency == doctest::Approx(f_r).epsilon(1e-9));
    CHECK(c.peaks[0].label() == "1 f_r");
    CHECK(c.peaks[1].frequency == doctest::Approx(0.5 * f_r).epsilon(1e-9));
    CHECK(c.peaks[1].label() == "1/2 f_r");
    // Power of a sine of amplitude A is A^2 / 2.
    CHECK(c.peaks[0].power == doctest::Approx(0.7 * 0.7 / 2).epsilon(0.01));
    CHECK(c.broadband_share < 1e-3);
}

TEST_CASE("a peak is labelled m/n f_r only when that fraction alone is its nearest bin's") {
    // Bins of df = f_r / 8 (a segment of 8 forcing periods), f_r = 3, a line at 0.375 f_r:
    // labelled "1/2 f_r" (a bin away) before; 1/3 f_r is within half a bin, alone.
    auto psd_with_peak = [](double df, int peak) {
        Psd psd;
        psd.df = df;
        for (int k = 0; k < 64; ++k) {
            psd.frequency.push_back(k * df);
            psd.density.push_back(k == peak ? 1.0 : 1e-3);
        }
        return psd;
    };
    const double f_r = 3.0;
    const SpectralContent coarse = spectral_content(psd_with_peak(f_r / 8, 3), f_r);
    REQUIRE(coarse.peaks.size() == 1);
    CHECK(coarse.peaks[0].numerator == 1);
    CHECK(coarse.peaks[0].denominator == 3);
    // df = f_r / 4: 1/4 f_r (on the bin) and 1/3 f_r (a third of a bin off) share it: no label.
    const SpectralContent ambiguous = spectral_content(psd_with_peak(f_r / 4, 1), f_r);
    REQUIRE(ambiguous.peaks.size() == 1);
    CHECK(ambiguous.peaks[0].denominator == 0);
    CHECK(ambiguous.peaks[0].label() == "-");
    // A harmonic on its bin keeps its label.
    const SpectralContent harmonic = spectral_content(psd_with_peak(f_r / 8, 16), f_r);
    REQUIRE(harmonic.peaks.size() == 1);
    CHECK(harmonic.peaks[0].label() == "2 f_r");
}

TEST_CASE("white noise is broadband") {
    std::mt19937 gen(3);
    std::normal_distribution<double> noise(0.0, 1.0);
    std::vector<double> x(1 << 15);
    for (auto& v : x)
        v = noise(gen);
    PsdOptions o;
    o.sample_rate = 32.0;
    o.segment_length = 4096;
    const SpectralContent c = spectral_content(welch_psd(x, o), 1.0);
    CHECK(c.broadband_share > 0.5);
}

TEST_CASE("bad input is refused") {
    PsdOptions o;
    o.segment_length = 64;
    CHECK_THROWS_AS(welch_psd(std::vector<double>(10, 1.0), o), std::invalid_argument);
    std::vector<double> x(128, 0.0);
    x[5] = NAN;
    CHECK_THROWS_AS(welch_psd(x, o), std::invalid_argument);
    CHECK_THROWS_AS(parse_window("kaiser"), std::invalid_argument);
}

namespace {

/// amplitude sin(2 pi cycles i) plus unit white noise, i = 0 .. samples - 1 (cycles per sample).
std::vector<double> sine_in_noise(double amplitude, double cycles, std::size_t samples,
                                  std::mt19937& gen) {
    std::normal_distribution<double> noise(0.0, 1.0);
    std::vector<double> x(samples);
    for (std::size_t i = 0; i < samples; ++i)
        x[i] = amplitude * std::sin(2 * pi * cycles * i) + noise(gen);
    return x;
}

/// The sample standard deviation of values (at least 2).
double sample_spread(const std::vector<double>& values) {
    const double mean = std::accumulate(values.begin(), values.end(), 0.0) / values.size();
    double squares = 0.0;
    for (double v : values)
        squares += (v - mean) * (v - mean);
    return std::sqrt(squares / (values.size() - 1));
}

} // namespace

TEST_CASE("a peak's power error is the scatter an independent record of the signal shows") {
    // A sine in white noise: the power in the line's bins varies from record to record. Each
    // record's own error (from its segments) must match the spread over 200 records.
    PsdOptions o;
    o.sample_rate = 32.0;
    o.segment_length = 256;
    const double f = 2.0; // on a bin: df = 0.125
    std::mt19937 gen(3);
    std::vector<double> powers, errors;
    for (int record = 0; record < 200; ++record) {
        const std::vector<double> x = sine_in_noise(0.3, f / o.sample_rate, 256 * 16, gen);
        const Psd psd = welch_psd(x, o);
        const SpectralContent c = spectral_content(psd, f);
        REQUIRE_FALSE(c.peaks.empty());
        const SpectralPeak& line = c.peaks.front();
        REQUIRE(line.frequency == doctest::Approx(f));
        CHECK(line.frequency_error == doctest::Approx(0.5 * psd.df));
        CHECK(std::isnan(line.power_error)); // spectral_content() alone does not estimate it
        powers.push_back(line.power);
        errors.push_back(band_power_errors(x, o, {{line.first_bin, line.last_bin}}).at(0));
    }
    const double spread = sample_spread(powers);
    std::sort(errors.begin(), errors.end());
    const double median = errors[errors.size() / 2];
    // Within 15 % either way (Welch's correction for the overlap; the record's length in whole
    // segments instead overstated it 1.3-1.4 times).
    MESSAGE("median error / spread over records: " << median / spread);
    CHECK(median > spread / 1.15);
    CHECK(median < spread * 1.15);
}

TEST_CASE("the broadband share's error is the scatter an independent record shows") {
    // A sine in white noise: the share of the noise away from the sine's fractions varies from
    // record to record. Each record's own error (from its segments) must match the spread
    // over 200 records. On Fig 13's row at f_r = 3.3 (chaotic), 24 windows of 2000 periods:
    // 0.0437 mean share, 7.3e-4 spread, 9.2e-4 stated (docs/chaos.md).
    PsdOptions o;
    o.sample_rate = 32.0;
    o.segment_length = 256;
    const double f = 2.0;
    std::mt19937 gen(5);
    std::vector<double> shares, errors;
    for (int record = 0; record < 200; ++record) {
        const std::vector<double> x = sine_in_noise(1.0, f / o.sample_rate, 256 * 16, gen);
        const SpectralContent c = spectral_content(welch_psd(x, o), f);
        CHECK(std::isnan(c.broadband_share_error)); // spectral_content() alone does not
        shares.push_back(c.broadband_share);
        errors.push_back(broadband_share_error(x, o, f));
    }
    const double spread = sample_spread(shares);
    // A share worth measuring: a quarter of the noise's bins lie away from the fractions.
    CHECK(std::accumulate(shares.begin(), shares.end(), 0.0) / shares.size() > 0.05);
    std::sort(errors.begin(), errors.end());
    const double median = errors[errors.size() / 2];
    MESSAGE("median share error / spread over records: " << median / spread);
    CHECK(median > spread / 1.15);
    CHECK(median < spread * 1.15);
    // One segment: not estimated.
    std::vector<double> one(256, 1.0);
    one[3] = 2.0;
    CHECK(std::isnan(broadband_share_error(one, o, f)));
}

TEST_CASE("a periodic record's power error is at round-off; one segment has none") {
    PsdOptions o;
    o.sample_rate = 64.0;
    o.segment_length = 512; // 8 periods of the unit-frequency sine a segment
    std::vector<double> x(512 * 4);
    for (std::size_t i = 0; i < x.size(); ++i)
        x[i] = std::sin(2 * pi * i / o.sample_rate) + 0.1 * std::sin(6 * pi * i / o.sample_rate);
    const SpectralContent c = spectral_content(welch_psd(x, o), 1.0);
    REQUIRE(c.peaks.size() >= 2);
    for (const SpectralPeak& p : c.peaks) {
        const double e = band_power_errors(x, o, {{p.first_bin, p.last_bin}}).at(0);
        CHECK(e <= 1e-12 * c.peaks.front().power);
    }
    // A frequency between bins lies within half a bin of its peak.
    std::vector<double> off(512);
    for (std::size_t i = 0; i < off.size(); ++i)
        off[i] = std::sin(2 * pi * 1.37 * i / o.sample_rate);
    const SpectralContent one = spectral_content(welch_psd(off, o), 1.37);
    REQUIRE_FALSE(one.peaks.empty());
    CHECK(std::abs(one.peaks.front().frequency - 1.37) <= one.peaks.front().frequency_error);
    CHECK(std::isnan(band_power_errors(off, o, {{1, 3}}).at(0)));
    CHECK_THROWS_AS(band_power_errors(off, o, {{3, 1}}), std::invalid_argument);
    CHECK_THROWS_AS(band_power_errors(off, o, {{0, 257}}), std::invalid_argument);
}

TEST_CASE("a line at the Nyquist frequency is a peak") {
    // The last bin has no right neighbour; at 2 samples per period the forcing's own line sits
    // there, and spectral_content() listed no peak at all.
    PsdOptions o;
    o.sample_rate = 2.0;
    o.segment_length = 64;
    o.window = Window::rectangular;
    std::vector<double> x(256);
    for (std::size_t i = 0; i < x.size(); ++i)
        x[i] = (i % 2 == 0 ? 1.0 : -1.0); // cos(pi i): the forcing f_r = 1 at 2 samples a period
    const SpectralContent c = spectral_content(welch_psd(x, o), 1.0);
    REQUIRE(c.peaks.size() == 1);
    CHECK(c.peaks.front().frequency == doctest::Approx(1.0));
    CHECK(c.peaks.front().label() == "1 f_r");
}

TEST_CASE("the broadband share's error refuses what the share refuses") {
    PsdOptions o;
    o.segment_length = 16;
    const std::vector<double> x(64, 1.0);
    // f_r = 0 marked fractions m / n f_r forever.
    CHECK_THROWS_WITH_AS(broadband_share_error(x, o, 0.0), doctest::Contains("f_r"),
                         std::invalid_argument);
    CHECK_THROWS_WITH_AS(broadband_share_error(x, o, 1.0, 0), doctest::Contains("max_order"),
                         std::invalid_argument);
    CHECK_THROWS_WITH_AS(broadband_share_error(x, o, 1.0, 4, -1), doctest::Contains("width"),
                         std::invalid_argument);
    CHECK(std::isnan(broadband_share_error(x, o, 1.0))); // a constant: no power
}

TEST_CASE("a pure sine recorded over whole periods and one more sample has no broadband power") {
    // gapchain-spectrum records the end point too: the record's mean then differs from every
    // segment's by a sample / record length, which the window leaked into bin 1 (1e-9 at 16
    // samples a period, on an offset sine as on a gap's).
    for (const int per_period : {16, 64}) {
        for (const double offset : {0.0, 5.0}) {
            CAPTURE(per_period);
            CAPTURE(offset);
            PsdOptions o;
            o.sample_rate = per_period;
            o.segment_length = 120 * per_period;
            std::vector<double> x(static_cast<std::size_t>(1000 * per_period) + 1);
            for (std::size_t i = 0; i < x.size(); ++i)
                x[i] = offset + 0.3 * std::sin(2 * pi * static_cast<double>(i) / per_period + 0.4);
            const SpectralContent c = spectral_content(welch_psd(x, o), 1.0);
            CHECK(c.broadband_share < 1e-20);
            CHECK(broadband_share_error(x, o, 1.0) < 1e-20);
        }
    }
}
