#pragma once
/// \file model.hpp
/// The chain of bodies with clearances (MODEL.md §1-3): reduced and physical parameters, the
/// conversions between them, and the per-body / per-gap Chain that every other layer reads.

#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

/// 4 pi^2: the reduced spring of a body (its angular frequency squared in reduced time) and the
/// factor of every reduced force (MODEL.md §2).
inline constexpr double four_pi_squared = 4.0 * std::numbers::pi * std::numbers::pi;

/// Dimensionless parameters of a homogeneous row (paper eqs 6-13, MODEL.md §3).
struct ReducedParameters {
    int Nm = 5;        ///< number of bodies, 1 <= Nm <= 1'000'000
    double fc = 100.0; ///< contact-to-body stiffness ratio Kc/K, 0 < fc <= 1e9
    double eps = 0.5;  ///< damping ratio C/(2 sqrt(KM)), 0 <= eps <= 100
    double e_r = 0.5;  ///< reduced clearance 4 pi^2 f0^2 e / a0, 0 <= e_r <= 1e6
    double f_r = 1.0;  ///< reduced forcing frequency f/f0, 0 < f_r <= 1e4
};

/// Dimensional parameters of a homogeneous row (SI units).
struct PhysicalParameters {
    int Nm = 5;      ///< number of bodies, 1 <= Nm <= 1'000'000
    double M = 1.0;  ///< body mass [kg], > 0
    double K = 1.0;  ///< body-to-ground stiffness [N/m], > 0
    double C = 0.0;  ///< body-to-ground damping [kg/s], >= 0
    double Kc = 1.0; ///< wall contact stiffness [N/m], > 0 (body-body contacts get Kc/2)
    double e = 0.0;  ///< clearance [m], >= 0
    double a0 = 1.0; ///< ground acceleration amplitude [m/s^2], > 0
    double f = 1.0;  ///< forcing frequency [Hz], > 0
};

/// Throws std::invalid_argument naming the first parameter outside its documented range.
void validate(const ReducedParameters& p);
/// Throws std::invalid_argument naming the first parameter outside its documented range.
void validate(const PhysicalParameters& p);

/// Natural frequency of one body on its spring, f0 = sqrt(K/M) / (2 pi) [Hz].
double natural_frequency(const PhysicalParameters& p);

/// Physical -> reduced (MODEL.md §3). Validates its input.
ReducedParameters to_reduced(const PhysicalParameters& p);

/// Reduced -> physical, given the three dimensional scales M [kg], K [N/m] and a0 [m/s^2]
/// (all > 0) that the reduced form divides out. Validates its input.
PhysicalParameters to_physical(const ReducedParameters& p, double M, double K, double a0);

/// Reduced impact force -> newtons: F_phys = F_r * M * a0 * sqrt(fc) (paper eqs 14-15).
double force_in_newtons(double reduced_force, const PhysicalParameters& p);

/// How a closed contact pushes back, as a function of its penetration p >= 0.
enum class ContactLaw {
    linear, ///< the paper's: force k p
    hertz,  ///< Hertz: force k p^(3/2) (k in reduced units, force per unit penetration^(3/2))
    /// Hunt and Crossley (1975), "Coefficient of restitution interpreted as damping in
    /// vibroimpact", J. Appl. Mech. 42: force k p^(3/2) (1 + alpha p'), clipped at 0 (no
    /// pull), with alpha = Chain::contact_damping. Hunt and Crossley relate it to the
    /// coefficient of restitution r at impact speed v_i by alpha = 3 (1 - r) / (2 v_i); the
    /// force vanishes with p, so the vector field has no jump at a switch.
    hunt_crossley,
};

/// "linear", "hertz" or "hunt_crossley".
const char* to_string(ContactLaw law);

/// The row in the reduced equations of MODEL.md §2, stored per body and per gap so that
/// non-uniform rows need no other code. Body i (0-based) obeys
///   u_i'' = -damping_i u_i' - spring_i u_i + ground(t)
///           + (4 pi^2 / mass_i) (k_{i} p_{i} - k_{i+1} p_{i+1})
/// with gaps j = 0..Nm (j = 0 the left wall, j = Nm the right wall), penetration
/// p_j = max(g_j, 0) and g_0 = -u_0 - e_0, g_j = u_{j-1} - u_j - e_j, g_Nm = u_{Nm-1} - e_Nm.
struct Chain {
    std::vector<double> mass;      ///< per body, relative to the nominal mass M, > 0
    std::vector<double> spring;    ///< per body, reduced spring rate (4 pi^2 for the nominal body)
    std::vector<double> damping;   ///< per body, reduced damping rate (4 pi eps nominal), >= 0
    std::vector<double> clearance; ///< per gap (Nm + 1 entries), reduced clearance, >= 0
    std::vector<double> contact;   ///< per gap, contact stiffness in units of K (fc, fc/2), > 0
    double force_scale = 1.0;      ///< reduced force F_j = contact_j p_j / force_scale (sqrt(fc))
    ContactLaw law = ContactLaw::linear; ///< linear (p), Hertz (p^(3/2)) or Hunt-Crossley
    /// Hunt-Crossley alpha [reduced time per reduced length], [0, 1e6]; used by that law only.
    double contact_damping = 0.0;

    /// Number of bodies.
    [[nodiscard]] int bodies() const { return static_cast<int>(mass.size()); }
    /// Number of contacts (gaps), bodies() + 1.
    [[nodiscard]] int gaps() const { return static_cast<int>(clearance.size()); }

    /// The paper's homogeneous row: walls fc, body-body fc/2 (MODEL.md §1). Validates p.
    static Chain homogeneous(const ReducedParameters& p);
};

/// One of the reduced numbers a diagram or a continuation varies.
enum class SweptParameter { f_r, e_r, fc, eps };
/// Parses "f_r", "e_r", "fc" or "eps"; throws std::invalid_argument (naming "parameter")
/// otherwise.
SweptParameter parse_swept_parameter(std::string_view name);
/// The name parse_swept_parameter() reads.
std::string_view to_string(SweptParameter p);
/// p with the swept parameter set to value (not validated).
ReducedParameters with_value(ReducedParameters p, SweptParameter which, double value);
/// The model's message if it refuses `value` for the parameter `which` of base (validate()
/// of with_value()), else nothing: the admissible range of a sweep or a continuation.
std::optional<std::string> swept_value_error(const ReducedParameters& base, SweptParameter which,
                                             double value);

/// Throws std::invalid_argument if the arrays have inconsistent lengths or invalid values.
void validate(const Chain& chain);

/// An upper bound on the fastest angular frequency of the row with every contact closed
/// [rad per unit reduced time], from Gershgorin's theorem (MODEL.md §4).
double max_angular_frequency(const Chain& chain);

} // namespace gapchain
