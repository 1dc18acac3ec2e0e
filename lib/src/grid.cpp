#include "gapchain/grid.hpp"

#include "detail/check.hpp"

#include <cmath>
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
    for (long k = 1; k + 1 < count; ++k) {
        const double x = static_cast<double>(k);
        v[k] = log ? from * std::pow(to / from, x / intervals)
                   : (from * (intervals - x) + to * x) / intervals;
    }
    // (x (count - 1)) / (count - 1) may round off x: the ends are the ends.
    if (count > 1) v.back() = to;
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
}

} // namespace gapchain
