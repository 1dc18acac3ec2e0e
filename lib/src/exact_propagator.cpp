#include "detail/check.hpp"
#include "detail/steppers.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace gapchain::detail {

namespace {

using Complex = std::complex<double>;

// Between two contact switches the row is linear with constant coefficients:
//   y' = A y + c + Re(b e^{i w t}),   b = (0, -4 pi^2 amplitude 1),
// so y(t) = y_p(t) + V e^{Lambda (t - t0)} V^-1 (y(t0) - y_p(t0)) with the particular solution
// y_p(t) = Re(Z e^{i w t}) + z0, (i w - A) Z = b, A z0 = -c, and A = V Lambda V^-1. The
// eigendecomposition is cached per contact configuration; a step then costs two O(n^2)
// complex matrix-vector products and is exact to round-off for any length, and the same
// formula gives the state at any time inside the last step (dense output).
class ExactPropagator final : public Stepper {
public:
    explicit ExactPropagator(const Dynamics& dyn)
        : m_dyn(dyn), m_n(dyn.bodies()), m_dim(2 * dyn.bodies()), m_closed(dyn.gaps()),
          m_omega(2.0 * std::numbers::pi * dyn.ground_motion().f_r()) {}

    void step(double t, double h, std::vector<double>& y) override {
        choose_configuration(t, y.data(), h);
        Configuration& c = configuration();
        Eigen::Map<const Eigen::VectorXd> y0(y.data(), m_dim);
        m_t0 = t;
        m_last = &c;
        m_r0 = y0 - particular(c, t);
        if (!c.defective) m_w0 = c.v_inverse * m_r0.cast<Complex>();
        // Step lengths from the period grid differ in their last bits from step to step (an
        // exact comparison missed half the time): a length within 8 ulps reuses the flow, whose
        // error is then |A| 8 ulps h, round-off.
        if (c.defective && !(std::abs(h - c.step_tau) <= 8 * unit_roundoff * h)) {
            c.step_flow = (c.a * h).exp();
            c.step_tau = h;
        }
        state_at(t + h, y.data());
        ++m_evaluations;
    }

    bool dense_state(double t, double* y) const override {
        if (m_last == nullptr) return false;
        state_at(t, y);
        return true;
    }

private:
    struct Configuration {
        Eigen::MatrixXcd v;
        Eigen::MatrixXcd v_inverse;
        Eigen::VectorXcd lambda;
        Eigen::VectorXcd z; // forced response amplitude
        Eigen::VectorXd z0; // static offset of the closed contacts' clearances
        // A with no reliable eigenbasis (critical damping: a repeated eigenvalue with one
        // eigenvector), propagated by its matrix exponential instead; empty otherwise.
        bool defective = false;
        Eigen::MatrixXd a;
        // exp(A tau) at the last step length taken in it: most steps have the plan's length.
        double step_tau = -1.0;
        Eigen::MatrixXd step_flow;
    };

    // A contact counts as closed if it will be penetrated just after the start of the step:
    // the sign of g + g' d + g'' d^2 / 2 at d = h / 1000. Away from g = 0 that is the sign of
    // g; on the surface it is decided by g', and where g = g' = 0 (bodies moving in lockstep
    // with e_r = 0) by g''. Freezing a wrong choice for a whole step would be an O(1) error.
    void choose_configuration(double t, const double* y, double h) {
        const double d = 1e-3 * h;
        const double ground = m_dyn.ground(t);
        for (int j = 0; j < m_dyn.gaps(); ++j) {
            const double g = m_dyn.gap(j, y);
            const double rate = m_dyn.gap_rate(j, y + m_n);
            double predicted = g + rate * d;
            if (std::abs(g) < 1e-3 * (std::abs(rate) * h + 1e-12))
                predicted += 0.5 * m_dyn.gap_acceleration(j, ground, y) * d * d;
            m_closed[j] = predicted > 0.0 ? 1 : 0;
        }
    }

    // At critical damping (eps = 1 in a contact-free mode: lambda = -2 pi twice) A is
    // defective and the computed eigenvectors nearly parallel: V Lambda V^-1 missed A by
    // 6e-3 relative and the states by 9e-3 (Nm = 2, fc = 100, e_r = 0.3, f_r = 1, against
    // rk8pd at 1e-11). Where the decomposition misses A by more than 1e-10 relative, this
    // configuration is propagated by exp(A t) (scaling and squaring, O(Nm^3) per state).
    // With 1e-6, configurations near critical still left errors of 5e-8 that varied from
    // cycle to cycle, so that Fig 13's row at eps = 1 never repeated to the steady state's
    // 1e-9. Healthy configurations miss by 1e-15 to 1e-13 on rows of up to 10 bodies (fc up
    // to 1e7). The price: Fig 13's row at eps = 1 runs 8 times slower than at 0.9999 (steps
    // split at switches and dense states each take an exponential); a 60-body row, whose
    // contact-free modes share one frequency, misses by up to 2e-8 and takes this path,
    // 8 times slower and 20 times closer to rk8pd (6e-8 -> 3e-9).
    static void mark_if_defective(Configuration& conf, const Eigen::MatrixXd& a) {
        const double mismatch =
            (conf.v * conf.lambda.asDiagonal() * conf.v_inverse - a.cast<Complex>()).norm();
        if (!(mismatch <= 1e-10 * a.norm())) {
            conf.defective = true;
            conf.a = a;
        }
    }

    Configuration& configuration() {
        const std::string key(m_closed.begin(), m_closed.end());
        auto it = m_cache.find(key);
        if (it != m_cache.end()) return it->second;
        // A chaotic long row can visit a great many configurations: bound the memory to about
        // 1 GB by starting the cache afresh when it is full (4096 entries of Nm = 150 took
        // 4.5 GB and more).
        const auto capacity = static_cast<std::size_t>(detail::exact_cache_capacity(m_dim));
        if (m_cache.size() >= capacity) {
            m_cache.clear();
            m_last = nullptr;
        }
        // Columns of A from the affine right-hand side of this configuration.
        Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m_dim, m_dim);
        std::vector<double> u(m_n, 0.0), v(m_n, 0.0), acc(m_n), offset(m_n);
        m_dyn.affine_acceleration(m_closed, 0.0, u.data(), v.data(), offset.data());
        for (int j = 0; j < m_dim; ++j) {
            std::fill(u.begin(), u.end(), 0.0);
            std::fill(v.begin(), v.end(), 0.0);
            (j < m_n ? u[j] : v[j - m_n]) = 1.0;
            m_dyn.affine_acceleration(m_closed, 0.0, u.data(), v.data(), acc.data());
            if (j >= m_n) a(j - m_n, j) = 1.0;
            for (int i = 0; i < m_n; ++i)
                a(m_n + i, j) = acc[i] - offset[i];
        }
        Eigen::VectorXd c = Eigen::VectorXd::Zero(m_dim);
        for (int i = 0; i < m_n; ++i)
            c[m_n + i] = offset[i];
        Configuration conf;
        Eigen::EigenSolver<Eigen::MatrixXd> eigen(a);
        conf.v = eigen.eigenvectors();
        conf.lambda = eigen.eigenvalues();
        conf.v_inverse = conf.v.inverse();
        mark_if_defective(conf, a);
        Eigen::VectorXcd b = Eigen::VectorXcd::Zero(m_dim);
        for (int i = 0; i < m_n; ++i)
            b[m_n + i] = -four_pi_squared * m_dyn.ground_motion().amplitude();
        const Eigen::MatrixXcd shifted =
            Complex(0.0, m_omega) * Eigen::MatrixXcd::Identity(m_dim, m_dim) - a.cast<Complex>();
        // A configuration with a free mode at the forcing frequency (only an undamped row has
        // one) answers with a response growing as t sin(w t): no particular solution of this
        // form exists, and the solve would return round-off amplified without bound.
        for (const Complex& l : conf.lambda)
            if (std::abs(Complex(0.0, m_omega) - l) <= exact_resonance_tolerance * m_omega ||
                std::abs(Complex(0.0, -m_omega) - l) <= exact_resonance_tolerance * m_omega)
                throw std::invalid_argument(
                    "run.scheme: exact cannot take an undamped row forced at a natural frequency "
                    "of one of its contact configurations (f_r = " +
                    detail::format_number(m_omega / (2.0 * std::numbers::pi)) +
                    ": the response grows as t sin); use rk4 or rk8pd");
        conf.z = shifted.partialPivLu().solve(b);
        conf.z0 = a.partialPivLu().solve(-c);
        return m_cache.emplace(key, std::move(conf)).first->second;
    }

    Eigen::VectorXd particular(const Configuration& c, double t) const {
        return (c.z * std::exp(Complex(0.0, m_omega * t))).real() + c.z0;
    }

    void state_at(double t, double* y) const {
        const Configuration& c = *m_last;
        Eigen::Map<Eigen::VectorXd> state(y, m_dim);
        if (c.defective) {
            const double tau = t - m_t0;
            const bool step_end = std::abs(tau - c.step_tau) <= 8 * unit_roundoff * c.step_tau;
            state = (step_end ? c.step_flow : Eigen::MatrixXd((c.a * tau).exp())) * m_r0 +
                    particular(c, t);
            return;
        }
        const Eigen::VectorXcd decayed =
            (c.lambda * (t - m_t0)).array().exp().matrix().cwiseProduct(m_w0);
        state = (c.v * decayed).real() + particular(c, t);
    }

    const Dynamics& m_dyn;
    int m_n;
    int m_dim;
    std::vector<char> m_closed;
    double m_omega;
    std::unordered_map<std::string, Configuration> m_cache;
    const Configuration* m_last = nullptr;
    double m_t0 = 0.0;
    Eigen::VectorXcd m_w0; // V^-1 (y(t0) - y_p(t0))
    Eigen::VectorXd m_r0;  // y(t0) - y_p(t0)
    static constexpr double unit_roundoff = std::numeric_limits<double>::epsilon();
};

} // namespace

std::unique_ptr<Stepper> make_exact_propagator(const Dynamics& dyn) {
    return std::make_unique<ExactPropagator>(dyn);
}

} // namespace gapchain::detail
