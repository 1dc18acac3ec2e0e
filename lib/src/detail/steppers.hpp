#pragma once
// Factories of the steppers that live in their own source files.

#include "gapchain/stepper.hpp"

#include <algorithm>
#include <memory>

namespace gapchain::detail {

// GSL odeiv2 adaptive Runge-Kutta (rk8pd if high_order, else rkf45) taking as many internal
// steps as its error control needs within each step it is asked for.
std::unique_ptr<Stepper> make_gsl_stepper(const Dynamics& dyn, bool high_order, double tolerance);

// Exact propagation of the piecewise-linear row between contact switches.
std::unique_ptr<Stepper> make_exact_propagator(const Dynamics& dyn);

// How many contact configurations the exact propagator keeps for a row of `dimension` (2 Nm)
// before it starts its cache afresh: about 1 GB of entries (two complex (2 Nm)^2 matrices, a
// defective one two real ones more: 1.5 times, counted), between 16 and 4096. run_work()
// counts on it: a row whose 2^(Nm + 1) configurations all fit sets each up once.
inline double exact_cache_capacity(int dimension) {
    const double entry_bytes = 3.0 * 16.0 * static_cast<double>(dimension) * dimension;
    return std::clamp(1e9 / entry_bytes, 16.0, 4096.0);
}

} // namespace gapchain::detail
