#include "gapchain/bifurcation.hpp"

#include "gapchain/poincare.hpp"
#include "gapchain/report.hpp"

#include "reference.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace gapchain;

namespace {
const ReducedParameters fig13{5, 60, 0.5, 0.06, 3.0};
}

TEST_CASE("Fig 13 row: a period-1 and a period-2 value are told apart") {
    BifurcationOptions o;
    o.from = 2.9;
    o.to = 3.6;
    o.steps = 2;
    o.transient_periods = 200;
    o.record_periods = 40;
    const BifurcationResult r = bifurcation(fig13, o);
    REQUIRE(r.rows.size() == 2);
    CHECK(r.rows[0].period == 1);
    CHECK(r.rows[1].period == 2);
    CHECK(r.rows[0].points.size() == 40);
    CHECK(r.rows[0].F_m > 0.0);
}

TEST_CASE("F_m_error: the tolerance where the row settles (covering a 1e-8 run), at least the "
          "window halves' spread where it does not") {
    BifurcationOptions o;
    o.from = 2.9; // period 1
    o.to = 3.2;   // chaotic from rest (issue 19)
    o.steps = 2;
    o.transient_periods = 300;
    o.record_periods = 300;
    const BifurcationResult r = bifurcation(fig13, o);
    REQUIRE(r.rows.size() == 2);
    const BifurcationRow& periodic = r.rows[0];
    CHECK(periodic.F_m_error == doctest::Approx(o.tolerance * periodic.F_m));
    BifurcationOptions tight = o;
    tight.to = o.from;
    tight.steps = 1;
    tight.tolerance = 1e-8;
    const double reference = bifurcation(fig13, tight).rows[0].F_m;
    CHECK(std::abs(periodic.F_m - reference) <= periodic.F_m_error);

    // The chaotic value: the spread is the maximum of each half, run on its own.
    const BifurcationRow& chaotic = r.rows[1];
    BifurcationOptions half = o;
    half.from = o.to;
    half.steps = 1;
    half.record_periods = 150;
    const double first = bifurcation(fig13, half).rows[0].F_m;
    half.transient_periods = 450;
    const double second = bifurcation(fig13, half).rows[0].F_m;
    // At least that spread; above it only by the tail of the per-period maxima (their spread,
    // test_observers.cpp), which is a few per cent of F_m here.
    CHECK(chaotic.F_m_error >= std::abs(first - second));
    CHECK(chaotic.F_m_error < 0.1 * chaotic.F_m);
    CHECK(chaotic.F_m_error > 10.0 * o.tolerance * chaotic.F_m);
    CHECK(chaotic.F_m == doctest::Approx(std::max(first, second)).epsilon(1e-12));
}

TEST_CASE("a diagram too large is refused up front: run.max_work is honoured, the memory capped") {
    BifurcationOptions o;
    o.steps = 1;
    o.from = o.to = 2.0;
    o.transient_periods = 0;
    o.record_periods = 10'000'000; // 8.7e8 body-steps: above a max_work of 1e8, below 3e10
    o.max_work = 1e8;
    CHECK_THROWS_WITH_AS(bifurcation(fig13, o), doctest::Contains("run.max_work"),
                         std::invalid_argument);
    // The whole diagram, not each value: 100 values up and back of 300 periods at 87 steps
    // each are 2.6e7 body-steps, one value 1.3e5 (the probe of 2026-11-26 ran it at 1e6).
    o.mode = SweepMode::continuation;
    o.steps = 100;
    o.to = 4.5;
    o.transient_periods = 200;
    o.record_periods = 100;
    o.max_work = 1e6;
    CHECK_THROWS_WITH_AS(bifurcation(fig13, o), doctest::Contains("this diagram runs up to"),
                         std::invalid_argument);
    o.mode = SweepMode::independent;
    o.steps = 20; // 2e8 section points kept
    o.record_periods = 10'000'000;
    o.max_work = 1e15;
    CHECK_THROWS_WITH_AS(bifurcation(fig13, o), doctest::Contains("record_periods"),
                         std::invalid_argument);
}

TEST_CASE("detect_period on synthetic sequences") {
    auto seq = [](std::vector<double> v) {
        std::vector<SectionPoint> s;
        for (double x : v)
            s.push_back({0.0, {x}});
        return s;
    };
    CHECK(detect_period(seq({1, 1, 1, 1}), 8, 1e-9) == 1);
    CHECK(detect_period(seq({1, 2, 1, 2, 1, 2}), 8, 1e-9) == 2);
    CHECK(detect_period(seq({1, 2, 3, 1, 2, 3, 1}), 8, 1e-9) == 3);
    CHECK(detect_period(seq({1, 2, 3, 4, 5, 6}), 8, 1e-9) == 0);
}

TEST_CASE("SectionRepeats, one point at a time, answers as the pairwise definition") {
    // The definition written out: every value repeats k points later (all pairs), within
    // tolerance (1 + the largest |value|), at least 2 k points.
    auto by_pairs = [](const std::vector<std::vector<double>>& x, int max_period, double tol) {
        double scale = 0.0;
        for (const auto& p : x)
            for (double v : p)
                scale = std::max(scale, std::abs(v));
        for (int k = 1; k <= max_period && 2 * k <= static_cast<int>(x.size()); ++k) {
            bool all = true;
            for (std::size_t i = 0; i + k < x.size(); ++i)
                for (std::size_t c = 0; c < x[i].size(); ++c)
                    all = all && std::abs(x[i][c] - x[i + k][c]) <= tol * (1.0 + scale);
            if (all) return k;
        }
        return 0;
    };
    unsigned seed = 12345;
    auto next = [&seed] { return (seed = seed * 1103515245u + 12345u) % 1000 / 1000.0; };
    for (int trial = 0; trial < 300; ++trial) {
        const int k = 1 + trial % 7, n = 1 + trial % 23, dim = 1 + trial % 3;
        std::vector<std::vector<double>> x;
        for (int i = 0; i < n; ++i) {
            if (i >= k && trial % 2 == 0) {
                x.push_back(x[i - k]); // exactly k-periodic, then perturbed below at times
                if (trial % 5 == 0 && i == n - 1) x.back()[0] += 1e-3;
            } else {
                std::vector<double> p;
                for (int c = 0; c < dim; ++c)
                    p.push_back(next());
                x.push_back(p);
            }
        }
        SectionRepeats repeats(8);
        for (const auto& p : x)
            repeats.add(p);
        CHECK(repeats.period(1e-6) == by_pairs(x, 8, 1e-6));
    }
}

TEST_CASE("a spiral onto an orbit is read as the orbit's period, not as its returns'") {
    // Points a r^n e^(2 pi i n theta) closing in on 0 (the orbit): with theta near 1/3 they come
    // back near their start every 3 periods (r^3 e^(2 pi i 3 theta) is near 1) while lag 1 is
    // still wider than the tolerance. Fig 13's row at f_r = 2.7715 did that (|mu| 0.966,
    // rotation 0.3255) and the diagram read period 3; Newton finds the symmetric orbit,
    // period 1.
    const double r = 0.966, theta = 0.3255, tol = 1e-6;
    for (const double a : {2e-6, 4e-6}) {
        CAPTURE(a);
        SectionRepeats repeats(16);
        for (int n = 0; n < 100; ++n) {
            const double radius = a * std::pow(r, n), angle = 2.0 * std::numbers::pi * theta * n;
            repeats.add({radius * std::cos(angle), radius * std::sin(angle)});
        }
        REQUIRE(repeats.period(tol) == 3); // the returns alone
        CHECK(repeats.period(tol, true) == 1);
    }
    // A true period-3 orbit keeps its period: its points stand apart.
    SectionRepeats cycle(16);
    for (int n = 0; n < 30; ++n)
        cycle.add({std::cos(2.0 * std::numbers::pi * n / 3.0),
                   std::sin(2.0 * std::numbers::pi * n / 3.0)});
    CHECK(cycle.period(tol, true) == 3);
    // And the row itself: period 1, as gapchain-orbit finds it (minimal period 1), from its
    // section points alone as well as from Newton's confirmation.
    BifurcationOptions o;
    o.from = o.to = 2.7715430861723447;
    o.steps = 1;
    for (const bool newton : {false, true}) {
        CAPTURE(newton);
        o.confirm_by_newton = newton;
        const BifurcationResult row = bifurcation(fig13, o);
        REQUIRE(row.rows.size() == 1);
        CHECK(row.rows[0].period == 1);
        CHECK(row.rows[0].newton_confirmed == newton);
    }
}

TEST_CASE("a periodic row's F_m is its orbit's, within its error of an independent scheme") {
    // Fig 13's row where the contact barely closes (4.119) and where the orbit's multiplier is
    // near 1 (2.47, |mu| 0.915): rk4 at the default tolerance read 0.00363071 +- 3.6e-7 and
    // 0.587975 +- 5.9e-5 over its window, 73 and 4.6 of those errors from the orbit. The
    // reference is a plain rk8pd run at 1e-10 from rest, no Newton and no exact propagator.
    for (const double f_r : {4.119, 2.47}) {
        CAPTURE(f_r);
        BifurcationOptions o;
        o.from = o.to = f_r;
        o.steps = 1;
        o.scheme = Scheme::rk4;
        BifurcationOptions reference = o;
        reference.scheme = Scheme::rk8pd;
        reference.tolerance = 1e-10;
        reference.confirm_by_newton = false;
        reference.transient_periods = 400;
        const BifurcationRow ref = bifurcation(fig13, reference).rows.at(0);
        REQUIRE(ref.period > 0);
        const BifurcationRow row = bifurcation(fig13, o).rows.at(0);
        REQUIRE(row.newton_confirmed);
        CHECK(row.period == ref.period);
        CHECK(row.max_multiplier < 1.0);
        CHECK(std::abs(row.F_m - ref.F_m) <= 1e-6 * ref.F_m);
        // The bar covers the window's reading on rk4, which is its scheme's truncation error.
        o.confirm_by_newton = false;
        const BifurcationRow window = bifurcation(fig13, o).rows.at(0);
        CHECK(std::abs(window.F_m - ref.F_m) > window.F_m_error); // the old bar did not hold
        CHECK(row.F_m_error >= std::abs(window.F_m - row.F_m));
        CHECK(row.F_m_error < 1e-2 * row.F_m);
        CHECK(std::isnan(window.max_multiplier));
    }
}

TEST_CASE("a periodic row Newton does not confirm keeps a bar that covers an independent run") {
    // Fig 13's row at fc = 950: rk4 settles on period 2, and Newton on the 2-period map from
    // there converged on the unstable period-1 orbit (|mu| 1.05), which had replaced the row's
    // F_m (0.698866 +- 1.1e-4 against rk8pd's 0.699712). At f_r = 2.1253 rk4 reads period 5
    // where Newton does not converge and rk8pd does not settle: its tolerance bar (1.1e-4) was
    // 19 times short.
    struct Case {
        SweptParameter parameter;
        double value;
    };
    for (const Case c : {Case{SweptParameter::fc, 950.0}, Case{SweptParameter::f_r, 2.125250501}}) {
        CAPTURE(c.value);
        BifurcationOptions o;
        o.parameter = c.parameter;
        o.from = o.to = c.value;
        o.steps = 1;
        o.scheme = Scheme::rk4;
        const BifurcationRow row = bifurcation(fig13, o).rows.at(0);
        CHECK(row.period > 0);
        CHECK_FALSE(row.newton_confirmed);
        CHECK(std::isnan(row.max_multiplier));
        BifurcationOptions reference = o;
        reference.scheme = Scheme::rk8pd;
        reference.tolerance = 1e-10;
        reference.confirm_by_newton = false;
        const BifurcationRow ref = bifurcation(fig13, reference).rows.at(0);
        CHECK(std::abs(row.F_m - ref.F_m) <= row.F_m_error);
        CHECK(row.F_m_error > 5.0 * o.tolerance * row.F_m); // the tolerance alone did not hold
        CHECK(row.F_m_error < 0.01 * row.F_m);
    }
}

TEST_CASE("a confirmed orbit that a finer run from the same start does not reach widens its bar") {
    // A researcher's probe (helper-81): Nm 3, fc 100, eps 0.2, e_r 0.1 has a contact-free and
    // an impacting period-1 orbit near f_r = 3.45, and rest lies so near their basins' boundary
    // that the scheme's error picks one. On the line from 3.40 to 3.50 in 11 values rk4 from rest
    // settled contact-free at the tenth (3.49 to round-off: 0 +- 0, confirmed by Newton) where an
    // independent integrator, this file's GSL reference at 1e-12, reaches the impacting orbit.
    const ReducedParameters row3{3, 100, 0.2, 0.1, 3.45};
    BifurcationOptions o;
    o.from = 3.40;
    o.to = 3.50;
    o.steps = 11;
    o.scheme = Scheme::rk4;
    const BifurcationResult line = bifurcation(row3, o);
    for (const std::size_t k : {std::size_t{9}, std::size_t{7}}) {
        const BifurcationRow& row = line.rows.at(k);
        CAPTURE(row.value);
        REQUIRE(row.newton_confirmed);
        const reference::Outcome ref = reference::run({3, 100, 0.2, 0.1, row.value}, 300, 200);
        MESSAGE("rk4 " << row.F_m << " +- " << row.F_m_error << ", reference " << ref.F_m);
        REQUIRE(ref.F_m > 1.7);
        CHECK(std::abs(row.F_m - ref.F_m) <= row.F_m_error);
        // Where the finer run settles on the same orbit the bar stays the tolerance's.
        CHECK(row.ended_elsewhere == (k == 9));
        if (k == 7) CHECK(row.F_m_error < 1e-3 * row.F_m);
    }
}

TEST_CASE("a row that is not periodic keeps a bar that covers an independent run") {
    // A reviewer's probe (helper-74): Fig 13's row after 100 discarded periods is still in its
    // transient at f_r = 2.4 and 2.6. With 1 recorded period the bar was the tolerance alone
    // (8.9e-5 and 3.6e-5) where rk8pd at 1e-11 and the exact scheme at 1e-10 agree on values
    // 6.1e-3 and 1.5e-2 away; with 50, 7 bars off at 2.4.
    for (const long record : {1L, 50L}) {
        BifurcationOptions o;
        o.from = 2.4;
        o.to = 2.6;
        o.steps = 2;
        o.transient_periods = 100;
        o.record_periods = record;
        const BifurcationResult diagram = bifurcation(fig13, o);
        BifurcationOptions reference = o;
        reference.scheme = Scheme::rk8pd;
        reference.tolerance = 1e-11;
        reference.confirm_by_newton = false;
        const BifurcationResult truth = bifurcation(fig13, reference);
        for (std::size_t k = 0; k < 2; ++k) {
            const BifurcationRow& row = diagram.rows.at(k);
            CAPTURE(record);
            CAPTURE(row.value);
            CHECK(row.period == 0);
            CHECK(std::abs(row.F_m - truth.rows.at(k).F_m) <= row.F_m_error);
            CHECK(row.F_m_error < 0.1 * row.F_m);
        }
    }
}

TEST_CASE("a spurious rk4 period doubling reads the exact orbit's minimal period") {
    // Fig 13's row at 4.1092: rk4 settles on a period-4 orbit of its own (by period 28, for
    // thousands of periods), where the exact scheme's section and Newton both read 2 (|mu| 0.83).
    BifurcationOptions o;
    o.from = o.to = 4.10921843687;
    o.steps = 1;
    o.scheme = Scheme::rk4;
    o.confirm_by_newton = false;
    // Only a note: which cell of a slow approach still reads the multiple moves between builds.
    WARN(bifurcation(fig13, o).rows.at(0).period == 4);
    o.scheme = Scheme::exact;
    CHECK(bifurcation(fig13, o).rows.at(0).period == 2);
    o.scheme = Scheme::rk4;
    o.confirm_by_newton = true;
    const BifurcationRow row = bifurcation(fig13, o).rows.at(0);
    CHECK(row.newton_confirmed);
    CHECK(row.period == 2);
    // The diagram draws the orbit's two points, not rk4's four: the same two a run on the
    // exact scheme records (200 periods of it hold on the orbit to its slow approach, |mu| 0.83).
    CHECK(row.points_from_orbit);
    REQUIRE(row.points.size() == 2);
    o.scheme = Scheme::exact;
    o.confirm_by_newton = false;
    o.transient_periods = 1000;
    const BifurcationRow exact = bifurcation(fig13, o).rows.at(0);
    REQUIRE(exact.period == 2);
    for (const auto& p : row.points) {
        double nearest = 1e300;
        for (const auto& q : exact.points)
            nearest = std::min(nearest, std::abs(p.values.at(0) - q.values.at(0)));
        CHECK(nearest < 1e-8);
    }
    // Timed over the run's last cycle: the last point at the run's end, one period apart.
    const double T = 1.0 / o.from;
    CHECK(row.points.back().t == doctest::Approx(300 * T).epsilon(1e-12));
    CHECK(row.points.back().t - row.points.front().t == doctest::Approx(T).epsilon(1e-12));
    // A row whose window already had the orbit's period keeps its own points.
    o.from = o.to = 3.0;
    o.scheme = Scheme::rk4;
    o.confirm_by_newton = true;
    o.transient_periods = 200;
    const BifurcationRow settled = bifurcation(fig13, o).rows.at(0);
    CHECK(settled.newton_confirmed);
    CHECK_FALSE(settled.points_from_orbit);
    CHECK(settled.points.size() == 100);
}

TEST_CASE("the diagram's period is the section state's, whatever variable it plots") {
    // F0 is 0 at every section instant where the left wall is open: on the chaotic row at
    // f_r = 3.3 it read "period 1". (t, which never repeats, is no longer a plotted variable.)
    for (const char* variable : {"u1", "F0"}) {
        BifurcationOptions o;
        o.from = 3.0;
        o.to = 3.3;
        o.steps = 2;
        o.transient_periods = 200;
        o.record_periods = 40;
        o.section.record = {SectionVariable::parse(variable, 5, "variable")};
        const BifurcationResult r = bifurcation(fig13, o);
        REQUIRE(r.rows.size() == 2);
        CHECK(r.rows[0].period == 1);
        CHECK(r.rows[1].period == 0);
        CHECK(r.rows[0].points.front().values.size() == 1); // the plotted variable alone
    }
}

TEST_CASE("independent mode: identical CSVs with 1 and 2 threads") {
    BifurcationOptions o;
    o.from = 2.4;
    o.to = 3.4;
    o.steps = 12;
    o.transient_periods = 30;
    o.record_periods = 20;
    o.threads = 1;
    const BifurcationResult one = bifurcation(fig13, o);
    o.threads = 2;
    const BifurcationResult two = bifurcation(fig13, o);
    CHECK(points_csv(one, o.section) == points_csv(two, o.section));
    CHECK(summary_csv(one) == summary_csv(two));
}

TEST_CASE("continuation sweeps from `from` to `to` and back, each value from the previous end "
          "state") {
    BifurcationOptions o;
    o.mode = SweepMode::continuation;
    o.from = 2.8;
    o.to = 3.0;
    o.steps = 3;
    o.transient_periods = 50;
    o.record_periods = 10;
    const BifurcationResult r = bifurcation(fig13, o);
    REQUIRE(r.rows.size() == 6);
    CHECK(r.rows[0].direction == SweepDirection::up);
    CHECK(r.rows[0].value == doctest::Approx(2.8));
    CHECK(r.rows[3].direction == SweepDirection::down);
    CHECK(r.rows[3].value == doctest::Approx(3.0));
    CHECK(r.rows[5].value == doctest::Approx(2.8));
    // On the period-1 branch both directions land on the same attractor.
    CHECK(r.rows[5].points.back().values[0] ==
          doctest::Approx(r.rows[0].points.back().values[0]).epsilon(1e-6));
    // A line given downwards goes down first, and says so.
    std::swap(o.from, o.to);
    const BifurcationResult down = bifurcation(fig13, o);
    REQUIRE(down.rows.size() == 6);
    CHECK(down.rows[0].direction == SweepDirection::down);
    CHECK(down.rows[0].value == doctest::Approx(3.0));
    CHECK(down.rows[3].direction == SweepDirection::up);
    CHECK(down.rows[3].value == doctest::Approx(2.8));
    // Independent values start from rest; their label says which way the line goes.
    o.mode = SweepMode::independent;
    for (const auto& row : bifurcation(fig13, o).rows)
        CHECK(row.direction == SweepDirection::down);
}

TEST_CASE("bad options name the option field (the tools translate it into their flag)") {
    BifurcationOptions o;
    o.from = -1.0;
    CHECK_THROWS_WITH_AS(validate(o, fig13), doctest::Contains("f_r"), std::invalid_argument);
    o = {};
    o.steps = 0;
    CHECK_THROWS_WITH_AS(validate(o, fig13), doctest::Contains("steps: must be"),
                         std::invalid_argument);
    // One value of a line 2 .. 4.5 ran `from` alone, silently.
    o.steps = 1;
    CHECK_THROWS_WITH_AS(validate(o, fig13), doctest::Contains("steps: one value needs from = to"),
                         std::invalid_argument);
    // The section's time was accepted and plotted as a diagram of section times.
    o = {};
    o.section.record = {SectionVariable::parse("t", fig13.Nm, "variable")};
    CHECK_THROWS_WITH_AS(validate(o, fig13),
                         doctest::Contains("variable: must be a state variable"),
                         std::invalid_argument);
}

TEST_CASE("bifurcation and regime maps: a cancelled run stops within one value per thread") {
    const ReducedParameters base{3, 60.0, 0.5, 0.06, 3.0};
    for (int threads : {1, 2}) {
        BifurcationOptions o;
        o.steps = 40;
        o.transient_periods = 20;
        o.record_periods = 10;
        o.threads = threads;
        // Cancel once 3 of the 40 values are done.
        const BifurcationResult r =
            bifurcation(base, o, [&](double done) { return done < 3.0 / 40.0 - 1e-12; });
        CHECK(r.cancelled);
        long ran = 0;
        for (const auto& row : r.rows)
            ran += row.status != RunStatus::cancelled;
        CHECK(ran >= 3);
        CHECK(ran <= 3 + threads); // values that finished while the third did

        ClassifyOptions co;
        co.transient_periods = 10;
        co.record_periods = 20;
        const RegimeMap map =
            regime_map(base, {0.0, 0.1, 0.2, 0.3, 0.4}, {1.0, 2.0, 3.0, 4.0}, co, threads,
                       [&](double done) { return done < 2.0 / 20.0 - 1e-12; });
        CHECK(map.cancelled);
        long cells = 0;
        for (const auto& c : map.cells)
            cells += c.status != RunStatus::cancelled;
        CHECK(cells >= 2);
        CHECK(cells <= 2 + threads);
    }
    BifurcationOptions o;
    o.steps = 10;
    o.transient_periods = 20;
    o.record_periods = 10;
    o.mode = SweepMode::continuation;
    const BifurcationResult r =
        bifurcation(base, o, [&](double done) { return done < 4.0 / 20.0 - 1e-12; });
    CHECK(r.cancelled);
    CHECK(r.rows.size() == 4);
}

TEST_CASE("bifurcation and regime maps: a cancel stops a long value inside its run") {
    // One value of a million periods (minutes): the first call from inside the run cancels it.
    const ReducedParameters base{3, 60.0, 0.5, 0.06, 3.0};
    for (const SweepMode mode : {SweepMode::independent, SweepMode::continuation}) {
        BifurcationOptions o;
        o.steps = 1;
        o.from = o.to = 3.0;
        o.transient_periods = 0;
        o.record_periods = 1'000'000;
        o.mode = mode;
        int calls = 0;
        const BifurcationResult r = bifurcation(base, o, [&](double) { return ++calls < 2; });
        CHECK(r.cancelled);
        for (const auto& row : r.rows)
            CHECK(row.status == RunStatus::cancelled);
    }
    ClassifyOptions co;
    co.transient_periods = 10;
    co.record_periods = 1'000'000;
    // Fig 13's chaotic point: it never settles, so the record runs to its end (the point above
    // settles on period 1 after 25 periods, which stops the record).
    int calls = 0;
    const RegimeMap map = regime_map({5, 60.0, 0.5, 0.06, 3.3}, {0.06}, {3.3}, co, 1,
                                     [&](double) { return ++calls < 2; });
    CHECK(map.cancelled);
    CHECK(map.cells.front().status == RunStatus::cancelled);
    CHECK(classify(base, co, [](double) { return false; }).status == RunStatus::cancelled);
}

TEST_CASE("a diagram starts every value (independent) or its first (continuation) from "
          "options.initial") {
    // Issue 19: at f_r = 3.2 the row is chaotic from rest (F_m 0.239) and reaches a torus with
    // F_m 0.385 from u = (0.5, -0.5, 0.5, -0.5, 0.5).
    BifurcationOptions o;
    o.from = o.to = 3.2;
    o.steps = 1;
    o.transient_periods = 300;
    o.record_periods = 300;
    const double rest = bifurcation(fig13, o).rows.front().F_m;
    o.initial = {0.5, -0.5, 0.5, -0.5, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0};
    const double torus = bifurcation(fig13, o).rows.front().F_m;
    o.mode = SweepMode::continuation;
    const double continued = bifurcation(fig13, o).rows.front().F_m;
    CHECK(rest < 0.3);
    CHECK(torus == doctest::Approx(0.385).epsilon(2e-3));
    CHECK(continued == torus);
    o.initial.pop_back();
    CHECK_THROWS_WITH_AS(validate(o, fig13), doctest::Contains("initial"), std::invalid_argument);
}

TEST_CASE("a diagram over fc whose end is beyond the exact scheme's stiffest contacts is refused "
          "up front") {
    BifurcationOptions o;
    o.parameter = SweptParameter::fc;
    o.from = 1.0e8;
    o.to = 3.0e8;
    o.scheme = Scheme::exact;
    CHECK_THROWS_WITH_AS(validate(o, ReducedParameters{2, 1e8, 0.5, 0.3, 5.0}),
                         doctest::Contains("run.scheme: exact takes contacts"),
                         std::invalid_argument);
    o.to = 1.1e8;
    CHECK_NOTHROW(validate(o, ReducedParameters{2, 1e8, 0.5, 0.3, 5.0}));
}
