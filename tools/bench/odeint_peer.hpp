#pragma once
// The peer of gapchain-bench peer: the loop a user writes with Boost.Odeint in an afternoon.

#include "gapchain/dynamics.hpp"

namespace gapchain::bench {

/// F_m and the run's cost as the peer measures them.
struct PeerRun {
    double F_m = 0.0;   ///< largest contact force read at the accepted steps (no peak search)
    long steps = 0;     ///< accepted steps
    double seconds = 0; ///< wall time [s]
};

/// Boost.Odeint's adaptive Dormand-Prince 5(4) (controlled stepper, absolute and relative
/// tolerance `tolerance`) on dyn's right-hand side from rest over `periods` forcing periods;
/// forces are read at the accepted steps from period `transient` on.
PeerRun odeint_dopri5(const Dynamics& dyn, long periods, long transient, double tolerance);

} // namespace gapchain::bench
