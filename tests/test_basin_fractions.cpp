#include "gapchain/basin_fractions.hpp"

#include "gapchain/report.hpp"
#include "gapchain/scene.hpp"

#include "attractor_searches.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

using namespace gapchain;
using test::short_runs;

TEST_CASE("a line reports each value as it is done, and a cancelled line keeps those values") {
    AttractorOptions o = short_runs(8, 1);
    o.run.periods = 300;
    const ReducedParameters base{5, 60, 0.5, 0.06, 3.0};
    std::vector<std::size_t> reported;
    std::vector<double> reported_values;
    const FractionContinuation c = continue_basin_fractions(
        base, SweptParameter::f_r, {3.0, 3.01, 3.02, 3.03}, o,
        [&](double) { return reported.size() < 2; }, // Ctrl-C once two values were shown
        [&](const FractionContinuation& line) {
            reported.push_back(line.values.size());
            reported_values.push_back(line.values.back());
            CHECK(line.sets.size() == line.values.size());
            CHECK(line.labels.size() == line.values.size());
            CHECK(line.labels.back().size() == line.sets.back().attractors.size());
        });
    CHECK(c.cancelled);
    CHECK(reported == std::vector<std::size_t>{1, 2});
    CHECK(c.values == reported_values);
    CHECK(c.sets.size() == 2);
    CHECK(fractions_csv(c).find("\n3.02") == std::string::npos);
}

TEST_CASE("a label follows an attractor along the line, even one that moved more than 0.2 A") {
    // Fig 13's line: the period-1 orbit (F_m 0.386) holds 77 % of the starts at f_r = 3.1 and
    // 65 % at 3.15, but its state at phase 0 moves by more than the centroid test's 0.2 A.
    AttractorOptions o = short_runs(30, 1);
    o.box = 1.0;
    o.run.periods = 1500;
    o.run.transient_periods = 750;
    const ReducedParameters base{5, 60, 0.5, 0.06, 3.1};
    const FractionContinuation c =
        continue_basin_fractions(base, SweptParameter::f_r, {3.1, 3.15}, o);
    REQUIRE(c.sets.size() == 2);
    std::vector<const Attractor*> period_one;
    std::vector<int> label;
    for (std::size_t k = 0; k < 2; ++k) {
        const auto& as = c.sets[k].attractors;
        const auto it = std::find_if(as.begin(), as.end(), [](const Attractor& a) {
            return a.period == 1 && a.newton_confirmed && a.F_m > 0.38;
        });
        REQUIRE(it != as.end());
        period_one.push_back(&*it);
        label.push_back(c.labels[k][static_cast<std::size_t>(it - as.begin())]);
    }
    CHECK(period_one[1]->F_m == doctest::Approx(period_one[0]->F_m).epsilon(0.01));
    double moved = 0.0; // scaled as the matching does: u by A, v by 2 pi f_r A
    for (int i = 0; i < 10; ++i) {
        const auto unit = [&](std::size_t k) {
            return c.sets[k].amplitude * (i < 5 ? 1.0 : 2.0 * std::numbers::pi * c.values[k]);
        };
        const double before = period_one[0]->state[i] / unit(0);
        const double after = period_one[1]->state[i] / unit(1);
        moved = std::max(moved, std::abs(after - before));
    }
    CHECK(moved > 0.2);
    CHECK(label[1] == label[0]);
    // Every label at the second value is either one of the first value's or new, used once.
    std::vector<int> sorted = c.labels[1];
    std::sort(sorted.begin(), sorted.end());
    CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    CHECK(sorted.back() < c.label_count);
}

TEST_CASE("bad line options are refused naming the option, before the first value runs") {
    AttractorOptions o;
    // A line of basin fractions whose last value the scheme cannot take is refused before its
    // first value runs (every value is validated first; the scheme is part of it now).
    o.samples = 2;
    o.run.scheme = Scheme::exact;
    const ReducedParameters soft{2, 1e8, 0.5, 0.3, 5.0};
    bool asked = false;
    CHECK_THROWS_WITH_AS(continue_basin_fractions(soft, SweptParameter::fc, {1e8, 3e8}, o,
                                                  [&](double) {
                                                      asked = true;
                                                      return true;
                                                  }),
                         doctest::Contains("run.scheme: exact takes contacts"),
                         std::invalid_argument);
    CHECK_FALSE(asked);
    // A line whose values are each within run.max_work but not together (10,000 values were
    // accepted with an estimate of 17 hours).
    o = AttractorOptions{};
    o.run.max_work = 1e9;
    const ReducedParameters fig13{5, 60, 0.5, 0.06, 3.0};
    CHECK_NOTHROW(validate(fig13, o));
    CHECK_THROWS_WITH_AS(
        continue_basin_fractions(fig13, SweptParameter::f_r, std::vector<double>(100, 3.0), o,
                                 [&](double) {
                                     asked = true;
                                     return true;
                                 }),
        doctest::Contains("run.max_work: this line runs up to"), std::invalid_argument);
    CHECK_FALSE(asked);
    const ReducedParameters mirror_pair = test::mirror_pair;
    // A line's end where the search refuses the row names that end (the tools map it to --to).
    CHECK_THROWS_WITH_AS(fraction_line_values(mirror_pair, SweptParameter::eps, 0.1, 0.0, 2),
                         doctest::Contains("to: model.eps: an attractor search needs damping"),
                         std::invalid_argument);
    CHECK(fraction_line_values(mirror_pair, SweptParameter::eps, 0.1, 0.3, 3).size() == 3);
    // The last value is `to` as written: 3 + (1e-300 - 3) 2 / 2 rounds to 0.
    CHECK(fraction_line_values(fig13, SweptParameter::f_r, 3.0, 1e-300, 3).back() == 1e-300);
    // ... and a row its search refuses at an end (too many steps per forcing period) names it.
    CHECK_THROWS_WITH_AS(
        continue_basin_fractions(fig13, SweptParameter::f_r, {1e-300, 3.0}, AttractorOptions{}),
        doctest::Contains("from: excitation.f_r: one forcing period"), std::invalid_argument);
    CHECK_THROWS_WITH_AS(
        continue_basin_fractions(fig13, SweptParameter::f_r, {3.0, 1e-300}, AttractorOptions{}),
        doctest::Contains("to: excitation.f_r: one forcing period"), std::invalid_argument);
}

TEST_CASE("fractions.csv: a label absent at a value has fraction 0 +- 1/N, not 0 +- 0; the "
          "transients' lifetime where measured") {
    // Two values, 25 starts each: label 1 is reached only at the first.
    FractionContinuation c;
    c.values = {1.0, 2.0};
    c.label_count = 2;
    for (int k = 0; k < 2; ++k) {
        AttractorSet set;
        set.sample_attractor.assign(25, 0);
        Attractor a;
        a.F_m = 1.5;
        a.F_m_error = 0.002;
        a.period = 1;
        a.basin_fraction = k == 0 ? 0.6 : 1.0;
        a.basin_fraction_error = 0.1;
        set.attractors.push_back(a);
        // The transients' lifetime, where it was measured (at the second value only).
        if (k == 1) {
            set.transients.lifetime = 150.0;
            set.transients.lifetime_error = 12.0;
        }
        if (k == 0) {
            a.id = 1;
            a.basin_fraction = 0.4;
            set.attractors.push_back(a);
        }
        c.sets.push_back(set);
        c.labels.push_back(k == 0 ? std::vector<int>{0, 1} : std::vector<int>{0});
    }
    std::istringstream csv(fractions_csv(c));
    std::string header, first, second;
    std::getline(csv, header);
    std::getline(csv, first);
    std::getline(csv, second);
    CHECK(header == "value,fraction_0,fraction_error_0,F_m_0,F_m_error_0,period_0,fraction_1,"
                    "fraction_error_1,F_m_1,F_m_error_1,period_1,transient_lifetime,"
                    "transient_lifetime_error");
    CHECK(first == "1,0.6,0.1,1.5,0.002,1,0.4,0.1,1.5,0.002,1,,");
    CHECK(second == "2,1,0.1,1.5,0.002,1,0,0.04,,,,150,12");

    // fractions.json keeps what the CSV cannot: each value's own row, where the starts were
    // drawn, and the run time.
    const Scene base = parse_scene(
        R"({"model": {"Nm": 2, "fc": 200, "eps": 0.1, "e_r": 0.351}, "excitation": {"f_r": 1}})");
    AttractorOptions o;
    o.center = {0.1, 0.0, 0.0, 0.0};
    c.wall_time_s = 3.5;
    const auto j = nlohmann::json::parse(to_json(c, o, base));
    CHECK(j.at("parameter") == "f_r");
    CHECK(j.at("wall_time_s") == 3.5);
    REQUIRE(j.at("points").size() == 2);
    for (int k = 0; k < 2; ++k) {
        const auto& point = j.at("points")[static_cast<std::size_t>(k)];
        CHECK(point.at("value") == c.values[static_cast<std::size_t>(k)]);
        CHECK(point.at("labels") == c.labels[static_cast<std::size_t>(k)]);
        CHECK(point.at("search").at("parameters").at("f_r") ==
              c.values[static_cast<std::size_t>(k)]);
        CHECK(point.at("search").at("parameters").at("Nm") == 2);
        CHECK(point.at("search").at("center") == o.center);
    }
    CHECK(j.at("points")[0].at("search").at("attractors")[1].at("basin_fraction") == 0.4);
    CHECK(j.at("points")[1].at("search").at("transients").at("lifetime") == 150.0);
}
