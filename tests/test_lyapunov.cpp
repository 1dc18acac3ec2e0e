#include "gapchain/lyapunov.hpp"
#include "gapchain/orbit.hpp"
#include "gapchain/signal.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

using namespace gapchain;
using std::numbers::pi;

namespace {
struct Lorenz final : TangentSystem {
    int dimension() const override { return 3; }
    void rhs(double, const double* y, double* f) const override {
        f[0] = 10 * (y[1] - y[0]);
        f[1] = y[0] * (28 - y[2]) - y[1];
        f[2] = y[0] * y[1] - 8.0 / 3.0 * y[2];
    }
    void jacobian(double, const double* y, double* j) const override {
        const double m[9] = {-10, 10, 0, 28 - y[2], -1, -y[0], y[1], y[0], -8.0 / 3.0};
        for (int i = 0; i < 9; ++i)
            j[i] = m[i];
    }
};
/// y' = -(1 + a e^(-t / tau) + b sin(2 pi t)) y: the exponent is -1, and a finite window
/// starting at 0 averages the decaying term in, a bias of a tau (1 - e^(-T / tau)) / T.
struct DecayingRate final : TangentSystem {
    double a = 0.0, tau = 1.0, b = 0.0;
    int dimension() const override { return 1; }
    double rate(double t) const { return -(1 + a * std::exp(-t / tau) + b * std::sin(2 * pi * t)); }
    void rhs(double t, const double* y, double* f) const override { f[0] = rate(t) * y[0]; }
    void jacobian(double t, const double*, double* j) const override { j[0] = rate(t); }
};
const ReducedParameters fig13_chaotic{5, 60, 0.5, 0.06, 3.3};
} // namespace

TEST_CASE("Lorenz 63: (0.9056, 0, -14.5723) within 1 %") {
    LyapunovOptions o;
    o.step = 0.005;
    o.transient = 50;
    o.duration = 1000;
    const LyapunovResult r = lyapunov_spectrum(Lorenz{}, {1, 1, 1}, o);
    CHECK(r.exponents[0] == doctest::Approx(0.9056).epsilon(0.01));
    CHECK(std::abs(r.exponents[1]) < 0.01);
    CHECK(r.exponents[2] == doctest::Approx(-14.5723).epsilon(0.01));
    CHECK(r.sum == doctest::Approx(-(10 + 1 + 8.0 / 3.0)).epsilon(1e-3)); // trace
}

TEST_CASE("chaotic row: exponents sum to -4 pi eps Nm and pair up about -2 pi eps") {
    const Dynamics dyn = Dynamics::paper_row(fig13_chaotic);
    RunOptions o;
    o.periods = 700;
    o.transient_periods = 100;
    const LyapunovResult r = chain_lyapunov(dyn, o, 10);
    const double eps = fig13_chaotic.eps;
    CHECK(r.exponents[0] > 0.3); // chaotic
    CHECK(r.exponents[0] > 5 * r.errors[0]);
    CHECK(r.sum == doctest::Approx(-4 * pi * eps * 5).epsilon(1e-6));
    // With damping proportional to mass the tangent flow is e^{-2 pi eps t} times a symplectic
    // one, so the spectrum is symmetric about -2 pi eps. Exponents from QR over a finite record
    // pair up to O(1/T) only, by an amount that depends on the realisation: 3e-4, 1.4e-4 and
    // 6.6e-5 on the leading pairs at 600, 1300 and 2700 recorded periods of this row (3e-6,
    // 1.5e-6, 7e-7 on another realisation of the same chaos, before two grazes were resolved).
    for (int k = 0; k < 5; ++k)
        CHECK(r.exponents[k] + r.exponents[9 - k] == doctest::Approx(-4 * pi * eps).epsilon(2e-4));
}

TEST_CASE("no contact: every exponent is -2 pi eps") {
    const ReducedParameters p{3, 60, 0.3, 100.0, 1.3};
    const Dynamics dyn = Dynamics::paper_row(p);
    RunOptions o;
    o.periods = 3000;
    o.transient_periods = 10;
    const LyapunovResult r = chain_lyapunov(dyn, o, 6);
    for (double l : r.exponents)
        CHECK(l == doctest::Approx(-2 * pi * p.eps).epsilon(2e-3));
    CHECK(r.sum == doctest::Approx(-4 * pi * p.eps * 3).epsilon(1e-9));
}

TEST_CASE("no contact, overdamped: exponents -2 pi (eps +- sqrt(eps^2 - 1)), however far apart") {
    // The fast and slow roots of each body are 2 pi (eps + sqrt(eps^2 - 1)) and its reciprocal
    // apart: at eps = 5, 62 per unit time, beyond the doubles' 36 over one forcing period, and
    // more at f_r = 0.3. Re-orthonormalised once a period, lambda_6..10 came out -37 +- 0.2
    // (eps = 5, f_r = 1), and eps = 5 on the mirror pair failed as "non-finite".
    for (const double f_r : {1.0, 0.3}) {
        const ReducedParameters p{5, 100, 5.0, 100.0, f_r};
        const Dynamics dyn = Dynamics::paper_row(p);
        RunOptions o;
        o.periods = 60;
        o.transient_periods = 15;
        const LyapunovResult r = chain_lyapunov(dyn, o, 10);
        REQUIRE(r.status == RunStatus::completed);
        const double root = std::sqrt(p.eps * p.eps - 1.0);
        for (int k = 0; k < 5; ++k) {
            CHECK(r.exponents[k] == doctest::Approx(-2 * pi * (p.eps - root)).epsilon(1e-6));
            CHECK(r.exponents[k + 5] == doctest::Approx(-2 * pi * (p.eps + root)).epsilon(1e-6));
        }
        CHECK(r.sum == doctest::Approx(-4 * pi * p.eps * 5).epsilon(1e-9));
        // Several re-orthonormalisations a period still leave 10 averaged periods unestimated
        // (the blocks counted them and gave "+- 1e-16").
        o.periods = 25;
        CHECK(std::isinf(chain_lyapunov(dyn, o, 10).errors.front()));
    }
}

TEST_CASE("a row of unequal damping: the sum is the trace, -sum of the damping rates") {
    // The expected sum was -4 pi eps Nm from the scene's eps, whatever the damping array.
    Chain chain = Chain::homogeneous({3, 60, 0.5, 0.06, 3.3});
    chain.damping = {0.5, 2.0, 4.0};
    const Dynamics dyn(chain, HarmonicForcing{3.3, 1.0});
    RunOptions o;
    o.periods = 200;
    const LyapunovResult r = chain_lyapunov(dyn, o, 6);
    CHECK(r.expected_sum == -6.5);
    CHECK(r.sum == doctest::Approx(-6.5).epsilon(1e-9));
    CHECK(std::isnan(chain_lyapunov(dyn, o, 2).expected_sum));
}

TEST_CASE("the time-series estimate is within 10 % of the tangent-space exponent") {
    const Dynamics dyn = Dynamics::paper_row(fig13_chaotic);
    RunOptions o;
    o.periods = 4200;
    o.transient_periods = 200;
    const LyapunovResult tangent = chain_lyapunov(dyn, o, 1);
    RunOutcome outcome;
    // u_1 four times per period (delay one quarter period), embedding 4, 15-period horizon.
    const Signal u1 = record_signal(dyn, o, SectionVariable{}, 4, outcome);
    TimeSeriesOptions ts;
    ts.embedding = 4;
    ts.delay = 1;
    ts.horizon = 60;
    ts.min_separation = 8;
    ts.max_points = 6000;
    const TimeSeriesExponent r = largest_exponent_from_series(u1.values, 1.0 / u1.sample_rate, ts);
    MESSAGE("time series " << r.lambda << " +- " << r.error << ", tangent "
                           << tangent.exponents[0]);
    CHECK(r.lambda == doctest::Approx(tangent.exponents[0]).epsilon(0.10));
}

TEST_CASE("run.max_work counts the tangent vectors: all 2 Nm exponents of a long row are refused "
          "before the run, one is not") {
    const Dynamics dyn = Dynamics::paper_row({100, 100, 0.5, 0.5, 1.0});
    RunOptions o;
    o.periods = 2;
    const long row_work = 100L * PlannedRun(dyn, o).plan().steps_per_period * 2;
    o.max_work = 20.0 * row_work; // the row alone: 1/20 of it; with 200 vectors: 10 times it
    CHECK_THROWS_WITH_AS(chain_lyapunov(dyn, o, 200), doctest::Contains("200 tangent vectors"),
                         std::invalid_argument);
    CHECK(chain_lyapunov(dyn, o, 1).status == RunStatus::completed);
}

TEST_CASE("a run with all 2 Nm tangent vectors asks its progress callback inside a period") {
    // Nm = 60 with 120 vectors: ~36 steps between asks, not ~4400 (more than the period's
    // steps: asked once, at its end), so that a long row's Lyapunov run stops within ~0.03 s.
    const Dynamics dyn = Dynamics::paper_row({60, 100, 0.5, 0.5, 1.0});
    RunOptions o;
    o.periods = 1;
    o.transient_periods = 0;
    o.scheme = Scheme::rk4;
    long asks = 0;
    chain_lyapunov(dyn, o, 120, {}, [&](double) {
        ++asks;
        return true;
    });
    CHECK(asks > 5);
}

TEST_CASE("auto: the exponent of a stable orbit through stiff contacts is its Floquet exponent") {
    // Fig 13's row at fc = 1e5, a stable period-1 orbit. rk4 at the default tolerance gave
    // -2.937 +- 0.006: its trajectory through contacts this stiff biases the exact tangent flow
    // it carries (at fc = 3e6 it gave +0.24). auto now takes the exact propagator.
    const ReducedParameters p{5, 1e5, 0.5, 0.06, 3.0};
    const Dynamics dyn = Dynamics::paper_row(p);
    OrbitOptions orbit;
    const PeriodicOrbit found = find_periodic_orbit_after(dyn, orbit, {}, 200);
    REQUIRE(found.status == OrbitStatus::converged);
    REQUIRE(found.max_multiplier < 1.0);
    const double floquet = std::log(found.max_multiplier) * p.f_r / found.period;
    RunOptions o;
    o.periods = 300;
    o.transient_periods = 30;
    const LyapunovResult r = chain_lyapunov(dyn, o, 1);
    MESSAGE("lambda_1 " << r.exponents[0] << " +- " << r.errors[0] << ", Floquet " << floquet);
    CHECK(std::abs(r.exponents[0] - floquet) < 0.02);
}

TEST_CASE("a tangent run on rk4 through contacts exact does not take keeps to 1e-6") {
    // Fig 13's row at fc = 2e8, beyond the exact scheme's reach: auto runs rk4. At the default
    // tolerance 1e-4 its trajectory's contact times put the stable orbit's largest multiplier
    // at 26 (rk8pd: 0.351) and lambda_1 at +10.0; the tangent run's tolerance is now at most
    // 1e-6. The reference is Newton's orbit on rk8pd at 1e-10, an independent scheme (its
    // largest multiplier is the contact-free decay's, exp(-pi / f_r) to 5 digits).
    const ReducedParameters p{5, 2e8, 0.5, 0.06, 3.0};
    const Dynamics dyn = Dynamics::paper_row(p);
    OrbitOptions orbit;
    orbit.scheme = Scheme::rk8pd;
    orbit.integration_tolerance = 1e-10;
    const PeriodicOrbit found = find_periodic_orbit_after(dyn, orbit, {}, 10);
    REQUIRE(found.status == OrbitStatus::converged);
    const double floquet = std::log(found.max_multiplier) * p.f_r / found.period;
    RunOptions o;
    o.periods = 30;
    o.transient_periods = 10;
    CHECK(tangent_run_options(dyn, o).scheme != Scheme::exact);
    CHECK(tangent_run_options(dyn, o).tolerance == max_tangent_run_tolerance);
    const LyapunovResult r = chain_lyapunov(dyn, o, 1);
    MESSAGE("lambda_1 " << r.exponents[0] << " +- " << r.errors[0] << ", Floquet " << floquet);
    CHECK(r.exponents[0] < 0.0);
    CHECK(std::abs(r.exponents[0] - floquet) < 3.0 * r.errors[0] + 0.1);
}

TEST_CASE("a window whose rates drift gets the drift as its error, and says so") {
    LyapunovOptions o;
    o.step = 0.01;
    o.duration = 100;
    DecayingRate slow;
    slow.a = 0.5;
    slow.tau = 30;
    const LyapunovResult r = lyapunov_spectrum(slow, {1}, o);
    const double bias = slow.a * slow.tau * (1 - std::exp(-o.duration / slow.tau)) / o.duration;
    CHECK(r.exponents[0] == doctest::Approx(-1 - bias).epsilon(1e-6));
    CHECK(r.drifting);
    // The standard error over the blocks alone, 0.042, missed the bias of 0.145.
    CHECK(std::abs(r.exponents[0] + 1) <= r.errors[0]);
    CHECK(r.errors[0] <= 3 * bias);
    // Whole periods of a modulation a block, and no decay: equal blocks, no drift.
    DecayingRate steady;
    steady.b = 0.5;
    const LyapunovResult s = lyapunov_spectrum(steady, {1}, o);
    CHECK_FALSE(s.drifting);
    CHECK(s.exponents[0] == doctest::Approx(-1).epsilon(1e-9));
    CHECK(s.errors[0] < 1e-9);
}
