#pragma once
/// \file tangent_flow.hpp
/// The variational (tangent) flow of the row along a run: a set of tangent vectors carried by
/// the exact piecewise flow exp(h J) between contact switches. With all 2 Nm unit vectors it
/// accumulates the monodromy matrix of a periodic orbit (MODEL.md §5: no saltation terms, the
/// vector field being continuous across switches).

#include "gapchain/run.hpp"

#include <vector>

namespace gapchain {

/// Observer that advances tangent vectors with the run. Between two steps the contact
/// configuration is fixed (the time loop splits steps at every switch), so for the linear law J
/// is constant there and the tangent flow is exp(h J), applied by its Taylor series to round-off
/// in coordinates (du, dv / omega) that keep |h J| near h omega (omega the fastest angular
/// frequency of the row). Nonlinear contact laws are refused (their J varies within a step).
class TangentFlow final : public Observer {
public:
    /// dyn must outlive the observer; count tangent vectors in [1, 2 Nm], initially the first
    /// count unit vectors (the identity when count = 2 Nm).
    TangentFlow(const Dynamics& dyn, int count);
    void on_step(const StepView& step) override;
    /// Each step propagates count() vectors, each about as costly as the row's own step.
    [[nodiscard]] double step_cost() const override { return m_count; }
    /// Vector k (0-based) in scaled coordinates (du, dv / omega), 2 Nm entries from column(k).
    [[nodiscard]] double* column(int k) { return &m_vectors[static_cast<std::size_t>(k) * m_dim]; }
    /// Number of tangent vectors.
    [[nodiscard]] int count() const { return m_count; }
    /// omega [rad per unit reduced time]: velocities are divided by it in the scaled vectors.
    [[nodiscard]] double scale() const { return m_scale; }
    /// The propagated vectors as a 2 Nm x count column-major matrix in the state's own
    /// coordinates (u, v): with count = 2 Nm, the state transition matrix since the start.
    [[nodiscard]] std::vector<double> unscaled_matrix() const;

private:
    void apply_jacobian(const double* x, double* out) const;
    /// col <- exp(h J) col by its Taylor series, for h max_rate() <= 2.
    void advance(double* col, double h);
    const Dynamics& m_dyn;
    int m_dim;
    int m_count;
    double m_scale;
    std::vector<double> m_vectors;
    std::vector<char> m_closed;
    std::vector<double> m_term, m_next, m_sum;
    mutable std::vector<double> m_dv;
};

} // namespace gapchain
