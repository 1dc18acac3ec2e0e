#include "gapchain/grid.hpp"

#include "detail/check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace gapchain {

namespace {

/// count values from `from` to `to`, evenly spaced in value or in log, with exact ends.
std::vector<double> spaced(double from, double to, long count, bool log) {
    if (count < 1) throw std::invalid_argument("count: must be >= 1, got " + std::to_string(count));
    if (!std::isfinite(from) || !std::isfinite(to) || (log && (from <= 0.0 || to <= 0.0)))
        throw std::invalid_argument(std::string("range ends: must be finite") +
                                    (log ? " and > 0" : ""));
    std::vector<double> v(static_cast<std::size_t>(count), from);
    const double intervals = static_cast<double>(count - 1);
    // to / from overflows for ends like 1e-303 and 1e6 (every inner value came out inf); there
    // the logs are spaced, elsewhere the ratio, as the documented studies were made.
    const double ratio = to / from;
    const bool ratio_finite = std::isfinite(ratio) && ratio > 0.0;
    for (long k = 1; k + 1 < count; ++k) {
        const double x = static_cast<double>(k);
        v[k] = !log ? (from * (intervals - x) + to * x) / intervals
               : ratio_finite
                   ? from * std::pow(ratio, x / intervals)
                   : std::exp(std::log(from) + (std::log(to) - std::log(from)) * x / intervals);
    }
    // (x (count - 1)) / (count - 1) may round off x: the ends are the ends.
    if (count > 1) v.back() = to;
    // -0 + 0 is +0: an end given as -0 was written "-0" in the CSVs and -0.0 in the JSON.
    for (double& x : v)
        x += 0.0;
    return v;
}

} // namespace

std::vector<double> linspace(double from, double to, long count) {
    return spaced(from, to, count, false);
}

std::vector<double> logspace(double from, double to, long count) {
    return spaced(from, to, count, true);
}

void require_line(double from, double to, long steps) {
    if (steps == 1 && from != to)
        throw std::invalid_argument("steps: one value needs from = to, got from " +
                                    detail::format_number(from) + " and to " +
                                    detail::format_number(to));
    if (steps > 1 && from == to)
        throw std::invalid_argument("steps: from = to (" + detail::format_number(from) +
                                    ") is one value, steps = 1, got " + std::to_string(steps));
    // Ends a few doubles apart: 3 to 3.0000000000000004 in 5 steps ran 3 four times over. The
    // values themselves are compared (as the lines make them), not a spacing estimate.
    // Non-finite ends, or a span beyond the doubles, are the callers' range checks to name.
    if (steps < 2 || !std::isfinite(from) || !std::isfinite(to) || !std::isfinite(to - from))
        return;
    const std::vector<double> values = linspace(from, to, steps);
    for (std::size_t k = 1; k < values.size(); ++k) {
        const double between =
            from + (to - from) * static_cast<double>(k) / static_cast<double>(steps - 1);
        const double before =
            from + (to - from) * static_cast<double>(k - 1) / static_cast<double>(steps - 1);
        if (values[k] != values[k - 1] && between != before) continue;
        char spacing[32];
        const double largest = std::max(std::abs(from), std::abs(to));
        std::snprintf(spacing, sizeof spacing, "%.2g", std::nextafter(largest, HUGE_VAL) - largest);
        throw std::invalid_argument("steps: from " + detail::format_number(from) + " to " +
                                    detail::format_number(to) + " in " + std::to_string(steps) +
                                    " steps repeats a value (the doubles there are " + spacing +
                                    " apart); widen the line or take fewer steps");
    }
}

} // namespace gapchain
