#pragma once
// Spectra operator y = (T - sigma I)^-1 x for a symmetric tridiagonal T, by an LDL^T
// factorisation in O(n). With sigma outside the spectrum T - sigma I is definite, so the
// factorisation needs no pivoting and is stable. Far cheaper than a general sparse LU on the
// long chains (Nm up to 1e6) where the sparse solver is used.

#include "gapchain/modes.hpp"

#include <Eigen/Core>

#include <stdexcept>
#include <vector>

namespace gapchain::detail {

class TridiagonalShiftSolve {
public:
    using Scalar = double;

    explicit TridiagonalShiftSolve(const Tridiagonal& t)
        : m_t(t), m_n(static_cast<Eigen::Index>(t.diagonal.size())), m_d(t.diagonal.size()),
          m_l(t.off_diagonal.size()) {}

    [[nodiscard]] Eigen::Index rows() const { return m_n; }
    [[nodiscard]] Eigen::Index cols() const { return m_n; }

    void set_shift(double sigma) {
        m_d[0] = m_t.diagonal[0] - sigma;
        for (Eigen::Index i = 0; i + 1 < m_n; ++i) {
            if (m_d[i] == 0.0) throw std::invalid_argument("shift-solve: singular shifted matrix");
            m_l[i] = m_t.off_diagonal[i] / m_d[i];
            m_d[i + 1] = m_t.diagonal[i + 1] - sigma - m_l[i] * m_t.off_diagonal[i];
        }
    }

    // y = (T - sigma I)^-1 x: L z = x, D w = z, L^T y = w.
    void perform_op(const double* x, double* y) const {
        y[0] = x[0];
        for (Eigen::Index i = 1; i < m_n; ++i)
            y[i] = x[i] - m_l[i - 1] * y[i - 1];
        for (Eigen::Index i = 0; i < m_n; ++i)
            y[i] /= m_d[i];
        for (Eigen::Index i = m_n - 2; i >= 0; --i)
            y[i] -= m_l[i] * y[i + 1];
    }

private:
    const Tridiagonal& m_t;
    Eigen::Index m_n;
    std::vector<double> m_d;
    std::vector<double> m_l;
};

} // namespace gapchain::detail
