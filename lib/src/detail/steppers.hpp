#pragma once
// Factories of the steppers that live in their own source files.

#include "gapchain/stepper.hpp"

#include <memory>

namespace gapchain::detail {

// GSL odeiv2 adaptive Runge-Kutta (rk8pd if high_order, else rkf45) taking as many internal
// steps as its error control needs within each step it is asked for.
std::unique_ptr<Stepper> make_gsl_stepper(const Dynamics& dyn, bool high_order, double tolerance);

// Exact propagation of the piecewise-linear row between contact switches.
std::unique_ptr<Stepper> make_exact_propagator(const Dynamics& dyn);

} // namespace gapchain::detail
