#include "gapchain/dynamics.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace gapchain;

namespace {
std::vector<double> random_state(int n, unsigned seed, double scale) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> d(-scale, scale);
    std::vector<double> y(2 * n);
    for (auto& x : y)
        x = d(gen);
    return y;
}
// Every Jacobian entry against central finite differences of the right-hand side, at random
// states (almost surely off the contact kinks).
void check_jacobian_by_differences(const Dynamics& dyn, unsigned first_seed, unsigned last_seed) {
    const int dim = dyn.dimension();
    std::vector<double> jac, fp(dim), fm(dim);
    for (unsigned seed = first_seed; seed <= last_seed; ++seed) {
        auto y = random_state(dyn.bodies(), seed, 0.6);
        dyn.jacobian(y.data(), jac);
        for (int c = 0; c < dim; ++c) {
            const double h = 1e-7;
            auto yp = y, ym = y;
            yp[c] += h;
            ym[c] -= h;
            dyn.rhs(0.3, yp.data(), fp.data());
            dyn.rhs(0.3, ym.data(), fm.data());
            for (int r = 0; r < dim; ++r)
                CHECK((fp[r] - fm[r]) / (2 * h) ==
                      doctest::Approx(jac[r * dim + c]).epsilon(1e-5).scale(100));
        }
    }
}
} // namespace

TEST_CASE("Jacobian trace is -4 pi eps Nm at every state (MODEL.md §5)") {
    const ReducedParameters p{6, 200, 0.3, 0.05, 2.0};
    const Dynamics dyn = Dynamics::paper_row(p);
    std::vector<double> jac;
    for (unsigned seed = 1; seed <= 20; ++seed) {
        const auto y = random_state(p.Nm, seed, 0.5);
        dyn.jacobian(y.data(), jac);
        double trace = 0.0;
        for (int i = 0; i < dyn.dimension(); ++i)
            trace += jac[i * dyn.dimension() + i];
        CHECK(trace == doctest::Approx(-4 * std::numbers::pi * p.eps * p.Nm).epsilon(1e-13));
    }
}

TEST_CASE("Jacobian matches central finite differences of the right-hand side") {
    const ReducedParameters p{4, 50, 0.2, 0.1, 1.3};
    check_jacobian_by_differences(Dynamics::paper_row(p), 3, 8);
}

TEST_CASE("gaps, forces and the sign convention of MODEL.md §2") {
    const ReducedParameters p{3, 100, 0.5, 0.1, 1.0};
    const Dynamics dyn = Dynamics::paper_row(p);
    // Body 1 pushed 0.3 into the left wall; bodies 2 and 3 pressed together by 0.2.
    std::vector<double> y{-0.4, 0.25, -0.05, 0, 0, 0};
    CHECK(dyn.gap(0, y.data()) == doctest::Approx(0.3));
    CHECK(dyn.gap(2, y.data()) == doctest::Approx(0.2));
    CHECK(dyn.gap(1, y.data()) < 0.0);
    CHECK(dyn.force(0, y.data()) == doctest::Approx(std::sqrt(100.0) * 0.3)); // sqrt(fc) p
    CHECK(dyn.force(2, y.data()) == doctest::Approx(std::sqrt(100.0) / 2 * 0.2));
    std::vector<double> a(3);
    dyn.acceleration(0.0, y.data(), y.data() + 3, a.data());
    const double c = 4 * std::numbers::pi * std::numbers::pi;
    CHECK(a[0] == doctest::Approx(-c * -0.4 + c * 100 * 0.3));
    CHECK(a[1] == doctest::Approx(-c * 0.25 - c * 50 * 0.2));
    CHECK(a[2] == doctest::Approx(-c * -0.05 + c * 50 * 0.2));
}

TEST_CASE("penetration_at_force inverts the elastic laws: sqrt(fc) p (linear), sqrt(fc) p^1.5 "
          "(Hertz)") {
    const ReducedParameters p{3, 100, 0.5, 0.1, 1.0};
    Chain chain = Chain::homogeneous(p);
    const Dynamics linear(chain, HarmonicForcing{p.f_r});
    chain.law = ContactLaw::hertz;
    const Dynamics hertz(chain, HarmonicForcing{p.f_r});
    // Wall j = 0 has gain sqrt(fc) = 10, body-body j = 1 half of it (MODEL.md §2).
    CHECK(linear.penetration_at_force(0, 3.0) == doctest::Approx(0.3));
    CHECK(linear.penetration_at_force(1, 3.0) == doctest::Approx(0.6));
    CHECK(hertz.penetration_at_force(0, 10.0 * std::pow(0.3, 1.5)) == doctest::Approx(0.3));
    CHECK(hertz.penetration_at_force(1, 5.0 * std::pow(0.6, 1.5)) == doctest::Approx(0.6));
    CHECK(linear.penetration_at_force(0, 0.0) == 0.0);
    CHECK(hertz.penetration_at_force(2, -1.0) == 0.0);
    for (double q : {1e-6, 0.01, 0.7, 5.0})
        CHECK(hertz.force_at_penetration(3, hertz.penetration_at_force(3, q)) ==
              doctest::Approx(q).epsilon(1e-14));
}

TEST_CASE("energy rate equals minus the damping power plus the forcing power") {
    const ReducedParameters p{5, 80, 0.4, 0.05, 1.0};
    const Dynamics dyn = Dynamics::paper_row(p);
    auto y = random_state(p.Nm, 11, 0.4);
    std::vector<double> f(dyn.dimension());
    const double t = 0.17;
    dyn.rhs(t, y.data(), f.data());
    // dE/dt along the flow by a directional finite difference.
    const double h = 1e-7;
    auto yp = y, ym = y;
    for (int i = 0; i < dyn.dimension(); ++i) {
        yp[i] += h * f[i];
        ym[i] -= h * f[i];
    }
    const double dEdt = (dyn.energy(yp.data()) - dyn.energy(ym.data())) / (2 * h);
    double expected = 0.0;
    for (int i = 0; i < p.Nm; ++i) {
        const double v = y[p.Nm + i];
        expected += -4 * std::numbers::pi * p.eps * v * v + dyn.ground(t) * v;
    }
    CHECK(dEdt == doctest::Approx(expected).epsilon(1e-6));
}

TEST_CASE("Hertz law: the Jacobian matches finite differences of the right-hand side") {
    Chain c = Chain::homogeneous({4, 50, 0.2, 0.05, 1.3});
    c.law = ContactLaw::hertz;
    check_jacobian_by_differences(Dynamics(c, {1.3, 1.0}), 20, 24);
    // Hunt-Crossley adds velocity columns (alpha 0.4 keeps 1 + alpha g' > 0 at these states).
    c.law = ContactLaw::hunt_crossley;
    c.contact_damping = 0.4;
    check_jacobian_by_differences(Dynamics(c, {1.3, 1.0}), 20, 24);
}

TEST_CASE("Hunt-Crossley: the jerk is the time derivative of the accelerations") {
    Chain c = Chain::homogeneous({3, 80, 0.1, 0.05, 1.0});
    c.law = ContactLaw::hunt_crossley;
    c.contact_damping = 0.3;
    const Dynamics dyn(c, {1.0, 1.0});
    for (unsigned seed = 30; seed < 34; ++seed) {
        const auto y = random_state(3, seed, 0.6);
        std::vector<double> f(6), a(3), jerk(3), fp(6), fm(6);
        dyn.rhs(0.2, y.data(), f.data());
        std::copy(f.begin() + 3, f.end(), a.begin());
        dyn.acceleration_rate(0.2, y.data(), a.data(), jerk.data());
        // Along the flow: y(t +- h) ~ y +- h f; the accelerations' central difference.
        const double h = 1e-6;
        auto yp = y, ym = y;
        for (int k = 0; k < 6; ++k) {
            yp[k] += h * f[k];
            ym[k] -= h * f[k];
        }
        dyn.rhs(0.2 + h, yp.data(), fp.data());
        dyn.rhs(0.2 - h, ym.data(), fm.data());
        for (int i = 0; i < 3; ++i)
            CHECK((fp[3 + i] - fm[3 + i]) / (2 * h) ==
                  doctest::Approx(jerk[i]).epsilon(1e-5).scale(10));
    }
}
