#include "gapchain/transient_lifetime.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace gapchain;

TEST_CASE("transient lifetimes: an exponential tail is measured, censored or not; a bounded one "
          "is rejected; too few endings are untested") {
    // Lengths 30 + an exponential of mean 150 periods (rounded up, as a settling period is).
    std::mt19937_64 random(7);
    std::exponential_distribution<double> escape(1.0 / 150.0);
    std::vector<long> lengths;
    for (int k = 0; k < 2000; ++k)
        lengths.push_back(30 + static_cast<long>(std::ceil(escape(random))));
    const TransientLifetime full = transient_lifetime(lengths, {});
    CHECK(full.constant_rate == ConstantRate::consistent);
    CHECK(std::abs(full.rate_ratio - 1.0) <= 3.0 * full.rate_ratio_error);
    // Half of the lengths end beyond the median (fewer where some equal it).
    CHECK(full.ended > 980);
    CHECK(full.ended <= 1000);
    CHECK(full.lifetime_error ==
          doctest::Approx(full.lifetime / std::sqrt(static_cast<double>(full.ended))));
    // The ceiling adds half a period to the mean excess of the continuous lengths.
    CHECK(std::abs(full.lifetime - 150.5) < 3.0 * full.lifetime_error);
    // Runs of 300 periods: the longer transients are still going at the end. Their time counts
    // as at least 300, so the estimate stays right; the ended ones alone say far shorter.
    std::vector<long> ended, going;
    for (long n : lengths)
        (n > 300 ? going : ended).push_back(n > 300 ? 300 : n);
    REQUIRE(going.size() > 300);
    const TransientLifetime censored = transient_lifetime(ended, going);
    CHECK(censored.censored == static_cast<long>(going.size()));
    CHECK(censored.from_period == full.from_period);
    CHECK(censored.constant_rate == ConstantRate::consistent);
    CHECK(std::abs(censored.lifetime - 150.5) < 3.0 * censored.lifetime_error);
    CHECK(transient_lifetime(ended, {}).lifetime < 100.0);
    // Settling by contraction from a bounded box: lengths uniform in [20, 400] end at a rising
    // rate (no transient outlasts 400), which is no escape from a saddle.
    std::uniform_int_distribution<long> bounded(20, 400);
    std::vector<long> uniform;
    for (int k = 0; k < 2000; ++k)
        uniform.push_back(bounded(random));
    const TransientLifetime rising = transient_lifetime(uniform, {});
    CHECK(rising.constant_rate == ConstantRate::rejected);
    CHECK(rising.rate_ratio > 2.0);
    // Where 1 % are still going: the exponential tail extended, for a constant rate only. The
    // lengths themselves say it too: 1 % of 2000 is the 20th longest.
    std::vector<long> sorted(lengths);
    std::sort(sorted.begin(), sorted.end());
    const double one_percent = full.periods_until(0.01);
    CHECK(one_percent == doctest::Approx(full.from_period + full.lifetime * std::log(50.0)));
    CHECK(std::abs(one_percent - static_cast<double>(sorted[2000 - 20])) <
          3.0 * full.lifetime_error * std::log(50.0));
    CHECK(std::isnan(rising.periods_until(0.01)));
    CHECK_THROWS_AS((void)full.periods_until(0.5), std::invalid_argument);
    // 21 lengths: 10 end beyond the median, 5 in each half at most: a lifetime, but no test.
    const std::vector<long> few(lengths.begin(), lengths.begin() + 21);
    const TransientLifetime small = transient_lifetime(few, {});
    CHECK(std::isfinite(small.lifetime));
    CHECK(small.constant_rate != ConstantRate::rejected);
    CHECK(transient_lifetime({17, 17, 18, 40, 50}, {}).constant_rate == ConstantRate::untested);
    // Kaplan-Meier's median, by hand: three censored at 15 leave 5 at risk at 20; the share
    // still going is 8/9 after 10, then x 4/5, x 3/4, x 2/3 = 0.356 at 40. (Counted as the
    // longest, the censored ones would put the median at 50; at 15, at 20.)
    CHECK(transient_lifetime({10, 20, 30, 40, 50, 60}, {15, 15, 15}).from_period == 40.0);
    // Too few ending beyond the median to measure; most still going: no median.
    CHECK(std::isnan(transient_lifetime({17, 17, 18, 40, 50}, {}).lifetime));
    CHECK(std::isnan(transient_lifetime({17, 20}, {100, 100, 100}).from_period));
    CHECK_THROWS_AS(transient_lifetime({-1, 17}, {}), std::invalid_argument);
    CHECK_THROWS_AS(transient_lifetime({17}, {-3}), std::invalid_argument);
}
