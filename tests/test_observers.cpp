#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <vector>

using namespace gapchain;

namespace {
// Largest force over all contacts of a tracker.
double largest_force(const MaxForceTracker& tracker) {
    double f = 0.0;
    for (const ContactMaximum& c : tracker.contacts())
        f = std::max(f, c.force);
    return f;
}
} // namespace

TEST_CASE("MaxForceTracker: the half-window maxima equal the maxima of runs recording only that "
          "half") {
    // A row whose largest force comes in the first half (the start-up transient): the second
    // half's peaks stay below the contacts' records, the case where a half maximum could be
    // missed (before the fix, by 3.9e-3 here).
    const ReducedParameters p{5, 60, 0.3, 0.3, 1.3};
    const Dynamics dyn(Chain::homogeneous(p), {p.f_r, 1.0});
    // Steps that do not end on contact switches put whole contacts inside steps, where the
    // tracker decides from a bound whether a peak is worth locating.
    StepPlan plan = plan_step(dyn, Scheme::rk4, 1e-4);
    plan.split_at_switches = false;
    constexpr long periods = 200, split = 100;

    // One run records everything and splits; two more record only one half each (the first
    // stops at the split, the second discards it as a transient) on the same step grid.
    auto run_with = [&](long total, long transient, long split_period) {
        auto stepper = make_stepper(plan, dyn);
        MaxForceTracker tracker(dyn, split_period);
        std::array<Observer*, 1> observers{&tracker};
        std::vector<double> y(2 * p.Nm, 0.0);
        const RunOutcome out = run(dyn, *stepper, plan, {total, transient, 0.0}, y, observers);
        REQUIRE(out.status == RunStatus::completed);
        return tracker;
    };
    const MaxForceTracker whole = run_with(periods, 0, split);
    const MaxForceTracker first = run_with(split, 0, -1);
    const MaxForceTracker second = run_with(periods, split, -1);

    MESSAGE("halves " << whole.first_half_max() << ", " << whole.second_half_max());
    CHECK(whole.first_half_max() == doctest::Approx(largest_force(first)).epsilon(1e-12));
    CHECK(whole.second_half_max() == doctest::Approx(largest_force(second)).epsilon(1e-12));
    CHECK(std::max(whole.first_half_max(), whole.second_half_max()) ==
          doctest::Approx(largest_force(whole)).epsilon(1e-12));
    // Not trivially equal: the record is in the first half, well above the second's maximum.
    CHECK(whole.first_half_max() > 1.05 * whole.second_half_max());
}
