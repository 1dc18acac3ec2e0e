#pragma once
// Portable seeded pseudo-randomness: the standard library's distributions differ between
// implementations, which would make seeded samples depend on the compiler.

#include <cmath>
#include <cstdint>
#include <numbers>

namespace gapchain::detail {

// SplitMix64 finaliser.
inline std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

// A hash of three integers.
inline std::uint64_t hash3(std::uint64_t seed, std::uint64_t a, std::uint64_t b) {
    return mix(mix(mix(seed) ^ a) ^ (b * 0xd6e8feb86659fd93ULL));
}

// Uniform in (0, 1) from a hash.
inline double unit_interval(std::uint64_t h) {
    return (static_cast<double>(h >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

// Standard normal number k of stream (seed, stream), by Box-Muller.
inline double standard_normal(std::uint64_t seed, std::uint64_t stream, std::uint64_t k) {
    const double u1 = unit_interval(hash3(seed, stream, 2 * k));
    const double u2 = unit_interval(hash3(seed, stream, 2 * k + 1));
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

} // namespace gapchain::detail
