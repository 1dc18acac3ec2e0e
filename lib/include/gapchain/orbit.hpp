#pragma once
/// \file orbit.hpp
/// Periodic orbits of the forced row by Newton shooting on the k-period stroboscopic map
/// x = P^k(x) (phase 0 of the forcing), with the monodromy matrix dP^k/dx from the exact tangent
/// flow between contact switches (MODEL.md §5), and their Floquet multipliers.

#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"

#include <complex>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace gapchain {

/// How the search went.
enum class OrbitStatus {
    converged,     ///< |P^k(x) - x| <= tolerance (1 + |x|)
    not_converged, ///< max_iterations reached, or the damped step stopped decreasing the residual
    singular,      ///< M - I was singular to working precision (a multiplier at +1: a fold)
    non_finite,    ///< the state became NaN or infinite
    cancelled,     ///< the progress callback stopped the transient run or a Newton shooting
};

/// Name of a status, as written in results ("converged", ...).
std::string_view to_string(OrbitStatus status);

/// Options of the Newton search.
struct OrbitOptions {
    int period = 1;           ///< k, forcing periods of the orbit, 1 .. 1000
    double tolerance = 1e-10; ///< residual |P^k(x) - x| / (1 + |x|) to reach, 1e-14 .. 1e-3
    int max_iterations = 40;  ///< Newton iterations, 1 .. 1000
    /// Integration of P^k: exact (the row is piecewise linear; rows up to max_exact_bodies), rk4,
    /// rkf45 or rk8pd; not automatic or central_difference.
    Scheme scheme = Scheme::exact;
    double integration_tolerance = 1e-12; ///< tolerance of the scheme, 1e-14 .. 1e-3
    /// Largest work of one integration (the transient run, one shooting) in body-steps, as
    /// RunOptions::max_work (the scene's run.max_work), 1 .. 1e15.
    double max_work = 3e10;
    /// find_periodic_orbit(): also estimate a converged orbit's F_m_error (orbit_force_error(),
    /// on the last shooting's monodromy: two plain runs of k periods more).
    bool estimate_force_error = false;
};

/// A periodic orbit and its stability.
struct PeriodicOrbit {
    OrbitStatus status = OrbitStatus::not_converged;
    std::string message;       ///< why the search failed (empty otherwise)
    int period = 1;            ///< k asked for [forcing periods]
    int minimal_period = 1;    ///< smallest divisor d of k with P^d(x) = x (to 1e3 x tolerance)
    std::vector<double> state; ///< x at phase 0: u_1..u_Nm, v_1..v_Nm
    double residual = 0.0;     ///< |P^k(x) - x| / (1 + |x|) at the end
    int iterations = 0;        ///< Newton iterations taken
    std::vector<double> residual_history; ///< residual before each iteration and at the end
    Scheme scheme = Scheme::exact;        ///< the scheme the shootings ran on
    double integration_tolerance = 0.0;   ///< and its tolerance
    /// Floquet multipliers of the k-period map (eigenvalues of the monodromy), largest modulus
    /// first.
    std::vector<std::complex<double>> multipliers;
    double max_multiplier = 0.0; ///< largest modulus
    /// Error of max_multiplier: its change under one more Newton step (the state's error
    /// moves it to first order); NaN unless converged, or beyond 1000 dimensions.
    double max_multiplier_error = std::numeric_limits<double>::quiet_NaN();
    /// Every modulus < 1 on a damped row; false on an undamped one (eps = 0: det M = 1, so the
    /// orbit is at best neutral).
    bool stable = false;
    /// |log|prod mu| - log det| / max(|log det|, 1), det = exp(-k T sum_i c_i) (Liouville,
    /// MODEL.md §5, c_i the damping rates; absolute where |log det| < 1, as at eps = 0): the
    /// multipliers' own check, ~1e-10 or better. NaN (null in JSON)
    /// when det^(1 / 2Nm) < 1e-6 max|mu|: the smallest multipliers are then below what double
    /// precision resolves next to the largest (a smaller period resolves them).
    double liouville_error = 0.0;
    double F_m = 0.0; ///< largest reduced impact force over one orbit (located between steps)
    /// Error of F_m [reduced force, >= 0] (orbit_force_error(): the difference from the same
    /// orbit on an independent scheme), set for a converged orbit by find_periodic_orbit_after()
    /// and where OrbitOptions::estimate_force_error asks; NaN where not estimated.
    double F_m_error = std::numeric_limits<double>::quiet_NaN();
    std::vector<ContactMaximum> per_contact; ///< per contact j = 0..Nm over one orbit
    std::vector<double> max_gap;             ///< per contact: largest g_j over one orbit
    /// The orbit's stroboscopic points: the state at the end of periods 1..k (the last one is
    /// P^k(x), which equals state to the residual).
    std::vector<std::vector<double>> period_ends;
    double wall_time_s = 0.0; ///< [s]
};

/// Throws std::invalid_argument naming the first option outside its range.
void validate(const OrbitOptions& options);

/// Largest row (bodies) a periodic-orbit search takes: Newton holds dense (2 Nm)^2 matrices
/// (the monodromy matrix, its Jacobian and their factorisations), 0.5 GB each at this size.
inline constexpr int max_orbit_bodies = 4096;

/// Throws std::invalid_argument naming model.Nm when dyn is longer than max_orbit_bodies, and
/// naming scheme when it is exact and dyn longer than max_exact_bodies.
void require_orbit_size(const Dynamics& dyn, Scheme scheme);

/// The work of one shooting of options on dyn in body-steps, >= 0: the row and its 2 Nm
/// tangent vectors over options.period periods, Nm x steps per period x period x (1 + 2 Nm).
double shooting_work(const Dynamics& dyn, const OrbitOptions& options);

/// Throws std::invalid_argument naming run.max_work when shooting_work() exceeds
/// options.max_work. The searches call it before any run; an analysis that only confirms its
/// runs by Newton (classify, the attractor search, a doubled branch) compares shooting_work()
/// itself and leaves the run unconfirmed instead.
void require_shooting_affordable(const Dynamics& dyn, const OrbitOptions& options);

/// One shooting evaluation: P^k(x), the monodromy dP^k/dx (2 Nm x 2 Nm, column-major) and the
/// contact maxima over the k periods. A harmonic, linear-law row only.
struct ShootingResult {
    std::vector<double> end_state;            ///< P^k(x)
    std::vector<double> monodromy;            ///< dP^k/dx, column-major
    std::vector<std::vector<double>> at_ends; ///< the state at the end of periods 1..k
    std::vector<ContactMaximum> per_contact;  ///< maxima over the k periods
    std::vector<double> max_gap;              ///< per contact, largest g_j at step ends
    bool finite = true;                       ///< false if the state became non-finite
    bool cancelled = false; ///< keep_going answered false: the other fields are partial
};

/// Integrates k = options.period forcing periods from x at t = 0 with the tangent flow.
/// keep_going is asked as the run advances (with its fraction done); false stops it
/// (cancelled), so that a shooting of a large row (seconds to minutes) can be interrupted.
ShootingResult shoot(const Dynamics& dyn, const OrbitOptions& options, const std::vector<double>& x,
                     const ProgressCallback& keep_going = {});

/// The minimal period of an orbit through x shot over k = s.at_ends.size() periods: the
/// smallest divisor d of k whose period-end state repeats x to 1e3 tolerance (relative, as the
/// Newton residual), or k.
int minimal_period(const std::vector<double>& x, const ShootingResult& s, double tolerance);

/// Newton shooting from start (2 Nm entries, e.g. the end state of a transient run): damped
/// Newton on P^k(x) - x with (M - I) dx = -(P^k(x) - x), the step halved (up to 10 times) until
/// the residual decreases. Needs harmonic forcing and the linear contact law (else
/// std::invalid_argument); numerical outcomes are in status. progress reports the Newton
/// iterations' share of max_iterations; answering false stops the search (status cancelled).
PeriodicOrbit find_periodic_orbit(const Dynamics& dyn, const OrbitOptions& options,
                                  const std::vector<double>& start,
                                  const ProgressCallback& progress = {});

/// find_periodic_orbit() on the k-period map, then, if the orbit's minimal period d is below k,
/// again on the d-period map from the converged state, so that the multipliers, stability and
/// period_ends are those of the minimal period (the k-map's multipliers are their (k/d)-th
/// powers). The first result is returned if the second search fails.
PeriodicOrbit find_minimal_periodic_orbit(const Dynamics& dyn, const OrbitOptions& options,
                                          const std::vector<double>& start);

/// How far (max norm, relative to 1 + |state|_inf) the orbit Newton confirms may lie from the
/// run's state it started from: farther, it is another orbit than the one the run is on. Fig
/// 13's 361 periodic diagram rows lie within 1.3e-3 on rk4 (its truncation error moves the
/// orbit).
inline constexpr double confirmation_distance = 1e-2;

/// The largest multiplier modulus an orbit a run settled on may have: a run does not settle on
/// an unstable orbit, and an undamped row's orbits are neutral (|mu| = 1 to round-off).
inline constexpr double confirmation_max_multiplier = 1.0 + 1e-6;

/// Newton's confirmation of a run's periodic steady state of `period` periods, from state (the
/// run's end, a period boundary): find_minimal_periodic_orbit() on the exact scheme to 1e-9 in
/// at most 12 iterations. Nothing where the exact scheme refuses the row or one shooting exceeds
/// max_work [body-steps]: the caller keeps its run's label unconfirmed rather than failing after
/// its runs (classify, the attractor search, a bifurcation diagram). Otherwise the search's
/// result, converged or not. An orbit that is not the run's is reported not_converged, with
/// the reason in its message: one farther than confirmation_distance from state, or one whose
/// largest multiplier exceeds confirmation_max_multiplier (Fig 13's row at fc = 950: rk4 settles
/// on period 2, and Newton on the 2-period map from there converged on the unstable period-1
/// orbit, |mu| 1.05, from which the period-2 orbit was born).
std::optional<PeriodicOrbit> confirm_periodic_orbit(const Dynamics& dyn, int period,
                                                    const std::vector<double>& state,
                                                    double max_work);

/// The error of the F_m of an orbit of `period` forcing periods through x (phase 0), found on
/// `scheme`, with monodromy its k-period map's dP^k/dx at x (column-major, as ShootingResult):
/// its difference from the F_m of the same orbit on an independent scheme, rk8pd at 1e-10
/// (rkf45 at 1e-10 when scheme is rk8pd), whose fixed point is taken one Newton step from x
/// with that monodromy; never below 1e-12 F_m. Two plain runs of k periods. Nothing where they
/// would exceed max_work [body-steps], stop early or are cancelled (keep_going answering
/// false), or I - M is singular (a fold).
std::optional<double> orbit_force_error(const Dynamics& dyn, Scheme scheme, int period,
                                        const std::vector<double>& x,
                                        const std::vector<double>& monodromy, double F_m,
                                        double max_work, const ProgressCallback& keep_going = {});

/// orbit_force_error() of an orbit of options.period periods through x found on
/// options.scheme, its monodromy from one more shooting (nothing where that exceeds
/// options.max_work or is not finite).
std::optional<double> orbit_force_error(const Dynamics& dyn, const OrbitOptions& options,
                                        const std::vector<double>& x, double F_m);

/// find_periodic_orbit() started from the end of a plain run of transient_periods (0 .. 1e7)
/// forcing periods from initial (empty: rest), on options.scheme: the usual way to reach an
/// attracting orbit's neighbourhood, where Newton converges. A converged orbit's F_m_error is
/// estimated (orbit_force_error(), whatever options.estimate_force_error says). progress reports
/// the transient run's fraction done (the first half of the fractions reported), then Newton's;
/// answering false stops either (status cancelled).
PeriodicOrbit find_periodic_orbit_after(const Dynamics& dyn, const OrbitOptions& options,
                                        const std::vector<double>& initial, long transient_periods,
                                        const ProgressCallback& progress = {});

} // namespace gapchain
