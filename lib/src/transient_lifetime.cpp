#include "gapchain/transient_lifetime.hpp"

#include "detail/check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace gapchain {

namespace {

/// Transients ending at lengths within (from, to], and the periods that every transient, ended
/// or censored, spent in that interval.
struct EndingRate {
    long ended = 0;
    double exposure = 0.0;
};

EndingRate ending_rate(const std::vector<long>& ended, const std::vector<long>& censored,
                       double from, double to) {
    EndingRate r;
    const auto add = [&](long n) {
        if (n > from) r.exposure += std::min(static_cast<double>(n), to) - from;
    };
    for (long n : ended) {
        add(n);
        if (n > from && n <= to) ++r.ended;
    }
    std::for_each(censored.begin(), censored.end(), add);
    return r;
}

/// The Kaplan-Meier median of the lengths (ended sorted): the first ending length where the
/// share still going falls to 1/2; NaN if it never does.
double survival_median(const std::vector<long>& ended, const std::vector<long>& censored) {
    // At a tie the censored ones are at risk too: a transient censored at n was still going.
    std::vector<long> sorted_censored(censored);
    std::sort(sorted_censored.begin(), sorted_censored.end());
    const double total = static_cast<double>(ended.size() + censored.size());
    double surviving = 1.0;
    for (auto it = ended.begin(); it != ended.end();) {
        const long n = *it;
        const auto next = std::upper_bound(it, ended.end(), n);
        // At risk at n: every length >= n, ended or censored.
        const double gone = static_cast<double>(it - ended.begin()) +
                            static_cast<double>(std::lower_bound(sorted_censored.begin(),
                                                                 sorted_censored.end(), n) -
                                                sorted_censored.begin());
        surviving *= 1.0 - static_cast<double>(next - it) / (total - gone);
        if (surviving <= 0.5) return static_cast<double>(n);
        it = next;
    }
    return std::numeric_limits<double>::quiet_NaN();
}

} // namespace

std::string_view to_string(ConstantRate r) {
    switch (r) {
    case ConstantRate::untested: return "untested";
    case ConstantRate::consistent: return "consistent";
    case ConstantRate::rejected: return "rejected";
    }
    return "untested";
}

double TransientLifetime::periods_until(double share) const {
    if (!(share > 0.0 && share < 0.5))
        throw std::invalid_argument("share: must be in (0, 0.5), got " +
                                    detail::format_number(share));
    if (constant_rate != ConstantRate::consistent) return std::numeric_limits<double>::quiet_NaN();
    return from_period + lifetime * std::log(0.5 / share);
}

TransientLifetime transient_lifetime(std::vector<long> ended, std::vector<long> censored) {
    for (const auto* lengths : {&ended, &censored})
        for (long n : *lengths)
            detail::require_count("transient length", n, 0, std::numeric_limits<long>::max());
    TransientLifetime t;
    t.censored = static_cast<long>(censored.size());
    std::sort(ended.begin(), ended.end());
    t.from_period = survival_median(ended, censored);
    if (std::isnan(t.from_period)) return t;
    constexpr double unbounded = std::numeric_limits<double>::infinity();
    const EndingRate beyond = ending_rate(ended, censored, t.from_period, unbounded);
    t.ended = beyond.ended;
    if (t.ended < 10) return t;
    t.lifetime = beyond.exposure / static_cast<double>(t.ended);
    t.lifetime_error = t.lifetime / std::sqrt(static_cast<double>(t.ended));
    // A constant rate: the earlier half of the endings beyond from_period against the later
    // half. A contraction onto an orbit from a bounded box ends its transients at a rising rate
    // (no start is farther than the box), a saddle's at a constant one.
    const auto later =
        std::upper_bound(ended.begin(), ended.end(), static_cast<long>(t.from_period));
    const double split = static_cast<double>(*(later + (ended.end() - later) / 2 - 1));
    const EndingRate first = ending_rate(ended, censored, t.from_period, split);
    const EndingRate second = ending_rate(ended, censored, split, unbounded);
    if (first.ended < 5 || second.ended < 5) return t;
    const double ratio = (static_cast<double>(second.ended) / second.exposure) /
                         (static_cast<double>(first.ended) / first.exposure);
    const double log_error =
        std::sqrt(1.0 / static_cast<double>(first.ended) + 1.0 / static_cast<double>(second.ended));
    t.rate_ratio = ratio;
    t.rate_ratio_error = ratio * log_error;
    t.constant_rate = std::abs(std::log(ratio)) <= 3.0 * log_error ? ConstantRate::consistent
                                                                   : ConstantRate::rejected;
    return t;
}

} // namespace gapchain
