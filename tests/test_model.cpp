#include "gapchain/model.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

using namespace gapchain;

TEST_CASE("physical -> reduced -> physical round trip") {
    PhysicalParameters q{7, 2.5, 3.0e4, 150.0, 1.2e7, 3.5e-3, 9.81, 12.0};
    const ReducedParameters r = to_reduced(q);
    const double f0 = std::sqrt(q.K / q.M) / (2 * std::numbers::pi);
    CHECK(r.Nm == 7);
    CHECK(r.fc == doctest::Approx(q.Kc / q.K).epsilon(1e-14));
    CHECK(r.eps == doctest::Approx(q.C / (2 * std::sqrt(q.K * q.M))).epsilon(1e-14));
    CHECK(r.f_r == doctest::Approx(q.f / f0).epsilon(1e-14));
    CHECK(r.e_r == doctest::Approx(4 * std::numbers::pi * std::numbers::pi * f0 * f0 * q.e / q.a0)
                       .epsilon(1e-14));
    const PhysicalParameters back = to_physical(r, q.M, q.K, q.a0);
    CHECK(back.C == doctest::Approx(q.C).epsilon(1e-12));
    CHECK(back.Kc == doctest::Approx(q.Kc).epsilon(1e-12));
    CHECK(back.e == doctest::Approx(q.e).epsilon(1e-12));
    CHECK(back.f == doctest::Approx(q.f).epsilon(1e-12));
    // F_phys = F_r M a0 sqrt(fc)
    CHECK(force_in_newtons(2.0, q) == doctest::Approx(2.0 * 2.5 * 9.81 * std::sqrt(400.0)));
}

TEST_CASE("eps where K M underflows: tiny K and M (their ranges keep K M below 1e27)") {
    // K M = 1e-400 underflowed to 0 and eps came out inf (refused) for a row whose eps is 5.
    const PhysicalParameters tiny{3, 1e-200, 1e-200, 1e-199, 1e-195, 3.5e-3, 10.0, 1e-3};
    CHECK(to_reduced(tiny).eps == doctest::Approx(5.0).epsilon(1e-14));
    CHECK(to_physical(to_reduced(tiny), tiny.M, tiny.K, tiny.a0).C ==
          doctest::Approx(tiny.C).epsilon(1e-13));
}

TEST_CASE("Table 4 experiment: e_r from the physical clearance") {
    // e_r = 4 pi^2 f0^2 e / a0 = 0.22 with e = 3.5 mm and a0 = 10 m/s^2 means f0 = 3.99 Hz.
    const double f0 = std::sqrt(0.22 * 10.0 / 3.5e-3) / (2 * std::numbers::pi);
    const double K = 1.0e5, M = K / std::pow(2 * std::numbers::pi * f0, 2);
    PhysicalParameters q{46, M, K, 2 * 0.1 * std::sqrt(K * M), 559 * K, 3.5e-3, 10.0, f0};
    const ReducedParameters r = to_reduced(q);
    CHECK(r.e_r == doctest::Approx(0.22).epsilon(1e-12));
    CHECK(r.eps == doctest::Approx(0.1).epsilon(1e-12));
    CHECK(r.fc == doctest::Approx(559).epsilon(1e-12));
    CHECK(r.f_r == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("validation names the key and the range") {
    auto message = [](ReducedParameters p) {
        try {
            validate(p);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(message({0, 1, 0.5, 0.1, 1}).find("model.Nm") != std::string::npos);
    CHECK(message({3, 0, 0.5, 0.1, 1}).find("model.fc") != std::string::npos);
    CHECK(message({3, 1, -0.1, 0.1, 1}).find("model.eps") != std::string::npos);
    CHECK(message({3, 1, 0.5, -1, 1}).find("model.e_r") != std::string::npos);
    CHECK(message({3, 1, 0.5, 0.1, 0}).find("excitation.f_r") != std::string::npos);
    CHECK(message({3, 1, NAN, 0.1, 1}).find("finite") != std::string::npos);
    CHECK(message({3, INFINITY, 0.5, 0.1, 1}).find("model.fc") != std::string::npos);
    CHECK(message({3, 1, 0.5, 0.1, 1}).empty());
}

TEST_CASE("homogeneous chain: walls fc, body-body fc/2 (MODEL.md §1)") {
    const Chain c = Chain::homogeneous({4, 60, 0.5, 0.06, 3});
    REQUIRE(c.bodies() == 4);
    REQUIRE(c.gaps() == 5);
    CHECK(c.contact[0] == 60);
    CHECK(c.contact[4] == 60);
    for (int j = 1; j < 4; ++j)
        CHECK(c.contact[j] == 30);
    CHECK(c.force_scale == doctest::Approx(std::sqrt(60.0)));
    // Gershgorin bound of MODEL.md §4: 2 pi sqrt(1 + 2 fc).
    CHECK(max_angular_frequency(c) ==
          doctest::Approx(2 * std::numbers::pi * std::sqrt(1 + 2 * 60.0)).epsilon(1e-14));
    Chain bad = c;
    bad.clearance.pop_back();
    CHECK_THROWS_AS(validate(bad), std::invalid_argument);
}
