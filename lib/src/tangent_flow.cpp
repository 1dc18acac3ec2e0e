#include "gapchain/tangent_flow.hpp"

#include "detail/check.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gapchain {

TangentFlow::TangentFlow(const Dynamics& dyn, int count)
    : m_dyn(dyn), m_dim(dyn.dimension()), m_count(count), m_scale(dyn.max_angular_frequency()),
      m_vectors(static_cast<std::size_t>(dyn.dimension()) * count, 0.0), m_closed(dyn.gaps()),
      m_term(dyn.dimension()), m_next(dyn.dimension()), m_sum(dyn.dimension()), m_dv(dyn.bodies()) {
    detail::require_range("count", count, 1, dyn.dimension());
    // exp(h J) with J constant between switches holds for the linear law alone (a Hertz
    // contact's stiffness varies with its penetration).
    if (dyn.chain().law != ContactLaw::linear)
        throw std::invalid_argument(
            "model.contact_law: the tangent flow needs the linear contact law (it assumes a "
            "constant Jacobian between switches; a " +
            std::string(to_string(dyn.chain().law)) +
            " contact's stiffness varies with its penetration), got " + to_string(dyn.chain().law));
    for (int k = 0; k < count; ++k)
        column(k)[k] = 1.0;
}

void TangentFlow::apply_jacobian(const double* x, double* out) const {
    // Scaled coordinates x = (du, dv / w): J' = [[0, w I], [A_u / w, A_v]].
    const int n = m_dyn.bodies();
    const double w = m_scale;
    for (int i = 0; i < n; ++i) {
        out[i] = w * x[n + i];
        m_dv[i] = w * x[n + i];
    }
    m_dyn.tangent_acceleration(m_closed, x, m_dv.data(), out + n);
    for (int i = 0; i < n; ++i)
        out[n + i] /= w;
}

void TangentFlow::on_step(const StepView& step) {
    // The step lies between switches: the contact set is that of its midpoint, on the cubic
    // Hermite interpolant of the gap. The mean of the ends alone is round-off where both ends
    // are switches (a contact that closes and opens again within one step of the plan).
    const double h = step.t1 - step.t0;
    const int n = m_dyn.bodies();
    for (int j = 0; j < m_dyn.gaps(); ++j) {
        const double ends = m_dyn.gap(j, step.y0) + m_dyn.gap(j, step.y1);
        const double rates = m_dyn.gap_rate(j, step.y0 + n) - m_dyn.gap_rate(j, step.y1 + n);
        m_closed[j] = 0.5 * ends + 0.125 * h * rates > 0.0 ? 1 : 0;
    }
    // The Taylor series of exp(h J) loses to cancellation where |h J| is large: the scaled
    // coordinates keep the oscillations near h omega (up to pi / 2 on the exact scheme's
    // output interval), but an overdamped body's rate (its damping, 1257 at eps = 100) is not
    // scaled away. Pieces of h rate <= 2 keep it to round-off.
    const int pieces =
        static_cast<int>(std::clamp(std::ceil(h * m_dyn.max_rate() / 2.0), 1.0, 1e6));
    for (int c = 0; c < m_count; ++c)
        for (int piece = 0; piece < pieces; ++piece)
            advance(column(c), h / pieces);
}

void TangentFlow::advance(double* col, double h) {
    std::copy(col, col + m_dim, m_term.begin());
    std::copy(col, col + m_dim, m_sum.begin());
    for (int k = 1; k <= 60; ++k) {
        apply_jacobian(m_term.data(), m_next.data());
        double term_norm = 0.0, sum_norm = 0.0;
        for (int i = 0; i < m_dim; ++i) {
            m_term[i] = m_next[i] * h / k;
            m_sum[i] += m_term[i];
            term_norm = std::max(term_norm, std::abs(m_term[i]));
            sum_norm = std::max(sum_norm, std::abs(m_sum[i]));
        }
        if (term_norm <= 1e-17 * sum_norm) break;
    }
    std::copy(m_sum.begin(), m_sum.end(), col);
}

std::vector<double> TangentFlow::unscaled_matrix() const {
    // Column k of the scaled flow maps S e_k; the state's own flow is S^-1 Phi' S with
    // S = diag(I, I / w): rows of velocities times w, columns of velocities divided by w.
    const int n = m_dyn.bodies();
    std::vector<double> m(m_vectors);
    for (int k = 0; k < m_count; ++k) {
        const double column_factor = k >= n ? 1.0 / m_scale : 1.0;
        for (int i = 0; i < m_dim; ++i) {
            const double row_factor = i >= n ? m_scale : 1.0;
            m[static_cast<std::size_t>(k) * m_dim + i] *= row_factor * column_factor;
        }
    }
    return m;
}

} // namespace gapchain
