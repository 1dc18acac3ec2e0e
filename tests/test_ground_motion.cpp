#include "gapchain/ground_motion.hpp"
#include "gapchain/lyapunov.hpp"
#include "gapchain/poincare.hpp"
#include "gapchain/scene.hpp"
#include "gapchain/simulation.hpp"
#include "gapchain/spectrum.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <numeric>
#include <string>

using namespace gapchain;

namespace {
constexpr double pi = std::numbers::pi;

RunOptions fixed_step_run(long periods, double step) {
    RunOptions o;
    o.periods = periods;
    o.scheme = Scheme::rk4;
    o.step = step;
    o.stop_at_steady_state = false;
    o.estimate_error = false;
    return o;
}

// Loads scene text from a file in dir, so that relative record paths resolve there.
Scene load_scene_text_in(const std::filesystem::path& dir, const std::string& text) {
    const auto path = dir / "scene.json";
    std::ofstream(path) << text;
    return load_scene(path.string());
}

std::string error_of(const std::string& text) {
    try {
        (void)parse_scene(text);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}
} // namespace

TEST_CASE("a record that samples the cosine reproduces the harmonic run to 1e-6 in F_m") {
    const ReducedParameters p{3, 100.0, 0.2, 0.3, 1.0};
    const long periods = 12;
    const int per_period = 400;
    std::vector<double> t, a;
    for (int k = 0; k <= per_period * (periods + 1); ++k) {
        t.push_back(static_cast<double>(k) / per_period);
        a.push_back(std::cos(2.0 * pi * t.back()));
    }
    const Dynamics harmonic(Chain::homogeneous(p), HarmonicForcing{1.0, 1.0});
    const Dynamics recorded(Chain::homogeneous(p), GroundMotion::record(t, a));
    const RunOptions o = fixed_step_run(periods, 1.0 / 2000.0);
    // A record has no forcing period and keeps its start; the harmonic run counts it too.
    RunOptions counted = o;
    counted.transient_periods = 0;
    const SimulationResult h = simulate(harmonic, counted);
    const SimulationResult r = simulate(recorded, o);
    CHECK(r.transient_periods_used == 0);
    REQUIRE(h.F_m > 0.1); // the row does hit: the comparison is about impact forces
    CHECK(std::abs(r.F_m - h.F_m) <= 1e-6 * h.F_m);
    for (int i = 0; i < 3; ++i)
        CHECK(std::abs(r.per_body[i].left - h.per_body[i].left) <= 1e-6 * h.F_m);
}

TEST_CASE("a record file in g, read through a physical scene, matches the harmonic scene") {
    const auto dir = std::filesystem::temp_directory_path() / "gapchain_test_ground_motion";
    std::filesystem::create_directories(dir);
    const double f = 1.0, a0 = 2.0, g = 9.80665; // f0 = 1 Hz for M = 1, K = 4 pi^2
    {
        std::ofstream csv(dir / "cosine.csv");
        csv << "# a sampled cosine\ntime_s,acc_g\n";
        csv.precision(17);
        for (int k = 0; k <= 400 * 10; ++k) {
            const double time = k / 400.0;
            csv << time << ',' << a0 / g * std::cos(2.0 * pi * f * time) << '\n';
        }
    }
    const std::string model =
        R"("units": "physical", "model": {"Nm": 2, "M": 1, "K": 39.47841760435743,
        "C": 1.0, "Kc": 2000, "e": 0.02})";
    const std::string run = R"("run": {"scheme": "rk4", "step": 0.0005, "estimate_error": false)";
    const Scene harmonic =
        parse_scene("{" + model + R"(, "excitation": {"a0": 2.0, "f": 1.0}, )" + run +
                    R"(, "periods": 10, "transient_periods": 0, "steady_state": false}})");
    const Scene recorded = load_scene_text_in(dir, "{" + model +
                                                       R"(, "excitation": {"type": "record",
        "file": "cosine.csv", "unit": "g"}, )" + run + "}}");
    CHECK(recorded.run.periods == 10);
    CHECK(recorded.physical->a0 == doctest::Approx(a0).epsilon(1e-12));
    CHECK(recorded.reduced.e_r == doctest::Approx(harmonic.reduced.e_r).epsilon(1e-12));
    const SimulationResult h = simulate(harmonic.dynamics(), harmonic.run);
    const SimulationResult r = simulate(recorded.dynamics(), recorded.run);
    REQUIRE(h.F_m > 0.1);
    CHECK(std::abs(r.F_m - h.F_m) <= 1e-6 * h.F_m);
    std::filesystem::remove_all(dir);
}

TEST_CASE("the synthetic motion's spectrum follows the Kanai-Tajimi shape") {
    KanaiTajimi kt;
    kt.ground_frequency = 2.5;
    kt.ground_damping = 0.6;
    kt.duration = 2000.0;
    kt.sample_interval = 0.01;
    kt.rise = 0.0;
    kt.hold = kt.duration; // stationary: the envelope is 1 throughout
    kt.seed = 7;
    const Accelerogram record = kanai_tajimi_accelerogram(kt, 3.0);
    CHECK(peak_ground_acceleration(record) == doctest::Approx(3.0).epsilon(1e-14));
    PsdOptions po;
    po.sample_rate = 1.0 / kt.sample_interval;
    po.segment_length = 1024;
    const Psd psd = welch_psd(record.acceleration, po);
    REQUIRE(psd.segments > 300);
    // Band averages of PSD / shape, each over +-0.4 Hz, must agree to within 10 % (the estimate
    // averages > 300 segments and ~8 bins: ~2 % scatter), from well below to well above f_g.
    // A filter that returned x or x' alone, or no filter, would miss by factors of 2 to 100.
    std::vector<double> ratios;
    for (double fc : {0.5, 1.0, 2.0, 2.5, 3.0, 4.0, 6.0, 9.0}) {
        double sum = 0.0;
        int count = 0;
        for (std::size_t k = 0; k < psd.frequency.size(); ++k) {
            if (std::abs(psd.frequency[k] - fc) > 0.4) continue;
            // The noise is held over each sample: its own spectrum falls as sinc^2.
            const double x = pi * psd.frequency[k] * kt.sample_interval;
            const double hold = x == 0.0 ? 1.0 : std::pow(std::sin(x) / x, 2);
            sum += psd.density[k] / (kanai_tajimi_shape(kt, psd.frequency[k]) * hold);
            ++count;
        }
        ratios.push_back(sum / count);
    }
    const double mean = std::accumulate(ratios.begin(), ratios.end(), 0.0) / ratios.size();
    for (double r : ratios)
        CHECK(r == doctest::Approx(mean).epsilon(0.10));
    // The shape is 1 at zero frequency and peaks near f_g.
    CHECK(kanai_tajimi_shape(kt, 0.0) == doctest::Approx(1.0));
    CHECK(kanai_tajimi_shape(kt, 2.3) > kanai_tajimi_shape(kt, 0.5));
}

TEST_CASE("the envelope and the seed behave as documented") {
    KanaiTajimi kt; // rise 2, hold 8, decay 0.5
    CHECK(envelope(kt, 1.0) == doctest::Approx(0.25));
    CHECK(envelope(kt, 5.0) == 1.0);
    CHECK(envelope(kt, 12.0) == doctest::Approx(std::exp(-1.0)));
    const Accelerogram a = kanai_tajimi_accelerogram(kt, 1.0);
    const Accelerogram b = kanai_tajimi_accelerogram(kt, 1.0);
    kt.seed = 2;
    const Accelerogram c = kanai_tajimi_accelerogram(kt, 1.0);
    CHECK(a.acceleration == b.acceleration);
    CHECK(a.acceleration != c.acceleration);
    CHECK(a.time.size() == 4001);
    CHECK(a.acceleration.front() == 0.0); // the envelope starts at 0
}

TEST_CASE("analyses that need a forcing period refuse a record, and so does exact") {
    const Dynamics dyn(Chain::homogeneous({2, 100.0, 0.2, 0.3, 1.0}),
                       GroundMotion::record({0.0, 1.0, 2.0}, {0.0, 1.0, 0.0}));
    RunOptions o;
    o.periods = 2;
    CHECK_THROWS_WITH_AS(PoincareSampler(dyn, SectionSpec{}, [](const SectionPoint&) {}),
                         doctest::Contains("harmonic"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(chain_lyapunov(dyn, o, 1), doctest::Contains("harmonic"),
                         std::invalid_argument);
    o.scheme = Scheme::exact;
    CHECK_THROWS_WITH_AS(simulate(dyn, o), doctest::Contains("harmonic"), std::invalid_argument);
    o.scheme = Scheme::automatic;
    const SimulationResult r = simulate(dyn, o);
    CHECK(r.scheme == Scheme::rk4);
    CHECK(!r.steady_state_period);
    // A record sampled far too finely for 1e9 steps per period names the record (it named
    // excitation.f_r, which a record scene has not).
    const Dynamics fine(Chain::homogeneous({2, 100.0, 0.2, 0.3, 1.0}),
                        GroundMotion::record({0.0, 1e-300, 2e-300}, {0.0, 1.0, 0.0}));
    CHECK_THROWS_WITH_AS(plan_step(fine, Scheme::rk4, 1e-4),
                         doctest::Contains("excitation.file: one natural period"),
                         std::invalid_argument);
}

TEST_CASE("bad ground-motion input names the key") {
    CHECK_THROWS_WITH_AS(GroundMotion::record({0.0, 1.0, 1.0}, {1.0, 0.0, 1.0}),
                         doctest::Contains("increase strictly"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(GroundMotion::record({0.0}, {1.0}), doctest::Contains("at least 2"),
                         std::invalid_argument);
    // Times before the run's start were dropped unseen: a record from -3 s to 0 s ran as silence.
    CHECK_THROWS_WITH_AS(GroundMotion::record({-3.0, -1.0, 0.0}, {1.0, 2.0, 1.0}),
                         doctest::Contains("times must be >= 0 (the run starts at t = 0)"),
                         std::invalid_argument);
    CHECK(error_of(R"({"excitation": {"type": "record", "file": "x.csv"}})").find("units") !=
          std::string::npos);
    const std::string physical = R"({"units": "physical", "excitation": {"type": "kanai_tajimi", )";
    CHECK(error_of(physical + R"("ground_damping": 0}})").find("excitation.ground_damping") !=
          std::string::npos);
    CHECK(error_of(physical + R"("f": 2}})").find("excitation.f") != std::string::npos);
    CHECK(error_of(physical + R"("sample_interval": 0.5}})").find("excitation.sample_interval") !=
          std::string::npos);
    CHECK(error_of(physical + R"("seed": 1}, "run": {"periods": 10}})").find("run.periods") !=
          std::string::npos);
    CHECK(error_of(R"({"units": "physical", "excitation": {"type": "record"}})")
              .find("excitation.file") != std::string::npos);
    CHECK(error_of(R"({"units": "physical", "excitation": {"type": "record", "file":
        "/nonexistent/record.csv"}})")
              .find("cannot read") != std::string::npos);
}
