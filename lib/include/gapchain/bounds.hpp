#pragma once
/// \file bounds.hpp
/// The paper's analytic results: the single-body response eq (20) and the no-impact boundary it
/// draws, the smooth-region maximum eq (24) and bound eq (25), the chaotic-region estimate
/// eq (36) and bound eq (37). All forces are reduced (F_phys = F M a0 sqrt(fc)).

namespace gapchain {

/// Eq (20): steady amplitude of one free body, 1 / sqrt((1 - f_r^2)^2 + 4 eps^2 f_r^2).
/// f_r >= 0, eps >= 0, not both f_r = 1 and eps = 0.
double single_body_amplitude(double f_r, double eps);

/// The no-impact boundary in the (e_r, f_r) plane: bodies moving as free bodies in phase reach a
/// wall when e_r < single_body_amplitude(f_r, eps). Returns that critical e_r.
double no_impact_clearance(double f_r, double eps);

/// Eq (21): natural frequency of an end body in contact with its wall, sqrt(1 + fc).
double wall_contact_frequency(double fc);

/// Eq (24): smooth-region maximum F_m = (1 / (2 eps)) sqrt(fc / (1 + fc - eps^2)).
/// fc > 0, 0 < eps, eps^2 < 1 + fc.
double smooth_max_force(double fc, double eps);

/// Eq (25): the smooth-region bound 1 / (2 eps), eps > 0.
double smooth_bound(double eps);

/// Eq (32) with eq (34), F_m = sqrt(fc) Phi_1(1) / (2 eps sqrt(f1^2 - eps^2)) with
/// Phi_1(1) = pi / Nm: the chaotic-region estimate for a given first natural frequency f1
/// (the exact one, or f_1a of eq (26)), f1 > eps > 0.
double chaotic_max_force(int Nm, double fc, double eps, double f1);

/// Eq (36): chaotic_max_force with f1 = f_1a of eq (26).
double chaotic_max_force_approx(int Nm, double fc, double eps);

/// Eq (37): the chaotic-region bound pi / (2 eps sqrt(4.935)), eps > 0.
double chaotic_bound(double eps);

/// Every estimate of the paper for one row (reduced forces; NaN where it does not exist: the
/// force estimates need eps > 0, eq (32) needs f1 > eps).
struct AnalyticEstimates {
    double amplitude = 0.0;               ///< eq (20) at f_r
    bool impacts = false;                 ///< e_r < amplitude: the free bodies reach a wall
    double wall_contact_frequency = 0.0;  ///< eq (21)
    double smooth_max_force = 0.0;        ///< eq (24); NaN where eps = 0 or eps^2 >= 1 + fc
    double smooth_bound = 0.0;            ///< eq (25)
    double chaotic_estimate_approx = 0.0; ///< eq (36), with f_1a of eq (26); NaN: f_1a <= eps
    double chaotic_estimate_exact = 0.0;  ///< eq (32) + (34) with the exact f_1; NaN: f_1 <= eps
    double chaotic_bound = 0.0;           ///< eq (37)
    double f1 = 0.0;                      ///< exact first linear-chain frequency (reduced)
    double f1_approx = 0.0;               ///< f_1a of eq (26)
};

/// The estimates for a row of Nm bodies with reduced parameters (fc, eps, e_r, f_r), given its
/// exact first linear-chain frequency f1 (modes.hpp). An estimate whose formula does not apply
/// is NaN: every force at eps = 0, eq (24) where eps^2 >= 1 + fc, eq (32) and (36) where the
/// first frequency is not above eps.
AnalyticEstimates analytic_estimates(int Nm, double fc, double eps, double e_r, double f_r,
                                     double f1);

} // namespace gapchain
