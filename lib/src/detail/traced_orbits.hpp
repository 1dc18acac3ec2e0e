#pragma once
// The orbits a continuation has traced, and whether a new point lies on one of them
// (continuation.cpp; a header of its own so that its rules are tested alone).

#include <Eigen/Dense>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace gapchain::detail {

/// The orbits a continuation has traced, as curves in (state at phase 0, parameter): each
/// branch once per phase, since a period-k orbit has k states at phase 0 and a branch can
/// come onto the same orbits at another of them (Fig 13's period-2 loop, reached from two
/// losses of stability of period 1, once at each phase).
class TracedOrbits {
public:
    using Vector = Eigen::VectorXd;

    /// Starts the curves of a new branch of period k.
    void begin_branch(int branch, int period) {
        m_current = m_curves.size();
        for (int s = 0; s < period; ++s)
            m_curves.push_back({branch, period, {}});
        m_arclength.clear();
    }

    /// Adds a point of the current branch, at its arclength from the branch's start: z is the
    /// orbit's state at phase 0 followed by the parameter, at_ends its states after periods
    /// 1..k (orbit.hpp's ShootingResult::at_ends; missing ones are taken as z's).
    void add(const Vector& z, const std::vector<std::vector<double>>& at_ends, double arclength) {
        const Eigen::Index n = z.size() - 1;
        const std::size_t k = m_curves.size() - m_current;
        for (std::size_t s = 0; s < k; ++s) {
            Vector point = z;
            // The state after s + 1 periods; after k, the orbit's own state, z.
            if (s + 1 < k && s < at_ends.size())
                std::copy(at_ends[s].begin(), at_ends[s].end(), point.data());
            point[n] = z[n];
            m_curves[m_current + s].points.push_back(std::move(point));
        }
        m_arclength.push_back(arclength);
    }

    /// The branch whose orbits z (of minimal period `minimal`) lies on, or -1. A branch of
    /// period k holds orbits whose minimal period divides k, so only those are compared: a
    /// doubled branch leaves its parent along it (Fig 13's period-4 branch from 2.33275 stays
    /// within 3e-4 of the period-2 orbits for 0.01 in f_r) and is compared with it only once
    /// its orbits are of the parent's period again. The current branch counts only on points
    /// more than 20 points and 4 steps of arclength back: nearer ones are its neighbours on the
    /// curve, a fold's other side among them. (In 20 max_step of arclength, as until
    /// 2026-11-26, Fig 13's period-4 loop at 3.13, 0.04 round at steps of 1e-3, went round 22
    /// times; in points alone, steps collapsed to 1e-6 would bring 20 points within a chord's
    /// tolerance.)
    [[nodiscard]] int branch_under(const Vector& z, int minimal, double arclength,
                                   double step) const {
        std::size_t old_end = m_arclength.size() > 20 ? m_arclength.size() - 20 : 0;
        while (old_end > 0 && arclength - m_arclength[old_end - 1] <= 4.0 * step)
            --old_end;
        for (std::size_t c = 0; c < m_curves.size(); ++c) {
            if (minimal > 0 && m_curves[c].period % minimal != 0) continue;
            const bool current = c >= m_current;
            if (on_curve(z, m_curves[c].points, current ? old_end : m_curves[c].points.size(),
                         step))
                return m_curves[c].branch;
        }
        return -1;
    }

private:
    /// Whether z lies on the curve through points[0, end): within twice the step of one of
    /// them and, closer still, on one of the chords to its neighbours.
    static bool on_curve(const Vector& z, const std::vector<Vector>& points, std::size_t end,
                         double step) {
        // Two sheets that meet at a fold come within a step of each other near it (Fig 13's
        // period-2 loop at 2.4557: 0.04 apart at steps of 0.027) without being one curve; a
        // retraced curve lies on its old chords to the corrector's tolerance and their
        // sagitta (1.3e-5 at the corner of 2.99783, steps of 0.05): within 0.006 step on Fig 13's
        // retraces, while a branch that crossed another at a shallow angle came within 0.004
        // step of it once, and within 0.1 step for 7 points in a row.
        const double chord = 0.02 * step;
        for (std::size_t i = 0; i < end; ++i) {
            if ((points[i] - z).norm() >= 2.0 * step) continue;
            if (i > 0 && distance_to_chord(z, points[i - 1], points[i]) <= chord) return true;
            if (i + 1 < points.size() && distance_to_chord(z, points[i], points[i + 1]) <= chord)
                return true;
        }
        return false;
    }

    static double distance_to_chord(const Vector& z, const Vector& a, const Vector& b) {
        const Vector ab = b - a;
        const double length2 = ab.squaredNorm();
        const double t = length2 > 0.0 ? std::clamp((z - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
        return (z - a - t * ab).norm();
    }

    struct Curve {
        int branch;
        int period;
        std::vector<Vector> points;
    };
    std::vector<Curve> m_curves;
    std::size_t m_current = 0;       // the current branch's first curve
    std::vector<double> m_arclength; // of the current branch's points
};

} // namespace gapchain::detail
