#pragma once
/// \file dynamics.hpp
/// The reduced equations of motion of a Chain (MODEL.md §2): gaps, contact forces, the
/// right-hand side, the tangent (Jacobian) map and the energy.
///
/// A state is a flat array y = (u_0..u_{Nm-1}, v_0..v_{Nm-1}) of 2 Nm reduced displacements
/// and velocities. Time is reduced time t = f0 t_phys.

#include "gapchain/ground_motion.hpp"
#include "gapchain/model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace gapchain {

/// A body's natural angular frequency on its spring at the nominal mass, in reduced units (time
/// in natural periods): 2 pi [rad / reduced time].
inline constexpr double natural_angular_frequency = 2.0 * std::numbers::pi;

/// Harmonic ground acceleration a0 cos(2 pi f_r t); in the reduced equations every body feels
/// ground(t) = -4 pi^2 amplitude cos(2 pi f_r t).
struct HarmonicForcing {
    double f_r = 1.0;       ///< reduced forcing frequency, > 0
    double amplitude = 1.0; ///< multiple of a0, >= 0 (0 switches the forcing off)
};

/// Equations of motion of one row under one ground motion. Immutable and safe to share between
/// threads; every method is O(Nm) or less.
class Dynamics {
public:
    /// Validates the chain and the forcing (std::invalid_argument on bad values).
    Dynamics(Chain chain, HarmonicForcing forcing);
    /// The row under any ground motion (harmonic, record, synthetic). Validates the chain.
    Dynamics(Chain chain, GroundMotion ground_motion);
    /// The paper's row: Chain::homogeneous(p) under harmonic forcing at p.f_r, unit amplitude.
    static Dynamics paper_row(const ReducedParameters& p);

    [[nodiscard]] const Chain& chain() const { return m_chain; }
    /// What shakes the ground.
    [[nodiscard]] const GroundMotion& ground_motion() const { return m_ground; }
    /// Number of bodies Nm.
    [[nodiscard]] int bodies() const { return m_n; }
    /// Number of contacts Nm + 1 (two walls and Nm - 1 body pairs).
    [[nodiscard]] int gaps() const { return m_n + 1; }
    /// State dimension 2 Nm.
    [[nodiscard]] int dimension() const { return 2 * m_n; }
    /// The time loop's period in reduced time: 1 / f_r (harmonic) or 1 (a record; see
    /// GroundMotion::period()).
    [[nodiscard]] double period() const { return m_ground.period(); }

    /// Ground term of every body's equation at reduced time t: -4 pi^2 a(t), a(t) the ground
    /// acceleration in units of a0 (A cos(2 pi f_r t) for harmonic forcing).
    [[nodiscard]] double ground(double t) const;

    /// Accelerations without the damping term (springs, contacts and ground), given the
    /// ground term. u and r have Nm entries.
    void restoring_acceleration(double ground, const double* u, double* r) const;
    /// Full accelerations a = restoring - damping * v.
    void acceleration(double ground, const double* u, const double* v, double* a) const;
    /// Time derivative of the accelerations (the jerk) at time t, state y and accelerations a
    /// (Nm entries each, jerk out). Used for quintic dense output of the velocities.
    void acceleration_rate(double t, const double* y, const double* a, double* jerk) const;
    /// y' = f(t, y) for y = (u, v); y and dydt have 2 Nm entries.
    void rhs(double t, const double* y, double* dydt) const;

    /// Shape of contact j's force with its rate: phi(g_j) d(g_j') for displacements u and
    /// velocities v.
    [[nodiscard]] double contact_term(int j, const double* u, const double* v) const {
        return shape(gap(j, u)) * dissipation_factor(gap_rate(j, v));
    }
    /// Gap g_j of contact j = 0..Nm (> 0 means penetration), given the displacements u.
    [[nodiscard]] double gap(int j, const double* u) const {
        const double e = m_chain.clearance[j];
        if (j == 0) return -u[0] - e;
        if (j == m_n) return u[m_n - 1] - e;
        return u[j - 1] - u[j] - e;
    }
    /// Time derivative of g_j, given the velocities v (the same combination as the gap).
    [[nodiscard]] double gap_rate(int j, const double* v) const {
        if (j == 0) return -v[0];
        if (j == m_n) return v[m_n - 1];
        return v[j - 1] - v[j];
    }
    /// Every gap at once: g[j] = gap(j, u) for j = 0..Nm (g has Nm + 1 entries).
    void gaps(const double* u, double* g) const;
    /// Every gap rate at once: r[j] = gap_rate(j, v) for j = 0..Nm (r has Nm + 1 entries).
    void gap_rates(const double* v, double* r) const;
    /// Second time derivative of g_j at the state y (2 Nm entries) and ground term.
    [[nodiscard]] double gap_acceleration(int j, double ground, const double* y) const;
    /// Acceleration of body i (0 <= i < Nm) alone at the state y (2 Nm entries) and ground
    /// term: acceleration()'s entry i in O(1).
    [[nodiscard]] double body_acceleration(int i, double ground, const double* y) const;
    /// Reduced impact force of contact j at state y (2 Nm entries): contact_j phi(g_j) d(g_j')
    /// / force_scale (eqs 14-15 for the linear law).
    [[nodiscard]] double force(int j, const double* y) const;
    /// Reduced force of contact j at penetration p >= 0 closing at rate p' (the gap rate):
    /// k_j phi(p) d(p') / force_scale, with phi(p) = p (linear law) or p^(3/2) (Hertz,
    /// Hunt-Crossley) and d the Hunt-Crossley factor (1 for the elastic laws).
    [[nodiscard]] double force_at_penetration(int j, double p, double rate = 0.0) const {
        return m_force_gain[j] * shape(p) * dissipation_factor(rate);
    }
    /// The penetration at which contact j's force at rest (rate 0) reaches force >= 0: the
    /// inverse of force_at_penetration(j, p); +inf where the contact has no stiffness. For the
    /// elastic laws it bounds the force of every penetration below it (Hunt-Crossley's force
    /// also grows with the closing rate).
    [[nodiscard]] double penetration_at_force(int j, double force) const;
    /// Hunt-Crossley's max(0, 1 + alpha p') (1 for the linear and Hertz laws).
    [[nodiscard]] double dissipation_factor(double rate) const {
        return m_alpha == 0.0 ? 1.0 : std::max(0.0, 1.0 + m_alpha * rate);
    }
    /// Whether contact forces depend on the velocities (Hunt-Crossley with alpha > 0).
    [[nodiscard]] bool dissipative_contacts() const { return m_alpha != 0.0; }
    /// The contact law's shape phi(p) for a penetration p (0 for p <= 0).
    [[nodiscard]] double shape(double p) const {
        const double q = std::max(p, 0.0); // branch-free on the linear law's hot path
        return m_hertz ? q * std::sqrt(q) : q;
    }
    /// Its derivative phi'(p) (0 for p <= 0).
    [[nodiscard]] double shape_slope(double p) const {
        if (p <= 0.0) return 0.0;
        return m_hertz ? 1.5 * std::sqrt(p) : 1.0;
    }

    /// Kinetic + spring + contact energy (per nominal mass); conserved when every damping is 0,
    /// the forcing amplitude is 0 and the contacts are elastic (MODEL.md §5).
    [[nodiscard]] double energy(const double* y) const;

    /// Jacobian df/dy at state y, row-major 2Nm x 2Nm into jac (resized). Elastic contact
    /// forces depend on positions only, so then its trace is -sum(damping) at every state.
    void jacobian(const double* y, std::vector<double>& jac) const;

    /// Linearised accelerations for a fixed contact configuration (closed[j] != 0: contact j
    /// closed; linear contact law only, where the Jacobian depends on the configuration alone):
    /// dacc = d(acceleration) for displacement and velocity perturbations du, dv (Nm entries each).
    /// This is the lower half of the Jacobian applied to (du, dv), in O(Nm).
    void tangent_acceleration(const std::vector<char>& closed, const double* du, const double* dv,
                              double* dacc) const;

    /// Accelerations as if exactly the contacts with closed[j] != 0 were closed (linear law
    /// only: their force linear in the gap, clearance included, even where the gap is negative):
    /// the affine right-hand side of one contact configuration, given the ground term.
    void affine_acceleration(const std::vector<char>& closed, double ground, const double* u,
                             const double* v, double* a) const;

    /// Upper bound on the fastest angular frequency [rad / reduced time] (MODEL.md §4).
    [[nodiscard]] double max_angular_frequency() const { return m_omega_max; }
    /// Upper bound on the fastest rate of the row's linearised motion [1 / reduced time]:
    /// max(max_angular_frequency(), largest damping rate). A body damped beyond critical has a
    /// real rate up to its damping rate c = 4 pi eps (1257 at eps = 100, where the fastest
    /// oscillation of a stiff row is 63): an explicit step resolves and stays stable on this.
    [[nodiscard]] double max_rate() const { return m_rate_max; }

private:
    Chain m_chain;
    GroundMotion m_ground;
    int m_n = 0;
    double m_omega_max = 0.0;
    double m_rate_max = 0.0;
    std::vector<double> m_contact_over_mass_left;  ///< 4 pi^2 k_j / m_j for body j's left gap
    std::vector<double> m_contact_over_mass_right; ///< 4 pi^2 k_{j+1} / m_j for the right gap
    std::vector<double> m_force_gain;              ///< k_j / force_scale
    bool m_hertz = false;                          ///< shape p^(3/2) (Hertz, Hunt-Crossley)
    double m_alpha = 0.0;                          ///< Hunt-Crossley damping (0 otherwise)
};

/// Throws std::invalid_argument unless dyn's ground motion is harmonic: `analysis` (its name,
/// e.g. "poincare") samples or averages over the forcing period, which a record does not have.
void require_harmonic(const Dynamics& dyn, const std::string& analysis);

/// The initial state of a run: `initial` (2 Nm finite entries) or, if empty, rest. Throws
/// std::invalid_argument naming the rule otherwise.
std::vector<double> initial_state(const Dynamics& dyn, const std::vector<double>& initial);

} // namespace gapchain
