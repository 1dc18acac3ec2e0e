#include "bench/odeint_peer.hpp"

#include <boost/numeric/odeint.hpp>

#include <algorithm>
#include <chrono>
#include <vector>

namespace gapchain::bench {

PeerRun odeint_dopri5(const Dynamics& dyn, long periods, long transient, double tolerance) {
    namespace odeint = boost::numeric::odeint;
    using State = std::vector<double>;
    const auto start = std::chrono::steady_clock::now();
    State y(dyn.dimension(), 0.0);
    const double t_record = static_cast<double>(transient) * dyn.period();
    PeerRun out;
    auto rhs = [&dyn](const State& x, State& dxdt, double t) { dyn.rhs(t, x.data(), dxdt.data()); };
    auto observe = [&](const State& x, double t) {
        ++out.steps;
        if (t < t_record) return;
        for (int j = 0; j < dyn.gaps(); ++j)
            out.F_m = std::max(out.F_m, dyn.force(j, x.data()));
    };
    auto stepper = odeint::make_controlled<odeint::runge_kutta_dopri5<State>>(tolerance, tolerance);
    // The first step: a tenth of the fastest contact period; the controller adapts it.
    const double h0 = 0.1 / dyn.max_angular_frequency();
    odeint::integrate_adaptive(stepper, rhs, y, 0.0, static_cast<double>(periods) * dyn.period(),
                               h0, observe);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

} // namespace gapchain::bench
