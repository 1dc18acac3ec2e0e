#include "gapchain/continuation.hpp"

#include "detail/check.hpp"
#include "detail/traced_orbits.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

namespace gapchain {

std::string_view to_string(SpecialPointType type) {
    switch (type) {
    case SpecialPointType::fold: return "fold";
    case SpecialPointType::period_doubling: return "period_doubling";
    case SpecialPointType::neimark_sacker: return "neimark_sacker";
    case SpecialPointType::grazing: return "grazing";
    case SpecialPointType::branch_point: return "branch_point";
    }
    return "?";
}

void validate(const ContinuationOptions& o) {
    detail::require_range("period", o.period, 1, 1000);
    detail::require_range("step", o.step, 1e-6, 1.0);
    detail::require_range("max_step", o.max_step, 1e-6, 1.0);
    if (o.max_step < o.step)
        throw std::invalid_argument("max_step: must be at least the first arclength step, " +
                                    detail::format_number(o.step) + ", got " +
                                    detail::format_number(o.max_step));
    detail::require_range("max_points", o.max_points, 1, 1'000'000);
    detail::require_range("max_branches", o.max_branches, 1, 64);
    detail::require_range("locate_tolerance", o.locate_tolerance, 1e-12, 1e-2);
    detail::require_count("transient_periods", o.transient_periods, 0, 10'000'000);
    if (!(o.from != o.to))
        throw std::invalid_argument(
            "to: must differ from the start value (from = " + detail::format_number(o.from) + ")");
    validate(o.orbit);
}

namespace {

using Matrix = Eigen::MatrixXd;
using Vector = Eigen::VectorXd;

/// A converged point of a branch: z = (x, p), its unit tangent, and what the orbit shows.
struct OrbitPoint {
    Vector z;
    Vector tangent;
    ShootingResult shot;
    std::vector<std::complex<double>> multipliers;
    double F_m = 0.0;
};

/// The continuation of one branch: the extended system F(x, p) = P^k(x; p) - x.
class BranchTracer {
public:
    /// keep_going is asked inside every shooting (one of a large row takes minutes).
    BranchTracer(const ReducedParameters& base, const ContinuationOptions& o, int period,
                 ProgressCallback keep_going)
        : m_base(base), m_o(o), m_orbit(o.orbit), m_keep_going(std::move(keep_going)) {
        m_orbit.period = period;
    }

    [[nodiscard]] int dimension() const { return 2 * m_base.Nm; }
    /// Whether keep_going stopped a shooting: every correction fails from then on.
    [[nodiscard]] bool cancelled() const { return m_cancelled; }
    [[nodiscard]] long shootings() const { return m_shootings; }

    /// Whether the orbit at a attracts: every multiplier inside the unit circle, on a damped
    /// row (at eps = 0 det M = 1 and a largest multiplier a hair below 1 is round-off, as in
    /// find_periodic_orbit()).
    [[nodiscard]] bool stable(const OrbitPoint& a) const {
        return std::abs(a.multipliers.front()) < 1.0 && damped(a);
    }
    /// Whether the row at a is damped (eps > 0): undamped, every multiplier lies on the unit
    /// circle (det M = 1) and a turn tells nothing by them.
    [[nodiscard]] bool damped(const OrbitPoint& a) const {
        return with_value(m_base, m_o.parameter, a.z[dimension()]).eps > 0.0;
    }
    /// The error of the F_m of the orbit at a (orbit_force_error()); NaN where not estimated.
    double force_error(const OrbitPoint& a) {
        const Eigen::Index n = dimension();
        const Dynamics dyn = Dynamics::paper_row(with_value(m_base, m_o.parameter, a.z[n]));
        const auto error = orbit_force_error(
            dyn, m_orbit.scheme, m_orbit.period, std::vector<double>(a.z.data(), a.z.data() + n),
            a.shot.monodromy, a.F_m, m_orbit.max_work, m_keep_going);
        return error ? *error : std::numeric_limits<double>::quiet_NaN();
    }
    /// Whether p is a value the model accepts for the continued parameter.
    [[nodiscard]] bool admissible(double p) const {
        return !swept_value_error(m_base, m_o.parameter, p);
    }

    /// Newton at the fixed parameter value guess[n] from guess; nothing if it fails.
    std::optional<OrbitPoint> correct_at_value(const Vector& guess) {
        Vector along_p = Vector::Zero(guess.size());
        along_p[guess.size() - 1] = 1.0;
        return correct(guess, along_p);
    }

    ShootingResult shoot_at(const Vector& x, double p) {
        ++m_shootings;
        const ReducedParameters q = with_value(m_base, m_o.parameter, p);
        const Dynamics dyn = Dynamics::paper_row(q);
        // Once cancelled, keep_going stops each shooting at its first check; its partial
        // result keeps its sizes and is marked failed.
        ShootingResult s =
            shoot(dyn, m_orbit, std::vector<double>(x.data(), x.data() + x.size()), m_keep_going);
        if (m_cancelled || s.cancelled) {
            m_cancelled = true;
            s.finite = false;
        }
        return s;
    }

    /// The Jacobian [M - I, dF/dp] (n x (n + 1)); dF/dp by central differences.
    Matrix jacobian(const Vector& z, const ShootingResult& s) {
        const Eigen::Index n = dimension();
        const double p = z[n];
        const double h = 1e-6 * std::max(1.0, std::abs(p));
        const Vector x = z.head(n);
        // One-sided at an end of the parameter's range (eps = 0, e_r = 0): the model takes no
        // value beyond it.
        const double p_up = admissible(p + h) ? p + h : p;
        const double p_down = admissible(p - h) ? p - h : p;
        const ShootingResult up = p_up == p ? s : shoot_at(x, p_up);
        const ShootingResult down = p_down == p ? s : shoot_at(x, p_down);
        Matrix j(n, n + 1);
        j.leftCols(n) = Eigen::Map<const Matrix>(s.monodromy.data(), n, n) - Matrix::Identity(n, n);
        for (Eigen::Index i = 0; i < n; ++i)
            j(i, n) = (up.end_state[i] - down.end_state[i]) / (p_up - p_down);
        return j;
    }

    /// Newton on [F(z); t . (z - predicted)] = 0 from predicted; nothing if it fails.
    std::optional<OrbitPoint> correct(const Vector& predicted, const Vector& t) {
        const Eigen::Index n = dimension();
        Vector z = predicted;
        for (int it = 0; it < 12; ++it) {
            // A diverging corrector can throw the parameter out of its range (f_r < 0): that
            // is a failed correction, which the walk answers with a shorter step.
            if (!admissible(z[n])) return std::nullopt;
            ShootingResult s = shoot_at(z.head(n), z[n]);
            if (!s.finite) return std::nullopt;
            const Vector r = Eigen::Map<const Vector>(s.end_state.data(), n) - z.head(n);
            const Matrix j = jacobian(z, s);
            if (r.norm() <= m_orbit.tolerance * (1.0 + z.head(n).norm()))
                return finish(z, t, std::move(s), j);
            Matrix a(n + 1, n + 1);
            a.topRows(n) = j;
            a.row(n) = t.transpose();
            Vector rhs(n + 1);
            rhs.head(n) = -r;
            rhs[n] = -t.dot(z - predicted);
            z += a.fullPivLu().solve(rhs);
            if (!z.allFinite()) return std::nullopt;
        }
        return std::nullopt;
    }

private:
    /// The converged point: its tangent (oriented along t), multipliers and F_m.
    OrbitPoint finish(const Vector& z, const Vector& t, ShootingResult s, const Matrix& j) {
        const Eigen::Index n = dimension();
        OrbitPoint point;
        point.z = z;
        Matrix a(n + 1, n + 1);
        a.topRows(n) = j;
        a.row(n) = t.transpose();
        Vector e = Vector::Zero(n + 1);
        e[n] = 1.0;
        point.tangent = a.fullPivLu().solve(e).normalized();
        const Matrix m = Eigen::Map<const Matrix>(s.monodromy.data(), n, n);
        const Eigen::EigenSolver<Matrix> solver(m, false);
        for (Eigen::Index i = 0; i < n; ++i)
            point.multipliers.push_back(solver.eigenvalues()[i]);
        std::sort(point.multipliers.begin(), point.multipliers.end(),
                  [](auto x, auto y) { return std::abs(x) > std::abs(y); });
        for (const auto& c : s.per_contact)
            point.F_m = std::max(point.F_m, c.force);
        point.shot = std::move(s);
        return point;
    }

    ReducedParameters m_base;
    const ContinuationOptions& m_o;
    OrbitOptions m_orbit;
    ProgressCallback m_keep_going;
    bool m_cancelled = false;
    long m_shootings = 0;
};

// Test functions whose sign change between two points reveals a special point.
double fold_test(const OrbitPoint& a) {
    return a.tangent[a.tangent.size() - 1];
}
double doubling_test(const OrbitPoint& a) {
    double product = 1.0; // det(M + I) = prod (mu + 1): a complex pair gives |mu + 1|^2 > 0
    for (const auto& mu : a.multipliers)
        product *= std::abs(mu.imag()) > 1e-12 ? std::abs(mu + 1.0) : mu.real() + 1.0;
    return product;
}
/// Real multipliers below -1 (real as torus_test() counts them: a pair with larger imaginary
/// parts is a Neimark-Sacker's). The mirror symmetry of MODEL.md §5 makes equal pairs of them,
/// and a pair through -1 together leaves det(M + I), and so doubling_test(), with its sign.
int multipliers_below_minus_one(const OrbitPoint& a) {
    int count = 0;
    for (const auto& mu : a.multipliers)
        count += mu.real() < -1.0 && std::abs(mu.imag()) <= 1e-9 * std::abs(mu) ? 1 : 0;
    return count;
}
/// Multipliers outside the unit circle (within 1e-6 of it counts as on it). A turn that keeps
/// their number is smooth where it lies on the branch born at a pitchfork, which turns into
/// its own mirror image, its multiplier touching +1 from below; one that changes it there is
/// the walk turning off that branch onto the symmetric orbit (exchange of stability).
int outside_unit_circle(const OrbitPoint& a) {
    int count = 0;
    for (const auto& mu : a.multipliers)
        count += std::abs(mu) > 1.0 + 1e-6 ? 1 : 0;
    return count;
}
double branch_test(const OrbitPoint& a) {
    double product = 1.0; // det(M - I) = prod (mu - 1): zero where a multiplier is +1
    for (const auto& mu : a.multipliers)
        product *= std::abs(mu.imag()) > 1e-12 ? std::abs(mu - 1.0) : mu.real() - 1.0;
    return product;
}
/// Largest |mu| - 1 over complex pairs; nothing if there is no pair.
std::optional<double> torus_test(const OrbitPoint& a) {
    std::optional<double> largest;
    for (const auto& mu : a.multipliers)
        if (std::abs(mu.imag()) > 1e-9 * std::abs(mu))
            largest = std::max(largest.value_or(-1.0), std::abs(mu) - 1.0);
    return largest;
}

} // namespace

namespace {

using detail::TracedOrbits;

/// One branch traced from a first point along its tangent, special points located on the way.
class BranchWalk {
public:
    BranchWalk(BranchTracer& tracer, const ContinuationOptions& o, int period, int branch,
               ContinuationResult& result, TracedOrbits& traced)
        : m_tracer(tracer), m_o(o), m_period(period), m_branch(branch), m_result(result),
          m_traced(traced) {
        m_traced.begin_branch(branch, period);
    }

    /// Doublings found (point, on which side the doubled branch lies) for branch switching.
    std::vector<std::pair<OrbitPoint, double>> doublings;
    /// The branch passed the end value `to` (it did not stop at a corner, turn back out of
    /// the range at `from`, or run out of points first).
    bool reached_end = false;
    /// The parameter value reached farthest in the direction from -> to.
    double farthest = 0.0;

    /// Walks from first until it lands on `to`, leaves [from, to], max_points or a failure.
    void walk(OrbitPoint first, const ProgressCallback& progress) {
        const Eigen::Index n = m_tracer.dimension();
        const double lo = std::min(m_o.from, m_o.to), hi = std::max(m_o.from, m_o.to);
        OrbitPoint a = std::move(first);
        farthest = a.z[n];
        record(a);
        double ds = m_o.step;
        // On from orbits already traced the branch would trace them again (came_onto()).
        m_traced.add(a.z, a.shot.at_ends, 0.0);
        double arclength = 0.0;
        int on_old = 0; // points in a row on traced orbits
        for (int count = 1; count < m_o.max_points; ++count) {
            bool beyond_range = false;
            std::optional<OrbitPoint> b = next_point(a, ds, beyond_range);
            if (m_tracer.cancelled()) {
                m_result.cancelled = true;
                return end("cancelled");
            }
            if (!b) {
                const std::string where =
                    std::string(to_string(m_o.parameter)) + " = " + std::to_string(a.z[n]);
                if (beyond_range) return end("reached the end of the model's range of " + where);
                if (m_cut_corner)
                    return end("reached a grazing corner at " + where +
                               ": the orbit goes on only on another sheet, with other impact "
                               "counts, not followed");
                return end("the corrector failed at the smallest step (1e-7) at " + where);
            }
            m_cut_corner = false;
            const bool landed = land_on_end(a, *b, ds);
            detect(a, *b, ds);
            arclength += (b->z - a.z).norm();
            a = std::move(*b);
            const int minimal = record(a);
            ds = std::min(1.5 * ds, m_o.max_step);
            const double p = a.z[n];
            farthest = m_o.to > m_o.from ? std::max(farthest, p) : std::min(farthest, p);
            if (progress && !progress(std::min(1.0, std::abs(p - m_o.from) / (hi - lo)))) {
                m_result.cancelled = true;
                return end("cancelled");
            }
            if (landed) {
                reached_end = true;
                return end("reached the end value " + std::string(to_string(m_o.parameter)) +
                           " = " + detail::format_number(m_o.to));
            }
            if (p < lo || p > hi) {
                reached_end = (p - m_o.from) * (m_o.to - m_o.from) > 0;
                return end(reached_end ? "left the parameter range at its end"
                                       : "turned back out of the parameter range at its start");
            }
            const int under =
                m_traced.branch_under(a.z, minimal, arclength, std::max(ds, m_o.step));
            on_old = under >= 0 ? on_old + 1 : 0;
            if (on_old == 3) return end(came_onto(under, p));
            m_traced.add(a.z, a.shot.at_ends, arclength);
        }
        end("max_points reached");
    }

private:
    void end(const std::string& why) { m_result.branch_end.push_back(why); }

    /// The next point from a along its tangent, ds halved until the corrector converges
    /// (down to 1e-7); nothing if it never does. beyond_range: the last prediction lay outside
    /// the model's range of the parameter.
    std::optional<OrbitPoint> next_point(const OrbitPoint& a, double& ds, bool& beyond_range) {
        const Eigen::Index n = m_tracer.dimension();
        std::optional<OrbitPoint> b;
        while (!b && ds >= 1e-7 && !m_tracer.cancelled()) {
            const Vector guess = a.z + ds * a.tangent;
            beyond_range = !m_tracer.admissible(guess[n]);
            b = m_tracer.correct(guess, a.tangent);
            // A corrected point far from its prediction sits on another sheet: joining the two
            // would draw a branch that does not exist.
            if (b && !near(*b, guess, ds)) b.reset();
            if (b && cuts_corner(a, *b, ds)) {
                b.reset();
                m_cut_corner = true;
            }
            // Not below the corrector's own floor (1e-7): the branch would end there as if the
            // corrector had failed.
            if (b && crowded(a, *b) && ds / 2 >= std::max(16.0 * m_o.locate_tolerance, 2e-7))
                b.reset();
            if (!b) ds /= 2;
        }
        return b;
    }

    /// Whether the step a -> b landed on another sheet across a grazing corner: b's contacts
    /// close another number of times than a's, and a's own orbit goes on past b's value,
    /// another orbit there (Newton at b's value from a's orbit carried along its tangent
    /// converges, near a, with a's impact counts, and not onto b). Near a corner where the
    /// branch turns back, the arclength corrector converges onto the far sheet: Fig 13's
    /// period-1 family stepped from 3.01871 (unstable, every contact striking) to 3.00128 on
    /// the sheet whose middle contacts stay open, 0.023 away in the state, skipping both
    /// sheets between there and their corner at 2.99783, and then walked the far sheet back
    /// into the corner instead of away from it (found by an independent review, 2026-11-27).
    /// Refused, the step shortens until the walk reaches the corner, where a's sheet ends:
    /// there Newton finds b itself, and the walk turns onto the far sheet and follows it.
    bool cuts_corner(const OrbitPoint& a, const OrbitPoint& b, double ds) {
        const Eigen::Index n = m_tracer.dimension();
        if (same_impacts(a, b)) return false;
        // a's orbit carried to b's value along a's tangent.
        const double along = (b.z[n] - a.z[n]) / a.tangent[n];
        Vector guess = a.z + (std::isfinite(along) ? along : 0.0) * a.tangent;
        guess[n] = b.z[n];
        const std::optional<OrbitPoint> own = m_tracer.correct_at_value(guess);
        if (!own || !near(*own, a.z, ds) || !same_impacts(*own, a)) return false;
        return (own->z.head(n) - b.z.head(n)).norm() >
               1e3 * m_o.orbit.tolerance * (1.0 + b.z.head(n).norm());
    }

    /// Whether two kinds of special point fall between a and b: a turn (fold or branch
    /// point), a multiplier through -1, a pair through the unit circle. The step is then
    /// halved (down to 16 locate_tolerance, and 2e-7), so that the orbits between them are on the
    /// branch: on Nm 1, fc 100, eps 0.2, e_r 0.05 (an independent review, helper-84) the stable
    /// stretch between the doubling at f_r = 2.62490 and the fold at 2.62439 lay inside one step,
    /// and branch.csv held no orbit of it.
    static bool crowded(const OrbitPoint& a, const OrbitPoint& b) {
        const auto changes = [&](auto test) { return (test(a) > 0) != (test(b) > 0); };
        const auto ta = torus_test(a), tb = torus_test(b);
        const bool pair_through_circle = ta && tb && (*ta > 0) != (*tb > 0);
        // A pair below -1 that changes beside a pair through the circle counts as two kinds,
        // though detect() lists one step holding both as the Neimark-Sacker point alone: halved,
        // the step at Fig 13's 3.13084 parted them (a doubling 8e-7 beyond the Neimark-Sacker
        // point, whose period-2 family the walk then follows). Where they coincide (a grazing
        // corner) the halving costs about 12 corrections.
        const bool through_minus_one = changes(doubling_test) || multipliers_below_minus_one(a) !=
                                                                     multipliers_below_minus_one(b);
        const int kinds = (changes(fold_test) || changes(branch_test) ? 1 : 0) +
                          (through_minus_one ? 1 : 0) + (pair_through_circle ? 1 : 0);
        return kinds >= 2;
    }

    /// Whether every contact closes as many times per orbit at a as at b.
    static bool same_impacts(const OrbitPoint& a, const OrbitPoint& b) {
        for (std::size_t j = 0; j < a.shot.per_contact.size(); ++j)
            if (a.shot.per_contact[j].impacts != b.shot.per_contact[j].impacts) return false;
        return true;
    }

    /// Moves b, past the end value `to`, onto `to` itself (Newton at that value from the
    /// chord a -> b) and shortens ds to match; false, b and ds untouched, where b is not past
    /// `to` or Newton fails. Otherwise the last point would lie up to a step past `to`, at a
    /// value not asked for.
    bool land_on_end(const OrbitPoint& a, OrbitPoint& b, double& ds) {
        const Eigen::Index n = m_tracer.dimension();
        if (!((b.z[n] - m_o.to) * (m_o.to - m_o.from) > 0)) return false;
        const double s = (m_o.to - a.z[n]) / (b.z[n] - a.z[n]);
        Vector guess = a.z + s * (b.z - a.z);
        guess[n] = m_o.to;
        std::optional<OrbitPoint> at_end = m_tracer.correct_at_value(guess);
        if (!at_end || !near(*at_end, guess, ds)) return false;
        // Corrected at a fixed value, its tangent comes out oriented along +p: on a walk down
        // it must keep the walk's orientation, or the fold test sees a sign change that is not
        // there (a fold reported at every downward end value; the probe of 2026-11-26).
        if (at_end->tangent.dot(b.tangent) < 0.0) at_end->tangent = -at_end->tangent;
        b = std::move(*at_end);
        ds *= s;
        return true;
    }

    /// Why a branch ends where it comes onto traced orbits, three points in a row (a branch that
    /// crosses another at a branch point touches it once, at a shallow angle for two points). Back
    /// onto itself, long after: it has closed (the period-2 loop between Fig 13's folds at 2.2573
    /// and 2.4651) or turned back at a corner (its period-1 family at 2.99783). Onto an earlier
    /// branch: the loop again, reached from another loss of stability, or a period-4 branch's
    /// orbits of minimal period 2.
    [[nodiscard]] std::string came_onto(int branch, double p) const {
        const std::string where = std::string(to_string(m_o.parameter)) + " = " + std::to_string(p);
        if (branch == m_branch)
            return "came back onto itself at " + where +
                   " (a closed loop, or a turn back at a corner): traced once";
        return "came onto branch " + std::to_string(branch) + " at " + where +
               ": its orbits are traced there";
    }

    /// Writes the point into the result; returns its orbit's minimal period.
    int record(const OrbitPoint& a) {
        const Eigen::Index n = m_tracer.dimension();
        std::vector<double> x(a.z.data(), a.z.data() + n);
        const int minimal = minimal_period(x, a.shot, m_o.orbit.tolerance);
        m_result.points.push_back({a.z[n], m_period, a.F_m, m_tracer.force_error(a), a.z[0],
                                   m_tracer.stable(a), std::abs(a.multipliers.front()), m_branch,
                                   minimal, std::move(x)});
        return minimal;
    }

    /// Whether a corrected point lies within ds of its prediction: a point farther off has
    /// jumped to another sheet (next to a corner the corrector can converge anywhere), and a
    /// bracket with one end on another sheet brackets nothing.
    static bool near(const OrbitPoint& corrected, const Vector& guess, double ds) {
        return (corrected.z - guess).norm() <= ds;
    }

    /// Two points of the branch on either side of a test function's sign change.
    struct Bracket {
        OrbitPoint lo, hi;
    };

    /// How far in the parameter a special point between a bracket's ends can lie from them:
    /// the bracket's width.
    double bracket_width(const Bracket& br) const {
        const Eigen::Index n = m_tracer.dimension();
        return std::abs(br.hi.z[n] - br.lo.z[n]);
    }

    /// The same for a fold, which lies beyond both ends, where the branch turns: with dp/ds
    /// linear between the ends' tangents t_lo and t_hi, p(s) peaks t_lo s* / 2 past the end at
    /// s = 0, s* = t_lo / (t_lo - t_hi) times the arclength between them; the width adds twice
    /// that, for the parabola's sake. At a fold both ends soon have one value of the parameter
    /// whatever their distance: the width alone missed Fig 13's e_r fold at 0.0738587 by 2.7
    /// widths and the period-2 loop's at 2.46507 by 2.6 (the review of 2026-11-27).
    double fold_width(const Bracket& br) const {
        const Eigen::Index n = m_tracer.dimension();
        const double t_lo = br.lo.tangent[n], t_hi = br.hi.tangent[n];
        const double s = t_lo / (t_lo - t_hi) * (br.hi.z - br.lo.z).norm();
        return bracket_width(br) + (std::isfinite(s) ? std::abs(t_lo * s) : 0.0);
    }

    /// Bisection of the bracket a, b of a step of length ds (Newton from its chord's midpoint
    /// on the hyperplane normal to a's tangent) until located(bracket), or the corrector fails.
    template <class Test, class Done>
    Bracket bisect(const OrbitPoint& a, const OrbitPoint& b, double ds, Test test, Done located) {
        const bool sign_lo = test(a) > 0;
        Bracket br{a, b};
        for (int it = 0; it < 60 && !located(br); ++it) {
            // From the chord between the bracket's ends, both on the branch: a guess on a's
            // tangent line lies off it by the branch's curvature, and next to a branch point
            // Newton went from there onto the branch born there (Fig 13's 2.76206 reported an
            // F_m 2.5e-6 off the family's; the review of 2026-11-27).
            const Vector guess = 0.5 * (br.lo.z + br.hi.z);
            std::optional<OrbitPoint> mid = m_tracer.correct(guess, a.tangent);
            // Next to a non-smooth corner the arclength corrector can fail where Newton at the
            // fixed parameter value still converges (away from a fold the orbit is a function
            // of the parameter).
            if (!mid) mid = m_tracer.correct_at_value(guess);
            if (!mid || !near(*mid, guess, ds)) break;
            ((test(*mid) > 0) == sign_lo ? br.lo : br.hi) = std::move(*mid);
        }
        return br;
    }

    /// The step a -> a + ds t walked again in short sub-steps: the first sub-step across which
    /// the test changes sign, or nothing.
    template <class Test>
    std::optional<std::pair<Bracket, double>> retrace(const OrbitPoint& a, double ds, Test test) {
        double sub = ds / 16;
        const bool sign_a = test(a) > 0;
        OrbitPoint x = a;
        // The branch between a and b can be longer than ds when it turns a corner; where the
        // corrector fails, the sub-step is halved as in the walk.
        double walked = 0.0;
        for (int i = 0; i < 200 && walked < 2 * ds && sub >= 1e-9; ++i) {
            const Vector guess = x.z + sub * x.tangent;
            std::optional<OrbitPoint> y = m_tracer.correct(guess, x.tangent);
            if (!y || !near(*y, guess, sub)) {
                sub /= 2;
                continue;
            }
            if ((test(*y) > 0) != sign_a) return std::make_pair(Bracket{x, std::move(*y)}, sub);
            x = std::move(*y);
            walked += sub;
        }
        return std::nullopt;
    }

    /// Bisection in the parameter itself, Newton at each fixed value from the chord between
    /// the bracket's ends: where the branch is a graph over the parameter, this closes in even
    /// where the arclength hyperplane cuts the branch twice.
    template <class Test>
    void bisect_in_value(Bracket& br, Test test) {
        const Eigen::Index n = m_tracer.dimension();
        const bool sign_lo = test(br.lo) > 0;
        for (int it = 0; it < 60 && std::abs(br.hi.z[n] - br.lo.z[n]) > m_o.locate_tolerance;
             ++it) {
            const Vector guess = 0.5 * (br.lo.z + br.hi.z);
            std::optional<OrbitPoint> mid = m_tracer.correct_at_value(guess);
            if (!mid || !near(*mid, guess, (br.hi.z - br.lo.z).norm())) return;
            ((test(*mid) > 0) == sign_lo ? br.lo : br.hi) = std::move(*mid);
        }
    }

    /// A located special point: the orbit at one end of the final bracket, the width within
    /// which the point lies of its value, and the other end (where both are one orbit).
    struct Located {
        OrbitPoint at;
        double value_error;
        std::optional<OrbitPoint> other;
        double F_m_spread = 0.0; ///< a further bound on the error of at's F_m
    };

    /// The error of the F_m of the orbit found at a branch point's turn (between a and b):
    /// along the branch born there F_m parts from the branch point's as the distance s from
    /// it (one contact's force grows, its mirror's falls), F_m = F + k |s|, while the value
    /// turns as p = p* - c s^2. A turn placed to within value_error lies within
    /// sqrt(value_error / c) of it, k and c read off the step's ends; at most their own F_m
    /// spread, the turn lying between them. Without it the pair's F_m at mirror-pair.json's
    /// turn read 0.77987 +- 9e-6 where the pitchfork's is 0.779849.
    double turn_force_error(const OrbitPoint& a, const Located& turn, const OrbitPoint& b) const {
        const Eigen::Index n = m_tracer.dimension();
        const OrbitPoint& x = turn.at;
        double error = 0.0;
        for (const OrbitPoint* y : {&a, &b}) {
            const double spread = std::abs(y->F_m - x.F_m);
            const double s = (y->z - x.z).norm();
            const double c = std::abs(y->z[n] - x.z[n]) / (s * s);
            const double bound = spread / s * std::sqrt(turn.value_error / c);
            error = std::max(error, std::isfinite(bound) ? std::min(bound, spread) : spread);
        }
        return error;
    }

    /// How far the turn of the parabola through a, x and b (the parameter against the chord
    /// length from a) lies from x's value. Next to a branch point Newton's matrix is nearly
    /// singular and the tangents that place a turn are not resolved, but the orbits' values
    /// are: on mirror-pair.json (steps of 5e-4) the turn was placed at 1.21611613 +- 2.9e-8,
    /// 1.1e-7 below the pitchfork (1.2161160180, an independent shooting code).
    double vertex_gap(const OrbitPoint& a, const OrbitPoint& x, const OrbitPoint& b) const {
        const Eigen::Index n = m_tracer.dimension();
        const double s1 = (x.z - a.z).norm(), s2 = s1 + (b.z - x.z).norm();
        const double p0 = a.z[n], p1 = x.z[n], p2 = b.z[n];
        // Divided differences: p = p0 + d1 s + c s (s - s1).
        const double d1 = (p1 - p0) / s1, d2 = (p2 - p1) / (s2 - s1);
        const double c = (d2 - d1) / s2;
        const double b1 = d1 - c * s1; // p = p0 + b1 s + c s^2
        const double vertex = p0 - b1 * b1 / (4.0 * c);
        return std::isfinite(vertex) ? std::abs(vertex - p1) : 0.0;
    }

    /// The fold between a and b: bisection in arclength alone, where the branch is regular
    /// (Newton at a fixed value, as bisect_in_value() takes it, is singular at a fold, and
    /// both sheets lie below it).
    Located locate_fold(const OrbitPoint& a, const OrbitPoint& b, double ds) {
        // The parameter stands still at a fold while the orbit moves on: its F_m is known to
        // the spread of the bracket's ends, which a bracket narrow in the parameter alone left
        // at up to 1e-3 on Fig 13's e_r line (docs/orbits.md).
        const auto located = [this](const Bracket& br) {
            return fold_width(br) <= m_o.locate_tolerance &&
                   std::abs(br.hi.F_m - br.lo.F_m) <= 1e-9 * std::max(1.0, br.lo.F_m);
        };
        Bracket br = bisect(a, b, ds, fold_test, located);
        const bool lo_closer = std::abs(fold_test(br.lo)) < std::abs(fold_test(br.hi));
        // The branch's points are solved to the orbit tolerance, and the fold sits on them to
        // about that: on Fig 13's e_r line, the exact scheme's and rk8pd's folds differed by up
        // to 1.4e-12 with brackets of 1e-14.
        const Eigen::Index n = m_tracer.dimension();
        const double floor = m_o.orbit.tolerance * (1.0 + std::abs(br.lo.z[n]));
        return {lo_closer ? br.lo : br.hi, std::max(fold_width(br), floor),
                lo_closer ? br.hi : br.lo};
    }

    /// The special point between a and b where test changes sign.
    template <class Test>
    Located locate(const OrbitPoint& a, const OrbitPoint& b, double ds, Test test) {
        const Eigen::Index n = m_tracer.dimension();
        const auto located = [this](const Bracket& x) {
            return bracket_width(x) <= m_o.locate_tolerance;
        };
        Bracket br = bisect(a, b, ds, test, located);
        // At a grazing the branch can turn so sharply within one step that the arclength
        // hyperplane cuts it twice, and the bisection hops between the two cuts without
        // closing in: the step is retraced in sub-steps and the sub-step with the sign change
        // bisected instead.
        OrbitPoint from = a;
        double step = ds;
        for (int refine = 0; refine < 3 && std::abs(br.hi.z[n] - br.lo.z[n]) > m_o.locate_tolerance;
             ++refine) {
            auto again = retrace(from, step, test);
            if (!again) break;
            from = again->first.lo;
            step = again->second;
            br = bisect(again->first.lo, again->first.hi, step, test, located);
        }
        bisect_in_value(br, test);
        // A bracket whose ends differ far more in the state than the parameter explains has its
        // ends on two orbits, however narrow it is.
        const double dp = std::abs(br.hi.z[n] - br.lo.z[n]);
        const double dx = (br.hi.z.head(n) - br.lo.z.head(n)).norm();
        if (dp > m_o.locate_tolerance || dx > 100.0 * dp + 1e-9 * (1.0 + br.lo.z.head(n).norm())) {
            auto [at, width] = follow_to_end(br, test);
            return {std::move(at), width, std::nullopt};
        }
        // The reported orbit is one end of the bracket, so the point lies within the bracket's
        // whole width of it.
        const bool lo_closer = std::abs(test(br.lo)) < std::abs(test(br.hi));
        return {lo_closer ? br.lo : br.hi, dp, lo_closer ? br.hi : br.lo};
    }

    /// Where the bracket's ends lie on two different orbits (the branch stepped across a corner
    /// between them), the orbit of the first end is followed in the parameter alone, Newton at
    /// each value from the last state found, until the test changes sign on it or it is no
    /// longer found (where a sheet ends at a grazing corner or a fold, or where Newton from the
    /// last state fails): the special point is there, bracketed by the last value where that
    /// orbit was found unchanged (same contact set, same test sign, near its prediction) and
    /// the first where it was not.
    template <class Test>
    std::pair<OrbitPoint, double> follow_to_end(Bracket br, Test test) {
        const Eigen::Index n = m_tracer.dimension();
        const bool sign_lo = test(br.lo) > 0;
        const auto same_orbit = [&](const OrbitPoint& x, const Vector& guess, double dp) {
            return (test(x) > 0) == sign_lo && near(x, guess, 20.0 * std::abs(dp)) &&
                   same_impacts(x, br.lo);
        };
        double p_hi = br.hi.z[n];
        for (int it = 0; it < 60 && std::abs(p_hi - br.lo.z[n]) > m_o.locate_tolerance; ++it) {
            const double dp = 0.5 * (p_hi - br.lo.z[n]);
            Vector guess = br.lo.z;
            guess[n] += dp;
            std::optional<OrbitPoint> mid = m_tracer.correct_at_value(guess);
            if (mid && same_orbit(*mid, guess, dp))
                br.lo = std::move(*mid);
            else
                p_hi = br.lo.z[n] + dp;
        }
        return {br.lo, std::abs(p_hi - br.lo.z[n])};
    }

    void add(SpecialPointType type, const Located& located, int contact = -1) {
        const OrbitPoint& at = located.at;
        const Eigen::Index n = m_tracer.dimension();
        const int minimal = minimal_period(std::vector<double>(at.z.data(), at.z.data() + n),
                                           at.shot, m_o.orbit.tolerance);
        double force_error = m_tracer.force_error(at);
        if (located.other) {
            const OrbitPoint& other = *located.other;
            // Next to a branch point the bisection's corrector can slide onto the branch born
            // there, whose F_m parts from this one's as the square root of the distance: the
            // point's F_m is known to the spread of the bracket's ends (at Fig 13's 2.76206,
            // 2.5e-6 where the branch moves 6e-9 across the bracket; the review of 2026-11-27).
            force_error = std::max(force_error, std::abs(other.F_m - at.F_m));
        }
        force_error = std::max(force_error, located.F_m_spread);
        SpecialPoint point{type,        at.z[n],  located.value_error,
                           m_period,    minimal,  at.F_m,
                           force_error, m_branch, contact};
        if (!merged_with_listed(point)) m_result.special.push_back(point);
    }

    /// Whether point is one this branch listed already, the two intervals value +- value_error
    /// overlapping; the listed one then covers both. Where a walk steps across a branch point
    /// from one branch onto the other crossing there, the bracket across the step and the
    /// next one along the other branch both hold it: on mirror-pair.json the pitchfork at
    /// 1.2161160 (an independent shooting code, 2026-11-27) was listed at 1.21611595 +- 1.9e-8
    /// (from the bracket across the two branches) and 1.21611623 +- 6.0e-7.
    bool merged_with_listed(const SpecialPoint& point) {
        for (SpecialPoint& listed : m_result.special) {
            if (listed.branch != point.branch || listed.type != point.type ||
                listed.contact != point.contact ||
                std::abs(listed.value - point.value) > listed.value_error + point.value_error)
                continue;
            const double lo =
                std::min(listed.value - listed.value_error, point.value - point.value_error);
            const double hi =
                std::max(listed.value + listed.value_error, point.value + point.value_error);
            // The wider one's orbit is kept, and its interval widened to cover both.
            const SpecialPoint& kept = point.value_error > listed.value_error ? point : listed;
            const double F_m_error =
                std::max(listed.F_m_error, point.F_m_error) + std::abs(listed.F_m - point.F_m);
            listed = kept;
            listed.value_error = std::max(hi - listed.value, listed.value - lo);
            listed.F_m_error = F_m_error;
            return true;
        }
        return false;
    }

    /// Whether the branch goes on past a turn located between a and b: Newton at a value just
    /// beyond it (away from both ends, ten times its value_error) finds an orbit within the
    /// step's chord of it. A fold has none there, its two sheets lying on the near side; a turn
    /// at a branch point has one, the branch crossing there. The count of multipliers outside
    /// the unit circle, which decided until 2026-11-29, does not tell them apart where another
    /// multiplier crosses -1 in the same step, or where the walk turns off the branch born at
    /// a pitchfork onto the symmetric family (exchange of stability): an independent review
    /// (helper-84) on Nm 1, fc 100, eps 0.2, e_r 0.05 found a fold at f_r = 2.62439229 (two
    /// asymmetric orbits above it, none below) listed as a branch point, and the pitchfork at
    /// 1.47792 listed as a fold too.
    bool goes_on_beyond(const OrbitPoint& a, const Located& turn, const OrbitPoint& b) {
        const Eigen::Index n = m_tracer.dimension();
        const double p = turn.at.z[n];
        const double side = a.z[n] + b.z[n] > 2.0 * p ? -1.0 : 1.0;
        // Far enough past the turn that Newton at the orbit tolerance cannot land back on it,
        // and near enough that a branch crossing there is found within a few steps of its
        // slope: the step's chord let another sheet beyond a fold count (a reread, helper-86).
        const double delta = std::max(10.0 * std::max(turn.value_error, m_o.locate_tolerance),
                                      1e3 * m_o.orbit.tolerance * (1.0 + std::abs(p)));
        Vector guess = turn.at.z;
        guess[n] = p + side * delta;
        if (!m_tracer.admissible(guess[n])) return false;
        const std::optional<OrbitPoint> beyond = m_tracer.correct_at_value(guess);
        const double reach = std::min((b.z - a.z).norm(), 1e3 * delta * (1.0 + turn.at.z.norm()));
        return beyond && near(*beyond, guess, reach);
    }

    /// A loss of stability next to -1 that is not smooth (at a grazing corner the multiplier
    /// near -1 jumps across the unit circle and det(M + I) keeps its sign) can also give birth
    /// to doubled orbits: offered for branch switching as a period doubling is.
    void offer_nonsmooth_doubling(const OrbitPoint& a, const OrbitPoint& b) {
        if (m_tracer.stable(a) == m_tracer.stable(b) ||
            (doubling_test(a) > 0) != (doubling_test(b) > 0))
            return;
        const OrbitPoint& unstable = m_tracer.stable(a) ? b : a;
        const OrbitPoint& still = m_tracer.stable(a) ? a : b;
        const std::complex<double> mu = unstable.multipliers.front();
        // Within 10 degrees of the negative real axis.
        if (!(mu.real() < 0.0 && std::abs(mu.imag()) < 0.17 * std::abs(mu))) return;
        const Eigen::Index n = m_tracer.dimension();
        doublings.emplace_back(unstable, unstable.z[n] > still.z[n] ? 1.0 : -1.0);
    }

    /// The turn between a and b, listed as a fold or, where the branch goes on past it
    /// (goes_on_beyond()), a branch point.
    void add_turn(const OrbitPoint& a, const OrbitPoint& b, double ds) {
        Located turn = locate_fold(a, b, ds);
        if (!m_tracer.damped(a) || !goes_on_beyond(a, turn, b))
            return add(SpecialPointType::fold, turn);
        // A smooth turn is placed by its parabola (vertex_gap()); a corner, where the walk
        // turned off onto the symmetric orbit, by the bisection alone: the parabola through a
        // corner is no measure of it (1.2e-3 at a pitchfork that the bisection places to 8e-7,
        // helper-84's row at 1.47792).
        if (outside_unit_circle(a) == outside_unit_circle(b))
            turn.value_error = std::max(turn.value_error, vertex_gap(a, turn.at, b));
        turn.F_m_spread = turn_force_error(a, turn, b);
        add(SpecialPointType::branch_point, turn);
    }

    void detect(const OrbitPoint& a, const OrbitPoint& b, double ds) {
        // A multiplier through +1 turns the branch back (a fold) or, where it goes on, meets
        // another branch (a pitchfork: the mirror symmetry of MODEL.md §5 makes them generic).
        // A turn past which the branch goes on is a branch point (goes_on_beyond()): seen from
        // the branch born at a pitchfork, which turns there into its own mirror image, its
        // multiplier touching +1 (on mirror-pair.json, the stable pair up to the symmetric
        // orbit's pitchfork at 1.2161160 and back down, 0.9999961 at 1.21611577, an
        // independent shooting code), or where the walk turns off it onto the symmetric orbit.
        if ((fold_test(a) > 0) != (fold_test(b) > 0))
            add_turn(a, b, ds);
        else if ((branch_test(a) > 0) != (branch_test(b) > 0))
            add(SpecialPointType::branch_point, locate(a, b, ds, branch_test));
        const auto ta = torus_test(a), tb = torus_test(b);
        const bool torus = ta && tb && (*ta > 0) != (*tb > 0);
        if ((doubling_test(a) > 0) != (doubling_test(b) > 0)) {
            const Located located = locate(a, b, ds, doubling_test);
            const OrbitPoint& at = located.at;
            add(SpecialPointType::period_doubling, located);
            // The doubled orbit lies where the k-orbit is unstable.
            const Eigen::Index n = m_tracer.dimension();
            const double side =
                (m_tracer.stable(a) ? b.z[n] - a.z[n] : a.z[n] - b.z[n]) > 0 ? 1.0 : -1.0;
            doublings.emplace_back(at, side);
        } else if (const int below = multipliers_below_minus_one(a);
                   below != multipliers_below_minus_one(b) && !torus) {
            // A pair through -1 together: Fig 13's period-1 family at f_r = 4.12101 (-1.102
            // twice at 4.118, -0.880 twice at 4.124) was listed as nothing. Listed, not offered
            // for switching: the doubled orbits' direction is a plane there, not a line. Where
            // a complex pair crosses the circle in the same interval (a grazing corner of the
            // period-4 branch at 2.43685), the Neimark-Sacker alone is listed.
            add(SpecialPointType::period_doubling, locate(a, b, ds, [below](const OrbitPoint& x) {
                    return multipliers_below_minus_one(x) == below ? 1.0 : -1.0;
                }));
        }
        offer_nonsmooth_doubling(a, b);
        if (torus)
            add(SpecialPointType::neimark_sacker,
                locate(a, b, ds, [](const OrbitPoint& x) { return torus_test(x).value_or(-1.0); }));
        // A grazing changes the orbit's contact set: some local maximum of a gap passes 0, so
        // the contact's closings per orbit change (the largest gap alone misses a second,
        // smaller impact appearing or vanishing).
        for (std::size_t j = 0; j < a.shot.per_contact.size(); ++j) {
            const long impacts = a.shot.per_contact[j].impacts;
            if (impacts == b.shot.per_contact[j].impacts) continue;
            add(SpecialPointType::grazing,
                locate(a, b, ds,
                       [j, impacts](const OrbitPoint& x) {
                           return x.shot.per_contact[j].impacts == impacts ? 1.0 : -1.0;
                       }),
                static_cast<int>(j));
        }
    }

    BranchTracer& m_tracer;
    const ContinuationOptions& m_o;
    int m_period;
    int m_branch;
    // Whether the last step shortened itself at a corner (cuts_corner()).
    bool m_cut_corner = false;
    ContinuationResult& m_result;
    TracedOrbits& m_traced;
};

/// The first point of a branch at fixed p from x (pseudo-arclength along the parameter axis).
std::optional<OrbitPoint> first_point(BranchTracer& tracer, const std::vector<double>& x, double p,
                                      double direction) {
    const Eigen::Index n = tracer.dimension();
    Vector z(n + 1);
    for (Eigen::Index i = 0; i < n; ++i)
        z[i] = x[static_cast<std::size_t>(i)];
    z[n] = p;
    Vector t = Vector::Zero(n + 1);
    t[n] = direction;
    return tracer.correct(z, t);
}

/// The doubled orbit next to a period doubling: Newton on the 2k-map from the k-orbit displaced
/// along the multiplier -1's eigenvector, a little into the side where it exists; nothing if
/// keep_going stopped its Newton search.
std::optional<std::vector<double>> doubled_orbit(const ReducedParameters& base,
                                                 const ContinuationOptions& o, int period,
                                                 const OrbitPoint& at, double side, double& p,
                                                 const ProgressCallback& keep_going) {
    const Eigen::Index n = static_cast<Eigen::Index>(2 * base.Nm);
    const Matrix m = Eigen::Map<const Matrix>(at.shot.monodromy.data(), n, n);
    const Eigen::EigenSolver<Matrix> solver(m, true);
    Eigen::Index k = 0;
    for (Eigen::Index i = 1; i < n; ++i)
        if (std::abs(solver.eigenvalues()[i] + 1.0) < std::abs(solver.eigenvalues()[k] + 1.0))
            k = i;
    const Vector v = solver.eigenvectors().col(k).real().normalized();
    OrbitOptions orbit = o.orbit;
    orbit.period = 2 * period;
    for (double offset : {0.2 * o.step, 0.5 * o.step, o.step}) {
        p = at.z[n] + side * offset;
        if (swept_value_error(base, o.parameter, p)) continue;
        const ReducedParameters q = with_value(base, o.parameter, p);
        const Dynamics dyn = Dynamics::paper_row(q);
        // A 2k-shooting beyond run.max_work leaves the doubling unfollowed, not the line lost.
        if (shooting_work(dyn, orbit) > orbit.max_work) continue;
        for (double a : {0.02, -0.02, 0.1, -0.1}) {
            std::vector<double> x(static_cast<std::size_t>(n));
            for (Eigen::Index i = 0; i < n; ++i)
                x[i] = at.z[i] + a * (1.0 + at.z.head(n).norm()) * v[i];
            const PeriodicOrbit found = find_periodic_orbit(dyn, orbit, x, keep_going);
            if (found.status == OrbitStatus::cancelled) return std::nullopt;
            if (found.status == OrbitStatus::converged && found.minimal_period == 2 * period)
                return found.state;
        }
    }
    return std::nullopt;
}

/// Past a non-smooth corner the corrector cannot turn (or where a branch turned back out of the
/// range): the branch restarts beyond the farthest value reached, one first step past it (then
/// one largest step, where no orbit of the period is found that close), from a fresh transient
/// run: possibly another orbit of the same period, so the CSV gives it its own branch index.
/// The state and the value; a cancelled transient run sets result.cancelled.
std::optional<std::pair<std::vector<double>, double>>
restart_beyond(const ReducedParameters& base, const ContinuationOptions& options,
               const std::vector<double>& initial, double farthest,
               const ProgressCallback& keep_going, ContinuationResult& result) {
    const double direction = options.to > options.from ? 1.0 : -1.0;
    OrbitOptions orbit = options.orbit;
    orbit.period = options.period;
    for (double offset : {options.step, options.max_step}) {
        // A step past the end value restarts at it, to be walked back only: the stretch up to
        // it was skipped (--to 2.771 on Fig 13's row lost the symmetric orbit's Neimark-Sacker
        // point at 2.77011, a second reader found).
        double p = farthest + direction * offset;
        if ((p - options.to) * direction >= 0.0) p = options.to;
        if ((p - options.from) * direction <= 0.0) return std::nullopt;
        const ReducedParameters q = with_value(base, options.parameter, p);
        const Dynamics dyn = Dynamics::paper_row(q);
        const PeriodicOrbit again =
            find_periodic_orbit_after(dyn, orbit, initial, options.transient_periods, keep_going);
        if (again.status == OrbitStatus::converged && again.minimal_period == orbit.period)
            return std::make_pair(again.state, p);
        if (again.status == OrbitStatus::cancelled) {
            result.cancelled = true;
            return std::nullopt;
        }
        if (p == options.to) break;
    }
    return std::nullopt;
}

/// base with the continued parameter at value, checked by the model; its range message is
/// prefixed with the option that carried the value ("from" or "to").
ReducedParameters model_with(const ReducedParameters& base, const ContinuationOptions& options,
                             double value, const char* option) {
    if (const auto error = swept_value_error(base, options.parameter, value))
        throw std::invalid_argument(std::string(option) + ": " + *error);
    return with_value(base, options.parameter, value);
}

/// The orbit of options.period at the start value after the transient run from initial; a
/// failure is the first branch's end, a cancelled transient the result's.
PeriodicOrbit first_orbit(const ReducedParameters& start, const ContinuationOptions& options,
                          const std::vector<double>& initial, const ProgressCallback& keep_going,
                          ContinuationResult& result) {
    OrbitOptions orbit = options.orbit;
    orbit.period = options.period;
    const Dynamics dyn = Dynamics::paper_row(start);
    PeriodicOrbit found =
        find_periodic_orbit_after(dyn, orbit, initial, options.transient_periods, keep_going);
    result.cancelled = found.status == OrbitStatus::cancelled;
    if (found.status != OrbitStatus::converged && !result.cancelled)
        result.branch_end.push_back("no orbit found at the start: " + found.message);
    return found;
}

} // namespace

namespace {

/// A branch still to trace: its first orbit's state x at parameter value p, its period, and
/// the direction it sets off in.
struct PendingBranch {
    std::vector<double> x;
    double p;
    int period;
    double direction;
    /// Where a walk back from a restart stops (the farthest value of the branch before it),
    /// traced over [until, p] only; none for a walk over the whole line
    std::optional<double> until = std::nullopt;
};

/// The branches still pending when max_branches ended the call, into result.unfollowed: said,
/// not dropped (the probe of 2026-11-27: --follow-doublings --max-branches 1 wrote what a run
/// without --follow-doublings did, and looked complete).
void list_unfollowed(const std::deque<PendingBranch>& pending, const ContinuationOptions& options,
                     ContinuationResult& result) {
    for (const PendingBranch& left : pending)
        result.unfollowed.push_back(
            "period " + std::to_string(left.period) + " from " +
            std::string(to_string(options.parameter)) + " = " + detail::format_number(left.p) +
            (left.until ? " back to " + detail::format_number(*left.until) : std::string()));
}

/// Refuses a line whose branches may not reach `to` within run.max_work: a step advances the
/// parameter by at most max_step, so a branch walked across the line takes |to - from| /
/// max_step points (or max_points, where it stops first), each a prediction and at least two
/// corrections, and up to max_branches branches are walked. --step 1e-6 --max-step 1e-6
/// --max-points 1000000 over 1 .. 4.5 ran on for hours, each of its shootings within the limit
/// (a hostile probe, helper-85; 3.6 shootings a point, 230 points a second on that row).
void require_walk_affordable(const ReducedParameters& start, const ReducedParameters& end,
                             const ContinuationOptions& options, const OrbitOptions& shooting) {
    const double points =
        std::min(static_cast<double>(options.max_points),
                 std::ceil(std::abs(options.to - options.from) / options.max_step));
    const double per_shooting = std::max(shooting_work(Dynamics::paper_row(start), shooting),
                                         shooting_work(Dynamics::paper_row(end), shooting));
    // The fields are named as the library and Python call them; the tool maps them to flags.
    detail::require_work(
        3.0 * points * options.max_branches * per_shooting, shooting.max_work,
        "walking the line may take",
        std::to_string(options.max_branches) + " branches (max_branches) of " +
            detail::format_number(points) + " points (max_points) of 3 shootings, at most " +
            detail::format_number(options.max_step) + " apart in the parameter (max_step)",
        "ask less (a larger max_step, fewer max_points or max_branches), a "
        "shorter line or a larger run.max_work");
}

/// The row at options.from, once the options, both ends of the line, the row's size and the
/// walk's work are checked (std::invalid_argument naming the first bad one).
ReducedParameters checked_start(const ReducedParameters& base, const ContinuationOptions& options) {
    validate(options);
    const ReducedParameters start = model_with(base, options, options.from, "from");
    const ReducedParameters end = model_with(base, options, options.to, "to");
    // Both ends: the exact scheme's limit on the contacts' speed rises with fc, and a line
    // that crossed it was refused only where it got there, its output lost.
    OrbitOptions shooting = options.orbit;
    shooting.period = options.period;
    for (const auto& [row, option] : {std::pair{start, "from"}, std::pair{end, "to"}}) {
        try {
            require_orbit_size(Dynamics::paper_row(row), shooting.scheme);
            require_shooting_affordable(Dynamics::paper_row(row), shooting);
        } catch (const std::invalid_argument& e) {
            detail::rethrow_naming_end(e, option);
        }
    }
    require_walk_affordable(start, end, options, shooting);
    return start;
}

/// The options a pending branch is walked with: the line's, or for a walk back from a restart
/// the stretch from its start back to where the branch it restarts ended.
ContinuationOptions walked_options(const ContinuationOptions& options, const PendingBranch& next) {
    ContinuationOptions walked = options;
    if (next.until) {
        walked.from = next.p;
        walked.to = *next.until;
    }
    return walked;
}

/// How a walk back from a restart ended when it got there.
std::string back_to(const ContinuationOptions& options, const PendingBranch& next) {
    std::ostringstream why;
    why.precision(7);
    why << "reached " << to_string(options.parameter) << " = " << *next.until
        << ", where the branch it restarts ended (traced back from the restart at " << next.p
        << ")";
    return why.str();
}

/// A restart beyond `farthest`, where a branch of the line's period turned back or ended short
/// of the end, queued first: traced on to the end, and back to `farthest`, or the stretch in
/// between is skipped. On Fig 13's row from 2.7 (default step 0.01) the branch restarted at
/// 2.772 after the pitchfork at 2.762 and the symmetric orbit's Neimark-Sacker point at 2.77011
/// was missing; found with a step of 0.002 (a helper's probe, 2026-11-27).
void queue_restart(const ReducedParameters& base, const ContinuationOptions& options,
                   const std::vector<double>& initial, double farthest,
                   const ProgressCallback& keep_going, ContinuationResult& result,
                   std::deque<PendingBranch>& pending) {
    const auto restart = restart_beyond(base, options, initial, farthest, keep_going, result);
    if (!restart) return;
    // The walk on comes first: where max_branches leaves room for one, the line reaches its
    // end and the walk back is listed as not followed.
    const double direction = options.to > options.from ? 1.0 : -1.0;
    pending.push_front({restart->first, restart->second, options.period, -direction, farthest});
    if (restart->second != options.to) // at the end value there is nothing left to walk on to
        pending.push_front({restart->first, restart->second, options.period, direction});
}

} // namespace

ContinuationResult continue_orbits(const ReducedParameters& base,
                                   const ContinuationOptions& options,
                                   const std::vector<double>& initial,
                                   const ProgressCallback& progress) {
    const auto clock = std::chrono::steady_clock::now();
    const ReducedParameters start = checked_start(base, options);
    // The first branch reports the farthest it has come (Fig 13's walked back from 46.8 to
    // 33.9 % at a fold), each branch begun its share of max_branches, the end 1 (a first
    // branch that turned back early held 10.9 % to the end, helper-85); the rest repeat it.
    double last_fraction = 0.0;
    const ProgressCallback first_branch = [&](double f) {
        last_fraction = std::max(last_fraction, f);
        return !progress || progress(last_fraction);
    };
    const ProgressCallback keep_going = [&](double) {
        return !progress || progress(last_fraction);
    };
    ContinuationResult result;
    const double direction = options.to > options.from ? 1.0 : -1.0;
    const PeriodicOrbit found = first_orbit(start, options, initial, keep_going, result);
    std::deque<PendingBranch> pending;
    TracedOrbits traced;
    if (found.status == OrbitStatus::converged)
        pending.push_back({found.state, options.from, options.period, direction});
    for (int branch = 0; !pending.empty() && branch < options.max_branches && !result.cancelled;
         ++branch) {
        const PendingBranch next = pending.front();
        pending.pop_front();
        last_fraction = std::max(last_fraction, static_cast<double>(branch) / options.max_branches);
        const ContinuationOptions walked = walked_options(options, next);
        BranchTracer tracer(base, walked, next.period, keep_going);
        std::optional<OrbitPoint> first = first_point(tracer, next.x, next.p, next.direction);
        if (!first) { // a cancelled tracer's corrections all fail
            result.cancelled = tracer.cancelled();
            result.branch_end.push_back(result.cancelled ? "cancelled"
                                                         : "the first point did not converge");
            continue;
        }
        BranchWalk walk(tracer, walked, next.period, branch, result, traced);
        walk.walk(std::move(*first), branch == 0 ? first_branch : keep_going);
        result.shootings += tracer.shootings();
        if (next.until && walk.reached_end) result.branch_end.back() = back_to(options, next);
        if (!walk.reached_end && !result.cancelled && next.period == options.period && !next.until)
            queue_restart(base, options, initial, walk.farthest, keep_going, result, pending);
        if (result.cancelled || !options.follow_doublings) continue; // the loop's test ends it
        for (const auto& [at, side] : walk.doublings) {
            double p = 0.0;
            if (auto x = doubled_orbit(base, options, next.period, at, side, p, keep_going))
                pending.push_back({*x, p, 2 * next.period, side});
        }
    }
    if (!result.cancelled) list_unfollowed(pending, options, result);
    // Done: a cancel asked now has nothing left to stop.
    if (!result.cancelled && progress) (void)progress(1.0);
    result.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    return result;
}

ForceErrorSummary force_error_summary(const ContinuationResult& result) {
    ForceErrorSummary summary;
    const auto count = [&](double error) {
        if (std::isnan(error))
            ++summary.unestimated;
        else
            summary.largest = std::max(summary.largest, error);
        ++summary.orbits;
    };
    for (const auto& p : result.points)
        count(p.F_m_error);
    for (const auto& s : result.special)
        count(s.F_m_error);
    return summary;
}

} // namespace gapchain
