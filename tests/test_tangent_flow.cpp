#include "gapchain/observers.hpp"
#include "gapchain/tangent_flow.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

using namespace gapchain;
using std::numbers::pi;

namespace {
// One body between the walls, e_r = 0.5: the right wall's gap is u - 0.5.
const ReducedParameters one_body{1, 60, 0.1, 0.5, 1.0};

/// The state transition matrix over time h of x'' + c x' + k x = 0 (underdamped), row-major
/// [[du/du0, du/dv0], [dv/du0, dv/dv0]]: the closed-form solution, independent of the code.
std::array<double, 4> oscillator_flow(double k, double c, double h) {
    const double a = 0.5 * c;
    const double b = std::sqrt(k - a * a);
    const double e = std::exp(-a * h), cs = std::cos(b * h), sn = std::sin(b * h);
    return {e * (cs + a / b * sn), e * sn / b, -e * k / b * sn, e * (cs - a / b * sn)};
}

/// One step of the tangent flow of two vectors (the identity) from y0 to y1, unscaled,
/// row-major as oscillator_flow() (unscaled_matrix() is column-major).
std::array<double, 4> one_step(const Dynamics& dyn, std::array<double, 2> y0,
                               std::array<double, 2> y1, double h) {
    TangentFlow flow(dyn, 2);
    flow.on_step(StepView{0.0, h, y0.data(), y1.data(), 0, true});
    const std::vector<double> m = flow.unscaled_matrix();
    return {m[0], m[2], m[1], m[3]};
}

void check_equal(const std::array<double, 4>& got, const std::array<double, 4>& expected) {
    for (int i = 0; i < 4; ++i)
        CHECK(got[i] == doctest::Approx(expected[i]).epsilon(1e-12).scale(1.0));
}

double determinant(std::vector<double> m, int n) {
    // Gaussian elimination with partial pivoting, column-major n x n.
    double det = 1.0;
    auto at = [&](int r, int c) -> double& { return m[static_cast<std::size_t>(c) * n + r]; };
    for (int c = 0; c < n; ++c) {
        int pivot = c;
        for (int r = c + 1; r < n; ++r)
            if (std::abs(at(r, c)) > std::abs(at(pivot, c))) pivot = r;
        if (pivot != c) {
            for (int k = 0; k < n; ++k)
                std::swap(at(c, k), at(pivot, k));
            det = -det;
        }
        det *= at(c, c);
        for (int r = c + 1; r < n; ++r) {
            const double f = at(r, c) / at(c, c);
            for (int k = c; k < n; ++k)
                at(r, k) -= f * at(c, k);
        }
    }
    return det;
}
} // namespace

TEST_CASE("between switches the flow is the exact exponential of the open or closed oscillator") {
    const Dynamics dyn = Dynamics::paper_row(one_body);
    const double k_free = 4 * pi * pi, c = 4 * pi * one_body.eps;
    const double k_closed = k_free * (1 + one_body.fc); // the wall's Kc = fc K in series with K
    const double h = 0.01;
    // Open: the body well inside the clearance.
    check_equal(one_step(dyn, {0.1, 0.3}, {0.103, 0.3}, h), oscillator_flow(k_free, c, h));
    // Closed: the body into the right wall over the whole step.
    check_equal(one_step(dyn, {0.51, 0.2}, {0.512, 0.1}, h), oscillator_flow(k_closed, c, h));
}

TEST_CASE("an overdamped body's long step is its exact exponential too") {
    // eps = 100: the real rates are 2 pi (eps -+ sqrt(eps^2 - 1)), 0.0314 and 1257; a step of
    // 0.05 has h rate = 63, where a single Taylor series of exp(h J) is lost to cancellation.
    const Dynamics dyn = Dynamics::paper_row({1, 60, 100.0, 0.5, 1.0});
    const double h = 0.05, root = std::sqrt(100.0 * 100.0 - 1.0);
    const double l1 = -2 * pi * (100.0 - root), l2 = -2 * pi * (100.0 + root);
    const double e1 = std::exp(l1 * h), e2 = std::exp(l2 * h), d = l1 - l2;
    const std::array<double, 4> expected{(l1 * e2 - l2 * e1) / d, (e1 - e2) / d,
                                         l1 * l2 * (e2 - e1) / d, (l1 * e1 - l2 * e2) / d};
    const auto got = one_step(dyn, {0.1, 0.0}, {0.1, 0.0}, h);
    for (int i = 0; i < 4; ++i)
        CHECK(got[i] == doctest::Approx(expected[i]).epsilon(1e-12).scale(1.0));
}

TEST_CASE("a contact that closes and opens within one step counts as closed over it") {
    // Both ends lie on the switch (gap 0). The mean of the end gaps is 0 and says nothing; the
    // cubic Hermite interpolant's midpoint, g(h/2) = h (g'(0) - g'(h)) / 8, says where the gap
    // went in between. Each case fails if the contact set is read from the ends alone.
    const Dynamics dyn = Dynamics::paper_row(one_body);
    const double k_free = 4 * pi * pi, c = 4 * pi * one_body.eps;
    const double k_closed = k_free * (1 + one_body.fc);
    const double h = 0.01;
    const auto closed = oscillator_flow(k_closed, c, h);
    const auto open = oscillator_flow(k_free, c, h);
    REQUIRE(std::abs(closed[2] - open[2]) > 1.0); // the two are told apart

    SUBCASE("struck and released: closed") {
        check_equal(one_step(dyn, {0.5, 0.4}, {0.5, -0.4}, h), closed);
    }
    SUBCASE("released and struck again: open") {
        check_equal(one_step(dyn, {0.5, -0.4}, {0.5, 0.4}, h), open);
    }
    SUBCASE("the left wall, whose gap is -u - e_r, and a small graze") {
        check_equal(one_step(dyn, {-0.5, -1e-3}, {-0.5, 1e-3}, h), closed);
    }
}

TEST_CASE("through a run with impacts the flow's determinant is exp(-4 pi eps Nm t)") {
    // Liouville (MODEL.md §5): the divergence of the vector field is the trace of the damping,
    // -4 pi eps per body, whatever the contact set; every switch is a piece boundary of the
    // flow, so a wrong contact set or a missed switch shows only in the entries, but a wrong
    // exponential or a lost piece shows here.
    const ReducedParameters p{3, 60, 0.2, 0.05, 2.0};
    const Dynamics dyn = Dynamics::paper_row(p);
    RunOptions o;
    o.periods = 6;
    o.transient_periods = 0;
    o.stop_at_steady_state = false;
    o.estimate_error = false;
    o.multistability_check = false;
    PlannedRun planned(dyn, o);
    TangentFlow flow(dyn, dyn.dimension());
    MaxForceTracker forces(dyn);
    Observer* observers[] = {&flow, &forces};
    planned.run(observers);
    REQUIRE(forces.max_force() > 0.0); // the run had impacts
    const double t = o.periods / p.f_r;
    const double det = determinant(flow.unscaled_matrix(), dyn.dimension());
    REQUIRE(det > 0.0);
    CHECK(std::log(det) == doctest::Approx(-4 * pi * p.eps * p.Nm * t).epsilon(1e-10));
}

TEST_CASE("bad arguments are refused") {
    const Dynamics dyn = Dynamics::paper_row(one_body);
    CHECK_THROWS_AS(TangentFlow(dyn, 0), std::invalid_argument);
    CHECK_THROWS_AS(TangentFlow(dyn, 3), std::invalid_argument);
    Chain hertz = Chain::homogeneous(one_body);
    hertz.law = ContactLaw::hertz;
    const Dynamics hertz_row(hertz, HarmonicForcing{1.0});
    CHECK_THROWS_AS(TangentFlow(hertz_row, 2), std::invalid_argument);
}
