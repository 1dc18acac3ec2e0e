#include "gapchain/dynamics.hpp"

#include "detail/check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace gapchain {

namespace {

/// The linear law's accelerations r_i of a row of n >= 2 bodies: ground - s_i u_i + the contact
/// terms, minus d_i v_i when Damped. The hot path of every long run: the walls are peeled off so
/// that the inner loop has no branch and no loop-carried value, and vectorises (each inner gap
/// is computed twice, which is cheaper than carrying it). The damping term is subtracted last,
/// as a separate pass would: the values are the same to the bit.
template <bool Damped>
void linear_row_acceleration(int n, double ground, const double* u, const double* v,
                             const double* s, const double* d, const double* e, const double* left,
                             const double* right, double* r) {
    r[0] = ground - s[0] * u[0] + left[0] * std::max(-u[0] - e[0], 0.0) -
           right[0] * std::max(u[0] - u[1] - e[1], 0.0);
    if constexpr (Damped) r[0] -= d[0] * v[0];
    for (int i = 1; i < n - 1; ++i) {
        r[i] = ground - s[i] * u[i] + left[i] * std::max(u[i - 1] - u[i] - e[i], 0.0) -
               right[i] * std::max(u[i] - u[i + 1] - e[i + 1], 0.0);
        if constexpr (Damped) r[i] -= d[i] * v[i];
    }
    r[n - 1] = ground - s[n - 1] * u[n - 1] +
               left[n - 1] * std::max(u[n - 2] - u[n - 1] - e[n - 1], 0.0) -
               right[n - 1] * std::max(u[n - 1] - e[n], 0.0);
    if constexpr (Damped) r[n - 1] -= d[n - 1] * v[n - 1];
}

} // namespace

Dynamics::Dynamics(Chain chain, HarmonicForcing forcing)
    : Dynamics(std::move(chain), GroundMotion::harmonic(forcing.f_r, forcing.amplitude)) {}

Dynamics Dynamics::paper_row(const ReducedParameters& p) {
    return {Chain::homogeneous(p), HarmonicForcing{p.f_r, 1.0}};
}

Dynamics::Dynamics(Chain chain, GroundMotion ground_motion)
    : m_chain(std::move(chain)), m_ground(std::move(ground_motion)) {
    validate(m_chain);
    m_n = m_chain.bodies();
    m_omega_max = gapchain::max_angular_frequency(m_chain);
    // Per mode, |lambda| = omega when underdamped and below the damping rate c when not (the
    // fast root c/2 + sqrt(c^2/4 - omega^2)).
    m_rate_max =
        std::max(m_omega_max, *std::max_element(m_chain.damping.begin(), m_chain.damping.end()));
    m_contact_over_mass_left.resize(m_n);
    m_contact_over_mass_right.resize(m_n);
    for (int i = 0; i < m_n; ++i) {
        m_contact_over_mass_left[i] = four_pi_squared * m_chain.contact[i] / m_chain.mass[i];
        m_contact_over_mass_right[i] = four_pi_squared * m_chain.contact[i + 1] / m_chain.mass[i];
    }
    m_hertz = m_chain.law != ContactLaw::linear;
    m_alpha = m_chain.law == ContactLaw::hunt_crossley ? m_chain.contact_damping : 0.0;
    m_force_gain.resize(m_n + 1);
    for (int j = 0; j <= m_n; ++j)
        m_force_gain[j] = m_chain.contact[j] / m_chain.force_scale;
}

double Dynamics::ground(double t) const {
    return -four_pi_squared * m_ground.acceleration(t);
}

void Dynamics::restoring_acceleration(double ground, const double* u, double* r) const {
    const double* e = m_chain.clearance.data();
    const double* s = m_chain.spring.data();
    const double* left = m_contact_over_mass_left.data();
    const double* right = m_contact_over_mass_right.data();
    const int n = m_n;
    if (m_hertz) {
        // Penetration of the gap on the left of body i, carried from one body to the next.
        double p_left = shape(-u[0] - e[0]);
        for (int i = 0; i < n; ++i) {
            const double p_right = shape((i + 1 < n ? u[i] - u[i + 1] : u[i]) - e[i + 1]);
            r[i] = ground - s[i] * u[i] + left[i] * p_left - right[i] * p_right;
            p_left = p_right;
        }
        return;
    }
    if (n == 1) {
        r[0] = ground - s[0] * u[0] + left[0] * std::max(-u[0] - e[0], 0.0) -
               right[0] * std::max(u[0] - e[1], 0.0);
        return;
    }
    linear_row_acceleration<false>(n, ground, u, nullptr, s, nullptr, e, left, right, r);
}

double Dynamics::penetration_at_force(int j, double force) const {
    if (!(force > 0.0)) return 0.0;
    if (!(m_force_gain[j] > 0.0)) return std::numeric_limits<double>::infinity();
    const double shape_value = force / m_force_gain[j];
    return m_hertz ? std::cbrt(shape_value * shape_value) : shape_value;
}

void Dynamics::gaps(const double* u, double* g) const {
    const double* e = m_chain.clearance.data();
    g[0] = -u[0] - e[0];
    for (int j = 1; j < m_n; ++j)
        g[j] = u[j - 1] - u[j] - e[j];
    g[m_n] = u[m_n - 1] - e[m_n];
}

void Dynamics::gap_rates(const double* v, double* r) const {
    r[0] = -v[0];
    for (int j = 1; j < m_n; ++j)
        r[j] = v[j - 1] - v[j];
    r[m_n] = v[m_n - 1];
}

void Dynamics::acceleration(double ground, const double* u, const double* v, double* a) const {
    const double* d = m_chain.damping.data();
    if (m_alpha == 0.0) {
        if (m_hertz || m_n == 1) {
            restoring_acceleration(ground, u, a);
            for (int i = 0; i < m_n; ++i)
                a[i] -= d[i] * v[i];
        } else {
            linear_row_acceleration<true>(m_n, ground, u, v, m_chain.spring.data(), d,
                                          m_chain.clearance.data(), m_contact_over_mass_left.data(),
                                          m_contact_over_mass_right.data(), a);
        }
        return;
    }
    // Hunt-Crossley: every contact force also depends on its gap rate.
    const double* s = m_chain.spring.data();
    double p_left = contact_term(0, u, v);
    for (int i = 0; i < m_n; ++i) {
        const double p_right = contact_term(i + 1, u, v);
        a[i] = ground - s[i] * u[i] - d[i] * v[i] + m_contact_over_mass_left[i] * p_left -
               m_contact_over_mass_right[i] * p_right;
        p_left = p_right;
    }
}

void Dynamics::acceleration_rate(double t, const double* y, const double* a, double* jerk) const {
    const double* u = y;
    const double* v = y + m_n;
    const double ground_rate = -four_pi_squared * m_ground.acceleration_rate(t);
    // A closed contact's penetration changes at the gap rate, an open one's not at all.
    // d phi(p)/dt = phi'(p) dg/dt on a closed contact, 0 on an open one; Hunt-Crossley adds
    // phi(p) alpha g'' while its factor 1 + alpha g' is positive (g'' from the accelerations,
    // the same combination as the gap).
    auto penetration_rate = [&](int j) {
        const double g = gap(j, u);
        const double rate = gap_rate(j, v);
        const double factor = dissipation_factor(rate);
        double r = shape_slope(g) * rate * factor;
        if (m_alpha != 0.0 && factor > 0.0) r += shape(g) * m_alpha * gap_rate(j, a);
        return r;
    };
    double q_left = penetration_rate(0);
    for (int i = 0; i < m_n; ++i) {
        const double q_right = penetration_rate(i + 1);
        jerk[i] = ground_rate - m_chain.spring[i] * v[i] - m_chain.damping[i] * a[i] +
                  m_contact_over_mass_left[i] * q_left - m_contact_over_mass_right[i] * q_right;
        q_left = q_right;
    }
}

void Dynamics::rhs(double t, const double* y, double* dydt) const {
    std::copy(y + m_n, y + 2 * m_n, dydt);
    acceleration(ground(t), y, y + m_n, dydt + m_n);
}

double Dynamics::body_acceleration(int i, double ground, const double* y) const {
    const double* u = y;
    const double* v = y + m_n;
    const double p_l = contact_term(i, u, v);
    const double p_r = contact_term(i + 1, u, v);
    return ground - m_chain.spring[i] * u[i] - m_chain.damping[i] * v[i] +
           m_contact_over_mass_left[i] * p_l - m_contact_over_mass_right[i] * p_r;
}

double Dynamics::gap_acceleration(int j, double ground, const double* y) const {
    // Only the (at most) two bodies on either side of gap j matter: O(1) per call.
    if (j == 0) return -body_acceleration(0, ground, y);
    if (j == m_n) return body_acceleration(m_n - 1, ground, y);
    return body_acceleration(j - 1, ground, y) - body_acceleration(j, ground, y);
}

double Dynamics::force(int j, const double* y) const {
    return m_force_gain[j] * contact_term(j, y, y + m_n);
}

double Dynamics::energy(const double* y) const {
    const double* u = y;
    const double* v = y + m_n;
    double e = 0.0;
    for (int i = 0; i < m_n; ++i)
        e += 0.5 * m_chain.mass[i] * (v[i] * v[i] + m_chain.spring[i] * u[i] * u[i]);
    for (int j = 0; j <= m_n; ++j) {
        // Potential of the contact force: p^2 / 2 (linear) or 2 p^(5/2) / 5 (Hertz).
        const double p = std::max(gap(j, u), 0.0);
        e += four_pi_squared * m_chain.contact[j] *
             (m_hertz ? 0.4 * p * p * std::sqrt(p) : 0.5 * p * p);
    }
    return e;
}

void Dynamics::tangent_acceleration(const std::vector<char>& closed, const double* du,
                                    const double* dv, double* dacc) const {
    const int n = m_n;
    // A closed contact's penetration follows its gap: dp_j = dg_j; an open one's stays 0.
    double dp_left = closed[0] ? -du[0] : 0.0;
    for (int i = 0; i < n; ++i) {
        double dp_right = 0.0;
        if (closed[i + 1]) dp_right = i + 1 < n ? du[i] - du[i + 1] : du[i];
        dacc[i] = -m_chain.spring[i] * du[i] - m_chain.damping[i] * dv[i] +
                  m_contact_over_mass_left[i] * dp_left - m_contact_over_mass_right[i] * dp_right;
        dp_left = dp_right;
    }
}

void Dynamics::affine_acceleration(const std::vector<char>& closed, double ground, const double* u,
                                   const double* v, double* a) const {
    const int n = m_n;
    double p_left = closed[0] ? gap(0, u) : 0.0;
    for (int i = 0; i < n; ++i) {
        const double p_right = closed[i + 1] ? gap(i + 1, u) : 0.0;
        a[i] = ground - m_chain.spring[i] * u[i] - m_chain.damping[i] * v[i] +
               m_contact_over_mass_left[i] * p_left - m_contact_over_mass_right[i] * p_right;
        p_left = p_right;
    }
}

void Dynamics::jacobian(const double* y, std::vector<double>& jac) const {
    const int n = m_n;
    const int dim = 2 * n;
    jac.assign(static_cast<std::size_t>(dim) * dim, 0.0);
    auto at = [&](int r, int c) -> double& { return jac[static_cast<std::size_t>(r) * dim + c]; };
    for (int i = 0; i < n; ++i) {
        at(i, n + i) = 1.0;
        at(n + i, i) = -m_chain.spring[i];
        at(n + i, n + i) = -m_chain.damping[i];
    }
    // A closed contact j adds k_j (c_j c_j^T) with c_j the gap's combination of displacements;
    // an open one adds nothing. At g_j = 0 exactly we take the open branch (one-sided limit).
    for (int j = 0; j <= n; ++j) {
        if (gap(j, y) <= 0.0) continue;
        const int left = j - 1; // body whose displacement enters g_j with +1 (or none)
        const int right = j;    // body whose displacement enters g_j with -1 (or none)
        const double g = gap(j, y);
        const double factor = dissipation_factor(gap_rate(j, y + n));
        // d(force)/d(gap) and, for Hunt-Crossley, d(force)/d(gap rate): both enter through the
        // same combination c_j, one in the displacement columns, one in the velocity columns.
        const double k = four_pi_squared * m_chain.contact[j] * shape_slope(g) * factor;
        const double c =
            factor > 0.0 ? four_pi_squared * m_chain.contact[j] * shape(g) * m_alpha : 0.0;
        for (const auto& [col0, w] : {std::pair{0, k}, std::pair{n, c}}) {
            if (w == 0.0) continue;
            if (left >= 0) at(n + left, col0 + left) -= w / m_chain.mass[left];
            if (right < n) at(n + right, col0 + right) -= w / m_chain.mass[right];
            if (left >= 0 && right < n) {
                at(n + left, col0 + right) += w / m_chain.mass[left];
                at(n + right, col0 + left) += w / m_chain.mass[right];
            }
        }
    }
}

void require_harmonic(const Dynamics& dyn, const std::string& analysis) {
    if (!dyn.ground_motion().is_harmonic())
        throw std::invalid_argument(analysis + ": needs harmonic forcing (excitation.type = "
                                               "harmonic): it works per forcing period, and a "
                                               "ground-motion record has none");
}

std::vector<double> initial_state(const Dynamics& dyn, const std::vector<double>& initial) {
    if (initial.empty()) return std::vector<double>(dyn.dimension(), 0.0);
    detail::require_length("initial state", initial.size(),
                           static_cast<std::size_t>(dyn.dimension()));
    for (double x : initial)
        if (!std::isfinite(x))
            throw std::invalid_argument("initial: every entry must be finite, got " +
                                        detail::format_number(x));
    return initial;
}

} // namespace gapchain
