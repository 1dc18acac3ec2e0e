#include "gapchain/modes.hpp"

#include "detail/check.hpp"

#include "detail/tridiagonal_shift_solve.hpp"

#include <Eigen/Dense>
#include <Spectra/SymEigsShiftSolver.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

namespace gapchain {

EigenMethod parse_eigen_method(std::string_view name) {
    if (name == "auto") return EigenMethod::automatic;
    if (name == "dense") return EigenMethod::dense;
    if (name == "sparse") return EigenMethod::sparse;
    throw std::invalid_argument("method: must be auto, dense or sparse, got \"" +
                                std::string(name) + "\"");
}

std::string_view to_string(EigenMethod method) {
    switch (method) {
    case EigenMethod::automatic: return "auto";
    case EigenMethod::dense: return "dense";
    case EigenMethod::sparse: return "sparse";
    }
    return "?";
}

Tridiagonal linear_chain_matrix(const Chain& c) {
    validate(c);
    const int n = c.bodies();
    Tridiagonal t;
    t.diagonal.resize(n);
    t.off_diagonal.resize(std::max(0, n - 1));
    // Chain::spring is in reduced rate units (4 pi^2 for the nominal body); K_lin is in K.
    for (int i = 0; i < n; ++i)
        t.diagonal[i] =
            (c.spring[i] * c.mass[i] / four_pi_squared + c.contact[i] + c.contact[i + 1]) /
            c.mass[i];
    for (int i = 0; i + 1 < n; ++i)
        t.off_diagonal[i] = -c.contact[i + 1] / std::sqrt(c.mass[i] * c.mass[i + 1]);
    return t;
}

double approx_frequency(int k, int Nm, double fc) {
    detail::require_range("k", k, 1, std::max(1, Nm));
    const double x = static_cast<double>(k) / Nm;
    return std::sqrt(1.0 + fc * x * x * (4.935 - 2.935 * std::pow(x, 1.81)));
}

double approx_first_mode_end_amplitude(int Nm) {
    detail::require_range("model.Nm", Nm, 1, 1'000'000'000);
    return std::numbers::pi / Nm;
}

namespace {

/// Fills frequencies, approximations, shapes (phi = M^-1/2 psi) and residuals from the
/// eigenpairs of the mass-normalised matrix.
void fill_modes(const Chain& c, const Tridiagonal& t, const Eigen::VectorXd& values,
                const Eigen::MatrixXd& vectors, int first_mode, bool shapes, double fc_nominal,
                ModalResult& r) {
    const int n = c.bodies();
    const int count = static_cast<int>(values.size());
    for (int m = 0; m < count; ++m) {
        const int k = first_mode + m;
        const double lambda = values[m];
        r.mode_numbers.push_back(k);
        r.frequencies.push_back(std::sqrt(lambda));
        r.approx.push_back(approx_frequency(k, n, fc_nominal));
        r.rel_error.push_back((r.approx.back() - r.frequencies.back()) / r.frequencies.back());
        const Eigen::VectorXd psi = vectors.col(m);
        double res2 = 0.0;
        for (int i = 0; i < n; ++i) {
            double a = t.diagonal[i] * psi[i];
            if (i > 0) a += t.off_diagonal[i - 1] * psi[i - 1];
            if (i + 1 < n) a += t.off_diagonal[i] * psi[i + 1];
            res2 += (a - lambda * psi[i]) * (a - lambda * psi[i]);
        }
        r.residuals.push_back(std::sqrt(res2) / lambda);
        if (shapes) {
            std::vector<double> phi(n);
            // A fixed sign convention: the first body moves positively (or the first nonzero).
            double sign = 1.0;
            for (int i = 0; i < n; ++i)
                if (std::abs(psi[i]) > 1e-12) {
                    sign = psi[i] > 0 ? 1.0 : -1.0;
                    break;
                }
            for (int i = 0; i < n; ++i)
                phi[i] = sign * psi[i] / std::sqrt(c.mass[i]);
            r.shapes.push_back(std::move(phi));
        }
    }
}

/// The solver modal_analysis() uses: o.method, or for auto the dense one for small rows and
/// many modes. Throws std::invalid_argument if the chosen solver cannot take the row.
EigenMethod chosen_method(const ModalOptions& o, int n, int count) {
    EigenMethod method = o.method;
    if (method == EigenMethod::automatic)
        method = (n <= 2000 || count == n || 2 * count + 1 > n) ? EigenMethod::dense
                                                                : EigenMethod::sparse;
    detail::require_range("max_dense_bodies", o.max_dense_bodies, 1, 1'000'000);
    if (method == EigenMethod::dense && n > o.max_dense_bodies) {
        const double gigabytes = 8.0 * n * static_cast<double>(n) / 1e9;
        throw std::invalid_argument(
            "max_dense_bodies: the dense solver for Nm = " + std::to_string(n) +
            " needs an Nm x Nm matrix (" + detail::format_number(gigabytes) + " GB) and ~" +
            detail::format_number(static_cast<double>(n) * n * n) +
            " operations, above the limit Nm <= " + std::to_string(o.max_dense_bodies) +
            "; ask fewer modes (1 <= modes < Nm / 2 use the sparse solver) or raise the limit");
    }
    if (method == EigenMethod::sparse && (o.count < 1 || 2 * count + 1 > n))
        throw std::invalid_argument("count: the sparse solver needs 1 <= modes < Nm / 2, got " +
                                    std::to_string(o.count) + " of Nm = " + std::to_string(n) +
                                    "; use the dense solver for more");
    return method;
}

/// The modes wanted, for the whole spectrum at once (Eigen's tridiagonal solver).
void dense_modes(const Chain& chain, const Tridiagonal& t, const ModalOptions& o, int first_mode,
                 int count, double fc, ModalResult& r) {
    const int n = chain.bodies();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver;
    const Eigen::Map<const Eigen::VectorXd> d(t.diagonal.data(), n);
    const Eigen::Map<const Eigen::VectorXd> e(t.off_diagonal.data(), n - 1);
    solver.computeFromTridiagonal(d, e, Eigen::ComputeEigenvectors);
    if (solver.info() != Eigen::Success) r.status = ModalStatus::not_converged;
    const int offset = first_mode - 1;
    fill_modes(chain, t, solver.eigenvalues().segment(offset, count),
               solver.eigenvectors().middleCols(offset, count), first_mode, o.shapes, fc, r);
}

/// Bounds on the spectrum: below, the smallest body spring (the contact matrix is positive
/// definite with walls); above, Gershgorin's.
struct SpectrumBounds {
    double lower = 0.0;
    double upper = 0.0;
};

SpectrumBounds spectrum_bounds(const Chain& chain, const Tridiagonal& t) {
    const int n = chain.bodies();
    SpectrumBounds b{t.diagonal[0], 0.0};
    for (int i = 0; i < n; ++i) {
        const double off = (i > 0 ? std::abs(t.off_diagonal[i - 1]) : 0.0) +
                           (i + 1 < n ? std::abs(t.off_diagonal[i]) : 0.0);
        b.lower = std::min(b.lower, chain.spring[i] / four_pi_squared);
        b.upper = std::max(b.upper, t.diagonal[i] + off);
    }
    return b;
}

/// Whether every mode's residual is what the Lanczos tolerance promises. Spectra's tolerance
/// holds for the inverted operator: carried back, |A psi - lambda psi| <= tolerance
/// |A - sigma I| <= tolerance (upper - lower) (a correct lowest mode of a scattered row read
/// 2.3e-12 against 1e-12), and rounding allows no better than 64 eps upper. A residual beyond
/// both is a wrong mode (the highest modes of short rows read 3e-2).
bool residuals_resolve(const ModalResult& r, double tolerance, const SpectrumBounds& bounds) {
    const double promised = std::max(tolerance * (bounds.upper - bounds.lower),
                                     64.0 * std::numeric_limits<double>::epsilon() * bounds.upper);
    for (std::size_t m = 0; m < r.residuals.size(); ++m) {
        const double lambda = r.frequencies[m] * r.frequencies[m];
        if (!(r.residuals[m] <= std::max(tolerance, promised / lambda))) return false;
    }
    return true;
}

/// The modes wanted, by shift-and-invert Lanczos (Spectra) about shift, outside the spectrum at
/// the wanted end; r.iterations adds its restarts.
void shifted_lanczos(const Chain& chain, const Tridiagonal& t, const ModalOptions& o,
                     int first_mode, int count, double fc, double shift, ModalResult& r) {
    const int n = chain.bodies();
    detail::TridiagonalShiftSolve op(t);
    const int ncv = std::min(n, std::max(2 * count + 1, 20));
    Spectra::SymEigsShiftSolver<detail::TridiagonalShiftSolve> eigs(op, count, ncv, shift);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestMagn, 1000, o.tolerance);
    r.iterations += eigs.num_iterations();
    switch (eigs.info()) {
    case Spectra::CompInfo::Successful: r.status = ModalStatus::converged; break;
    case Spectra::CompInfo::NotConverging: r.status = ModalStatus::not_converged; break;
    default: r.status = ModalStatus::numerical_issue; break;
    }
    if (r.status != ModalStatus::converged) return;
    // Spectra returns them by decreasing |1/(lambda - sigma)|; sort ascending.
    Eigen::VectorXd values = eigs.eigenvalues();
    Eigen::MatrixXd vectors = eigs.eigenvectors();
    std::vector<int> order(count);
    for (int m = 0; m < count; ++m)
        order[m] = m;
    std::sort(order.begin(), order.end(), [&](int x, int y) { return values[x] < values[y]; });
    Eigen::VectorXd sorted_values(count);
    Eigen::MatrixXd sorted_vectors(n, count);
    for (int m = 0; m < count; ++m) {
        sorted_values[m] = values[order[m]];
        sorted_vectors.col(m) = vectors.col(order[m]);
    }
    fill_modes(chain, t, sorted_values, sorted_vectors, first_mode, o.shapes, fc, r);
}

/// The modes wanted, by shift-and-invert Lanczos. A shift close to the spectrum separates modes
/// that crowd together near f = 1 on long chains. But the uniform row's highest eigenvalue,
/// 1 + 2 fc (the alternating vector), is the Gershgorin bound itself: a shift 1e-12 above it
/// makes (A - sigma I) nearly singular, and its solves swamp the other modes (Nm = 10,
/// fc = 100: the 3 highest read 0.5 % low, "converged", residuals 3e-2). The shift therefore
/// moves away until every residual is what the tolerance promises. A solve that never gets
/// there says not_converged, with the trial whose largest residual was smallest.
void sparse_modes(const Chain& chain, const Tridiagonal& t, const ModalOptions& o, int first_mode,
                  int count, double fc, ModalResult& r) {
    const SpectrumBounds bounds = spectrum_bounds(chain, t);
    const ModalResult blank = r;
    const auto largest_residual = [](const ModalResult& m) {
        return m.residuals.empty() ? std::numeric_limits<double>::infinity()
                                   : *std::max_element(m.residuals.begin(), m.residuals.end());
    };
    long iterations = 0;
    bool kept = false;
    for (const double distance : {1e-12, 1e-9, 1e-6, 1e-4, 1e-2}) {
        ModalResult trial = blank;
        trial.iterations = iterations;
        const double shift = o.end == SpectrumEnd::lowest ? bounds.lower * (1.0 - distance)
                                                          : bounds.upper * (1.0 + distance);
        shifted_lanczos(chain, t, o, first_mode, count, fc, shift, trial);
        iterations = trial.iterations;
        const bool resolved =
            trial.status == ModalStatus::converged && residuals_resolve(trial, o.tolerance, bounds);
        if (!resolved && trial.status == ModalStatus::converged)
            trial.status = ModalStatus::not_converged;
        if (resolved || !kept || largest_residual(trial) < largest_residual(r)) {
            r = std::move(trial);
            kept = true;
        }
        r.iterations = iterations;
        if (resolved) return;
    }
}

} // namespace

ModalResult modal_analysis(const Chain& chain, const ModalOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    // A Hertz or Hunt-Crossley contact has no stiffness at zero overlap: the modes printed were
    // those of a linear row the scene did not describe.
    if (chain.law != ContactLaw::linear)
        throw std::invalid_argument(
            std::string("model.contact_law: the linear chain's modes need the linear contact law "
                        "(a ") +
            to_string(chain.law) + " contact has no stiffness at zero overlap), got " +
            to_string(chain.law));
    const Tridiagonal t = linear_chain_matrix(chain);
    const int n = chain.bodies();
    // The sparse solver's own range first: "[0, 3]" for 4 modes of Nm = 3, then "1 <= modes <
    // Nm / 2" for 3, read as two rules contradicting each other.
    if (o.method != EigenMethod::sparse) detail::require_range("count", o.count, 0, n);
    detail::require_range("tolerance", o.tolerance, 0.0, 1e-2, detail::Bound::open_low);
    // Nominal fc for eq (26): the wall contact stiffness (fc for the paper's row).
    const double fc = chain.contact.front();
    const int count = o.count == 0 ? n : o.count;
    ModalResult r;
    r.method = chosen_method(o, n, count);
    const int first_mode = o.end == SpectrumEnd::lowest ? 1 : n - count + 1;
    if (r.method == EigenMethod::dense)
        dense_modes(chain, t, o, first_mode, count, fc, r);
    else
        sparse_modes(chain, t, o, first_mode, count, fc, r);
    // Eq (26) is the paper's uniform row's: against a row of other masses, springs or contacts
    // it reported "rel.error 44.9 %" as if it were the formula's error.
    const auto uniform = [&] {
        try {
            return std::optional(Chain::homogeneous({n, fc, 0.0, 0.0, 1.0}));
        } catch (const std::invalid_argument&) { // a wall contact out of the paper's range
            return std::optional<Chain>();
        }
    }();
    if (!uniform || chain.mass != uniform->mass || chain.spring != uniform->spring ||
        chain.contact != uniform->contact) {
        r.approx.assign(r.approx.size(), std::numeric_limits<double>::quiet_NaN());
        r.rel_error.assign(r.rel_error.size(), std::numeric_limits<double>::quiet_NaN());
    }
    r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

ApproximationGrid approximation_grid(const std::vector<int>& Nm_values,
                                     const std::vector<double>& fc_values,
                                     const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    ApproximationGrid grid;
    ModalOptions o;
    o.shapes = false;
    const auto work = [](int Nm) { return 1.0 + std::pow(static_cast<double>(Nm), 3); };
    double total = 0.0, done = 0.0;
    for (int Nm : Nm_values)
        total += work(Nm) * static_cast<double>(fc_values.size());
    // --grid-Nm-max 2000 --grid-fc-points 100000 was accepted and would have run for years
    // (a hostile probe, helper-85: 400 and 10 took 44 s).
    if (total > max_grid_work)
        throw std::invalid_argument(
            "fc_values: " + std::to_string(fc_values.size()) + " values of fc on rows up to Nm = " +
            std::to_string(*std::max_element(Nm_values.begin(), Nm_values.end())) + " are about " +
            detail::format_number(std::ceil(total)) +
            " units of dense work (the sum of Nm^3), about " +
            detail::format_number(std::ceil(total / 1.5e9 / 60.0)) +
            " min at 1.5e9 a second; at most " + detail::format_number(max_grid_work) +
            ": ask less (fewer fc values or a smaller largest Nm)");
    for (int Nm : Nm_values)
        for (double fc : fc_values) {
            if (progress && !progress(done / total)) {
                grid.cancelled = true;
                return grid;
            }
            done += work(Nm);
            const ModalResult r = modal_analysis(Chain::homogeneous({Nm, fc, 0.5, 0.0, 1.0}), o);
            ApproximationError e;
            e.Nm = Nm;
            e.fc = fc;
            e.first = r.rel_error[0];
            for (int k = 1; k < Nm; ++k)
                if (std::abs(r.rel_error[k]) > e.other) {
                    e.other = std::abs(r.rel_error[k]);
                    e.other_mode = k + 1;
                }
            if (grid.points.empty() || std::abs(e.first) > std::abs(grid.worst_first.first))
                grid.worst_first = e;
            if (grid.points.empty() || e.other > grid.worst_other.other) grid.worst_other = e;
            grid.points.push_back(e);
        }
    grid.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return grid;
}

} // namespace gapchain
