#pragma once
// Rows and search options shared by the tests of the attractor search and of the modules built
// on it (design value, basin fractions).

#include "gapchain/attractors.hpp"

#include <cstdint>

namespace test {

/// Nm = 1 between the walls, e_r = 0.6, f_r = 1.2: two period-1 orbits, one hitting each wall.
inline const gapchain::ReducedParameters mirror_pair{1, 100, 0.1, 0.6, 1.2};

/// A search of `samples` starts in a box of 2 A, 600-period runs.
inline gapchain::AttractorOptions short_runs(long samples, std::uint64_t seed) {
    gapchain::AttractorOptions o;
    o.samples = samples;
    o.seed = seed;
    o.box = 2.0;
    o.run.periods = 600;
    return o;
}

} // namespace test
