#pragma once
/// \file grid.hpp
/// Evenly spaced values, the one definition every scene, driver and tool uses.

#include <vector>

namespace gapchain {

/// count values from `from` to `to`, ends included and exact: the k-th is
/// (from (count - 1 - k) + to k) / (count - 1) (the ends are `from` and `to` themselves), so
/// integer ranges stay integers ([1, 100, 100] gives 14, not 14.000000000000002). count >= 1 (1:
/// just from); throws std::invalid_argument for count < 1 or non-finite ends.
std::vector<double> linspace(double from, double to, long count);

/// count values from `from` to `to` evenly spaced in log: from (to / from)^(k / (count - 1)).
/// from, to > 0 and finite, count >= 1; throws std::invalid_argument otherwise.
std::vector<double> logspace(double from, double to, long count);

/// Refuses ends and a count that do not make a line of distinct values: steps = 1 with
/// from != to (only `from` would run) and steps > 1 with from = to (one value run again and
/// again), and ends too few doubles apart for steps distinct values. Throws
/// std::invalid_argument naming "steps" and the values; the range of steps
/// itself is the caller's to check.
void require_line(double from, double to, long steps);

} // namespace gapchain
