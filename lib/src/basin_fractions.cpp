#include "gapchain/basin_fractions.hpp"

#include "gapchain/grid.hpp"

#include "detail/attractor_search.hpp"
#include "detail/check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace gapchain {

using detail::state_scale;
using detail::StateScale;

namespace {

/// Mean of an attractor's section points, in scaled coordinates.
std::vector<double> centroid(const Attractor& a, const StateScale& scale) {
    std::vector<double> c(a.section.front().size(), 0.0);
    for (const auto& x : a.section)
        for (std::size_t i = 0; i < c.size(); ++i)
            c[i] += x[i] / scale.of(static_cast<int>(i)) / static_cast<double>(a.section.size());
    return c;
}

/// Where each of previous's attractors went at the next value p (Attractors.jl's seeding): the
/// attractor of `next` that a run at p from a state on it reaches, or -1. An attractor that
/// persists is followed however far it moved; one that died hands its label to where its
/// state now goes only if no other seed nearer in F_m reaches that attractor, and never across
/// a jump of F_m by more than 25 % (match_labels()).
std::vector<int> seeded_successors(const AttractorSet& previous, const AttractorSet& next,
                                   const ReducedParameters& p, const AttractorOptions& o,
                                   const ProgressCallback& keep_going) {
    const Dynamics dyn = Dynamics::paper_row(p);
    const StateScale scale = state_scale(p);
    std::vector<int> successor;
    for (const auto& a : previous.attractors)
        successor.push_back(
            detail::attractor_reached_from(dyn, o, a.state, next.attractors, scale, keep_going));
    return successor;
}

/// Labels for `next`'s attractors. First the seeds: an attractor that a previous one's seed
/// reached takes that one's label (of several seeds, the one with the nearest F_m). Then
/// the rest by nearest centroid (within 0.2, scaled), each previous label used once, nearest
/// pairs first; a new label otherwise. Either way the two F_m are within 25 %.
std::vector<int> match_labels(const AttractorSet& previous, const std::vector<int>& previous_labels,
                              const AttractorSet& next, const std::vector<int>& successor,
                              const StateScale& previous_scale, const StateScale& next_scale,
                              int& label_count) {
    struct Pair {
        bool seeded;
        double force_gap; // |F_m - F_m'| / max(F_m, F_m')
        double distance;
        std::size_t from, to;
    };
    std::vector<std::vector<double>> before, after;
    for (const auto& a : previous.attractors)
        before.push_back(centroid(a, previous_scale));
    for (const auto& a : next.attractors)
        after.push_back(centroid(a, next_scale));
    std::vector<Pair> pairs;
    for (std::size_t i = 0; i < before.size(); ++i)
        for (std::size_t j = 0; j < after.size(); ++j) {
            double d = 0.0;
            for (std::size_t m = 0; m < before[i].size(); ++m)
                d = std::max(d, std::abs(before[i][m] - after[j][m]));
            const bool seeded = successor[i] == static_cast<int>(j);
            const double a = previous.attractors[i].F_m, b = next.attractors[j].F_m;
            const double gap = std::max(a, b) > 0.0 ? std::abs(a - b) / std::max(a, b) : 0.0;
            // F_m moves continuously along an attractor that persists: a jump of more than 25 %
            // from one value to the next is another attractor, whatever the seed or the
            // centroid say (a seed whose attractor died lands on one that lives on).
            if (gap <= 0.25 && (seeded || d <= 0.2)) pairs.push_back({seeded, gap, d, i, j});
        }
    // Of several seeds that reach one attractor (the others' attractors died into it), the one
    // whose F_m it continues wins: F_m moves continuously along an attractor, while the
    // centroid of a chaotic cloud says little.
    std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
        if (x.seeded != y.seeded) return x.seeded;
        if (x.seeded && x.force_gap != y.force_gap) return x.force_gap < y.force_gap;
        return x.distance < y.distance;
    });
    std::vector<int> labels(next.attractors.size(), -1);
    std::vector<char> used(previous.attractors.size(), 0);
    for (const Pair& pr : pairs)
        if (!used[pr.from] && labels[pr.to] < 0) {
            used[pr.from] = 1;
            labels[pr.to] = previous_labels[pr.from];
        }
    for (int& l : labels)
        if (l < 0) l = label_count++;
    return labels;
}

} // namespace

std::vector<double> fraction_line_values(const ReducedParameters& base, SweptParameter parameter,
                                         double from, double to, int steps) {
    for (const auto& [name, value] : {std::pair{"from", from}, std::pair{"to", to}}) {
        auto error = swept_value_error(base, parameter, value);
        if (!error) error = detail::search_row_error(with_value(base, parameter, value));
        if (error) throw std::invalid_argument(std::string(name) + ": " + *error);
    }
    detail::require_range("steps", steps, 1, 10000);
    require_line(from, to, steps);
    // Not linspace(): the documented figures were made with these values, bit for bit.
    std::vector<double> values;
    for (int k = 0; k < steps; ++k)
        values.push_back(steps == 1 ? from : from + (to - from) * k / (steps - 1));
    // The last is `to` as written: from 3 to 1e-300 in 3 steps ended at 0 (refused as "to: got
    // 0"); the documented lines end on `to` either way.
    values.back() = to;
    return values;
}

namespace {

/// Validates each value's search and checks the line as a whole against run.max_work (10,000
/// values, each within the limit, were accepted with an estimate of 17 hours); a row refused at
/// an end names its option.
void require_line_affordable(const ReducedParameters& base, SweptParameter parameter,
                             const std::vector<double>& values, const AttractorOptions& options) {
    double body_steps = 0.0;
    for (std::size_t k = 0; k < values.size(); ++k) {
        const ReducedParameters p = with_value(base, parameter, values[k]);
        try {
            validate(p, options);
        } catch (const std::invalid_argument& e) {
            detail::rethrow_naming_end(e, k == 0                   ? "from"
                                          : k + 1 == values.size() ? "to"
                                                                   : nullptr);
        }
        const Dynamics dyn = Dynamics::paper_row(p);
        body_steps += detail::search_body_steps(dyn, options);
    }
    detail::require_work(body_steps, options.run.max_work, "this line runs up to",
                         std::to_string(values.size()) + " searches, every start at full length",
                         "fewer values (steps), fewer starts, a shorter run.periods, or raise "
                         "run.max_work");
}

} // namespace

FractionContinuation
continue_basin_fractions(const ReducedParameters& base, SweptParameter parameter,
                         const std::vector<double>& values, const AttractorOptions& options,
                         const ProgressCallback& progress, const FractionValueCallback& on_value) {
    const auto clock = std::chrono::steady_clock::now();
    if (values.empty()) throw std::invalid_argument("steps: at least one value, got none");
    require_line_affordable(base, parameter, values, options);
    FractionContinuation fc;
    fc.parameter = parameter;
    for (std::size_t k = 0; k < values.size(); ++k) {
        const ReducedParameters p = with_value(base, parameter, values[k]);
        const auto n = static_cast<double>(values.size());
        const ProgressCallback keep_going = [&](double f) {
            return !progress || progress((static_cast<double>(k) + f) / n);
        };
        AttractorSet set = find_attractors(p, options, keep_going);
        if (set.cancelled) {
            fc.cancelled = true;
            break;
        }
        std::vector<int> labels;
        if (k == 0) {
            for (const auto& a : set.attractors)
                labels.push_back(a.id);
            fc.label_count = static_cast<int>(labels.size());
        } else {
            // The seeds report this value as done (their own fractions would run backwards).
            const auto successor = seeded_successors(fc.sets.back(), set, p, options,
                                                     [&](double) { return keep_going(1.0); });
            if (!keep_going(1.0)) {
                fc.cancelled = true;
                break;
            }
            const ReducedParameters q = with_value(base, parameter, values[k - 1]);
            labels = match_labels(fc.sets.back(), fc.labels.back(), set, successor, state_scale(q),
                                  state_scale(p), fc.label_count);
        }
        fc.values.push_back(values[k]);
        fc.sets.push_back(std::move(set));
        fc.labels.push_back(std::move(labels));
        if (on_value) on_value(fc);
    }
    fc.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    return fc;
}

} // namespace gapchain
