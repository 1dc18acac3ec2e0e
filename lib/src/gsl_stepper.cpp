#include "detail/steppers.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace gapchain::detail {

namespace {

class GslStepper final : public Stepper {
public:
    GslStepper(const Dynamics& dyn, bool high_order, double tolerance)
        : m_dyn(dyn),
          m_dim(static_cast<std::size_t>(dyn.dimension())), m_system{&GslStepper::rhs, nullptr,
                                                                     m_dim, this},
          m_step(gsl_odeiv2_step_alloc(high_order ? gsl_odeiv2_step_rk8pd : gsl_odeiv2_step_rkf45,
                                       m_dim)),
          // Absolute and relative tolerance alike: reduced states are of order 1.
          m_control(gsl_odeiv2_control_y_new(0.1 * tolerance, 0.1 * tolerance)),
          m_evolve(gsl_odeiv2_evolve_alloc(m_dim)) {}
    ~GslStepper() override {
        gsl_odeiv2_evolve_free(m_evolve);
        gsl_odeiv2_control_free(m_control);
        gsl_odeiv2_step_free(m_step);
    }
    GslStepper(const GslStepper&) = delete;
    GslStepper& operator=(const GslStepper&) = delete;

    void step(double t, double h, std::vector<double>& y) override {
        const double t_end = t + h;
        if (m_h_internal <= 0.0 || m_h_internal > h) m_h_internal = h;
        gsl_odeiv2_evolve_reset(m_evolve);
        while (t < t_end) {
            const int status = gsl_odeiv2_evolve_apply(m_evolve, m_control, m_step, &m_system, &t,
                                                       t_end, &m_h_internal, y.data());
            if (status != GSL_SUCCESS) {
                // Leave a non-finite state: the time loop reports it with time and body.
                std::fill(y.begin(), y.end(), std::numeric_limits<double>::quiet_NaN());
                return;
            }
        }
    }

private:
    static int rhs(double t, const double y[], double dydt[], void* self) {
        auto* me = static_cast<GslStepper*>(self);
        me->m_dyn.rhs(t, y, dydt);
        ++me->m_evaluations;
        return GSL_SUCCESS;
    }

    const Dynamics& m_dyn;
    std::size_t m_dim;
    gsl_odeiv2_system m_system;
    gsl_odeiv2_step* m_step;
    gsl_odeiv2_control* m_control;
    gsl_odeiv2_evolve* m_evolve;
    double m_h_internal = 0.0;
};

} // namespace

std::unique_ptr<Stepper> make_gsl_stepper(const Dynamics& dyn, bool high_order, double tolerance) {
    return std::make_unique<GslStepper>(dyn, high_order, tolerance);
}

} // namespace gapchain::detail
