#include "gapchain/model.hpp"

#include "detail/check.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace gapchain {

using detail::require_range;

void validate(const ReducedParameters& p) {
    require_range("model.Nm", p.Nm, 1, 1'000'000);
    require_range("model.fc", p.fc, 0.0, 1e9, detail::Bound::open_low);
    require_range("model.eps", p.eps, 0.0, 100.0);
    require_range("model.e_r", p.e_r, 0.0, 1e6);
    require_range("excitation.f_r", p.f_r, 0.0, 1e4, detail::Bound::open_low);
}

void validate(const PhysicalParameters& p) {
    require_range("model.Nm", p.Nm, 1, 1'000'000);
    require_range("model.M", p.M, 0.0, 1e12, detail::Bound::open_low);
    require_range("model.K", p.K, 0.0, 1e15, detail::Bound::open_low);
    require_range("model.C", p.C, 0.0, 1e15);
    require_range("model.Kc", p.Kc, 0.0, 1e18, detail::Bound::open_low);
    require_range("model.e", p.e, 0.0, 1e3);
    require_range("excitation.a0", p.a0, 0.0, 1e6, detail::Bound::open_low);
    require_range("excitation.f", p.f, 0.0, 1e6, detail::Bound::open_low);
}

double natural_frequency(const PhysicalParameters& p) {
    return std::sqrt(p.K / p.M) / (2.0 * std::numbers::pi);
}

namespace {

/// sqrt(K M), also where the product underflows (K = M = 1e-200 gave eps = inf for a row whose
/// eps is 5); the product's root where it is a normal double, so that ordinary rows keep their
/// last bits.
double root_of_product(double K, double M) {
    const double product = K * M;
    if (std::isnormal(product)) return std::sqrt(product);
    return std::sqrt(K) * std::sqrt(M);
}

} // namespace

ReducedParameters to_reduced(const PhysicalParameters& p) {
    validate(p);
    const double f0 = natural_frequency(p);
    const double two_pi_f0 = 2.0 * std::numbers::pi * f0;
    ReducedParameters r;
    r.Nm = p.Nm;
    r.fc = p.Kc / p.K;
    r.eps = p.C / (2.0 * root_of_product(p.K, p.M));
    r.e_r = two_pi_f0 * two_pi_f0 * p.e / p.a0;
    r.f_r = p.f / f0;
    // The reduced numbers are derived: a value out of range names the keys the user wrote.
    auto derived = [](const char* keys, const char* formula, double value, double lo, double hi) {
        if (!(value >= lo && value <= hi))
            throw std::invalid_argument(
                std::string(keys) + ": give " + formula + " in [" + detail::format_number(lo) +
                ", " + detail::format_number(hi) + "], got " + detail::format_number(value));
    };
    derived("model.Kc, model.K", "fc = Kc / K", r.fc, 1e-9, 1e9);
    derived("model.C, model.K, model.M", "eps = C / (2 sqrt(K M))", r.eps, 0.0, 100.0);
    derived("model.e, excitation.a0, model.K, model.M", "e_r = 4 pi^2 f0^2 e / a0", r.e_r, 0.0,
            1e6);
    derived("excitation.f, model.K, model.M", "f_r = f / f0 (f0 = sqrt(K / M) / (2 pi))", r.f_r,
            1e-5, 1e4);
    validate(r);
    return r;
}

PhysicalParameters to_physical(const ReducedParameters& p, double M, double K, double a0) {
    validate(p);
    require_range("M", M, 0.0, 1e12, detail::Bound::open_low);
    require_range("K", K, 0.0, 1e15, detail::Bound::open_low);
    require_range("a0", a0, 0.0, 1e6, detail::Bound::open_low);
    PhysicalParameters q;
    q.Nm = p.Nm;
    q.M = M;
    q.K = K;
    q.a0 = a0;
    q.Kc = p.fc * K;
    q.C = 2.0 * p.eps * root_of_product(K, M);
    const double f0 = natural_frequency(q);
    const double two_pi_f0 = 2.0 * std::numbers::pi * f0;
    q.e = p.e_r * a0 / (two_pi_f0 * two_pi_f0);
    q.f = p.f_r * f0;
    return q;
}

double force_in_newtons(double reduced_force, const PhysicalParameters& p) {
    return reduced_force * p.M * p.a0 * std::sqrt(p.Kc / p.K);
}

Chain Chain::homogeneous(const ReducedParameters& p) {
    validate(p);
    constexpr double pi = std::numbers::pi;
    const auto n = static_cast<std::size_t>(p.Nm);
    Chain c;
    c.mass.assign(n, 1.0);
    c.spring.assign(n, four_pi_squared);
    c.damping.assign(n, 4.0 * pi * p.eps);
    c.clearance.assign(n + 1, p.e_r);
    // Two local deformations of stiffness Kc in series between bodies (MODEL.md §1).
    c.contact.assign(n + 1, p.fc / 2.0);
    c.contact.front() = p.fc;
    c.contact.back() = p.fc;
    c.force_scale = std::sqrt(p.fc);
    return c;
}

void validate(const Chain& c) {
    const auto n = c.mass.size();
    if (n < 1) throw std::invalid_argument("model.mass: need at least one body, got 0");
    detail::require_length("model.spring", c.spring.size(), n);
    detail::require_length("model.damping", c.damping.size(), n);
    detail::require_length("model.clearance", c.clearance.size(), n + 1);
    detail::require_length("model.contact", c.contact.size(), n + 1);
    for (double m : c.mass)
        require_range("model.mass", m, 0.0, 1e12, detail::Bound::open_low);
    for (double s : c.spring)
        require_range("model.spring", s, 0.0, 1e15, detail::Bound::open_low);
    for (double d : c.damping)
        require_range("model.damping", d, 0.0, 1e15);
    for (double e : c.clearance)
        require_range("model.clearance", e, 0.0, 1e6);
    for (double k : c.contact)
        require_range("model.contact", k, 0.0, 1e12, detail::Bound::open_low);
    require_range("model.force_scale", c.force_scale, 0.0, 1e12, detail::Bound::open_low);
    require_range("model.contact_damping", c.contact_damping, 0.0, 1e6);
}

const char* to_string(ContactLaw law) {
    switch (law) {
    case ContactLaw::linear: return "linear";
    case ContactLaw::hertz: return "hertz";
    case ContactLaw::hunt_crossley: return "hunt_crossley";
    }
    return "?";
}

double max_angular_frequency(const Chain& c) {
    const int n = c.bodies();
    // Gershgorin on M^-1 K with all contacts closed: diagonal plus the off-diagonal row sum.
    double bound = 0.0;
    for (int i = 0; i < n; ++i) {
        const double kl = c.contact[i];
        const double kr = c.contact[i + 1];
        const double diag = c.spring[i] + four_pi_squared * (kl + kr) / c.mass[i];
        const double off =
            four_pi_squared * ((i > 0 ? kl : 0.0) + (i + 1 < n ? kr : 0.0)) / c.mass[i];
        bound = std::max(bound, diag + off);
    }
    return std::sqrt(bound);
}

SweptParameter parse_swept_parameter(std::string_view name) {
    if (name == "f_r") return SweptParameter::f_r;
    if (name == "e_r") return SweptParameter::e_r;
    if (name == "fc") return SweptParameter::fc;
    if (name == "eps") return SweptParameter::eps;
    throw std::invalid_argument("parameter: must be one of f_r, e_r, fc, eps, got \"" +
                                std::string(name) + "\"");
}

std::string_view to_string(SweptParameter p) {
    switch (p) {
    case SweptParameter::f_r: return "f_r";
    case SweptParameter::e_r: return "e_r";
    case SweptParameter::fc: return "fc";
    case SweptParameter::eps: return "eps";
    }
    return "?";
}

ReducedParameters with_value(ReducedParameters p, SweptParameter which, double value) {
    switch (which) {
    case SweptParameter::f_r: p.f_r = value; break;
    case SweptParameter::e_r: p.e_r = value; break;
    case SweptParameter::fc: p.fc = value; break;
    case SweptParameter::eps: p.eps = value; break;
    }
    return p;
}

std::optional<std::string> swept_value_error(const ReducedParameters& base, SweptParameter which,
                                             double value) {
    try {
        validate(with_value(base, which, value));
        return std::nullopt;
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
}

} // namespace gapchain
