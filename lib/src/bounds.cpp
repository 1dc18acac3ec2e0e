#include "gapchain/bounds.hpp"

#include "detail/check.hpp"
#include "gapchain/modes.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace gapchain {

using detail::Bound;
using detail::require_range;

double single_body_amplitude(double f_r, double eps) {
    require_range("f_r", f_r, 0.0, 1e6);
    require_range("eps", eps, 0.0, 100.0);
    // hypot, not the sum of squares: eps = 1e-200 at f_r = 1 underflowed to 0 there and was
    // refused as undamped (a reviewer's probe, helper-75).
    const double d = std::hypot(1.0 - f_r * f_r, 2.0 * eps * f_r);
    if (d == 0.0)
        throw std::invalid_argument("eps: must be > 0 at f_r = 1 (undamped resonance), got 0");
    return 1.0 / d;
}

double no_impact_clearance(double f_r, double eps) {
    return single_body_amplitude(f_r, eps);
}

double wall_contact_frequency(double fc) {
    require_range("fc", fc, 0.0, 1e12, Bound::open_low);
    return std::sqrt(1.0 + fc);
}

double smooth_max_force(double fc, double eps) {
    require_range("fc", fc, 0.0, 1e12, Bound::open_low);
    require_range("eps", eps, 0.0, 100.0, Bound::open_low);
    if (eps * eps >= 1.0 + fc)
        throw std::invalid_argument("eps: eq (24) needs eps^2 < 1 + fc, got eps = " +
                                    detail::format_number(eps));
    return std::sqrt(fc / (1.0 + fc - eps * eps)) / (2.0 * eps);
}

double smooth_bound(double eps) {
    require_range("eps", eps, 0.0, 100.0, Bound::open_low);
    return 1.0 / (2.0 * eps);
}

double chaotic_max_force(int Nm, double fc, double eps, double f1) {
    require_range("Nm", Nm, 1, 1'000'000'000);
    require_range("fc", fc, 0.0, 1e12, Bound::open_low);
    require_range("eps", eps, 0.0, 100.0, Bound::open_low);
    if (!(f1 > eps))
        throw std::invalid_argument("f1: eq (32) needs f1 > eps, got f1 = " +
                                    detail::format_number(f1));
    const double u1m =
        approx_first_mode_end_amplitude(Nm) / (2.0 * eps * std::sqrt(f1 * f1 - eps * eps));
    return std::sqrt(fc) * u1m;
}

double chaotic_max_force_approx(int Nm, double fc, double eps) {
    return chaotic_max_force(Nm, fc, eps, approx_frequency(1, Nm, fc));
}

double chaotic_bound(double eps) {
    require_range("eps", eps, 0.0, 100.0, Bound::open_low);
    return std::numbers::pi / (2.0 * eps * std::sqrt(4.935));
}

AnalyticEstimates analytic_estimates(int Nm, double fc, double eps, double e_r, double f_r,
                                     double f1) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    AnalyticEstimates a;
    a.amplitude = single_body_amplitude(f_r, eps);
    a.impacts = e_r < a.amplitude;
    a.wall_contact_frequency = wall_contact_frequency(fc);
    a.f1 = f1;
    a.f1_approx = approx_frequency(1, Nm, fc);
    const bool damped = eps > 0.0;
    // Where a formula does not apply (eq (24) needs eps^2 < 1 + fc, eq (32) f1 > eps) its
    // estimate is left out, as every estimate is at eps = 0, rather than refusing the rest.
    a.smooth_max_force = damped && eps * eps < 1.0 + fc ? smooth_max_force(fc, eps) : nan;
    a.smooth_bound = damped ? smooth_bound(eps) : nan;
    a.chaotic_estimate_approx =
        damped && a.f1_approx > eps ? chaotic_max_force_approx(Nm, fc, eps) : nan;
    a.chaotic_estimate_exact = damped && f1 > eps ? chaotic_max_force(Nm, fc, eps, f1) : nan;
    a.chaotic_bound = damped ? chaotic_bound(eps) : nan;
    return a;
}

} // namespace gapchain
