#pragma once
/// \file modes.hpp
/// Linear-chain modal analysis (paper Section 5, MODEL.md §4): with e_r = 0 and every contact
/// acting both ways the row is linear, with reduced stiffness matrix K_lin = S + sum_j k_j c_j
/// c_j^T (S the body springs in units of K, k_j the contact stiffnesses in units of K). Its
/// natural frequencies f_k = sqrt(eig_k(M^-1 K_lin)) are compared with the paper's eq (26).

#include "gapchain/model.hpp"
#include "gapchain/run.hpp"

#include <string_view>
#include <vector>

namespace gapchain {

/// Symmetric tridiagonal matrix: diagonal (n entries) and off-diagonal (n - 1 entries).
struct Tridiagonal {
    std::vector<double> diagonal;     ///< n entries, units of K / M
    std::vector<double> off_diagonal; ///< n - 1 entries, the same units
};

/// The mass-normalised linear-chain matrix M^-1/2 K_lin M^-1/2 of a chain (units of K/M);
/// for the homogeneous row, I + fc T with T of MODEL.md §4.
Tridiagonal linear_chain_matrix(const Chain& chain);

/// Eigen solvers.
enum class EigenMethod {
    automatic, ///< dense below 2000 bodies or when every mode is asked for, sparse otherwise
    dense,     ///< Eigen's tridiagonal QR: all modes, O(Nm^2) with shapes
    sparse,    ///< Spectra shift-invert Lanczos (O(n) tridiagonal solves): the k extreme modes
};
/// Parses "auto", "dense" or "sparse"; throws std::invalid_argument otherwise.
EigenMethod parse_eigen_method(std::string_view name);
/// The name parse_eigen_method() reads.
std::string_view to_string(EigenMethod method);

/// Which end of the spectrum to compute.
enum class SpectrumEnd { lowest, highest };

/// What to compute.
struct ModalOptions {
    int count = 0;                               ///< modes wanted, 0 = all (dense only), <= Nm
    SpectrumEnd end = SpectrumEnd::lowest;       ///< lowest or highest modes
    EigenMethod method = EigenMethod::automatic; ///< dense, sparse (Spectra) or chosen by size
    bool shapes = true;                          ///< also return the mode shapes
    double tolerance = 1e-12;                    ///< relative eigenvalue tolerance (sparse), > 0
    /// Largest Nm the dense solver takes, 1 .. 1e6: it stores an Nm x Nm matrix (8 Nm^2 bytes)
    /// and costs ~Nm^3 operations (Nm = 5000: 200 MB, about a minute; 20000: 3.2 GB, hours).
    int max_dense_bodies = 5000;
};

/// Outcome of an eigen solve, as Spectra's CompInfo.
enum class ModalStatus { converged, not_converged, numerical_issue };

/// Modes, in ascending frequency order.
struct ModalResult {
    std::vector<int> mode_numbers;   ///< k, 1-based, ascending
    std::vector<double> frequencies; ///< reduced f_k = sqrt(eigenvalue_k)
    /// Paper eq (26) f_ka for the same k; NaN where the row is not the paper's uniform one
    /// (other masses, springs or contacts), which the formula does not describe.
    std::vector<double> approx;
    std::vector<double> rel_error;           ///< (f_ka - f_k) / f_k; NaN where approx is
    std::vector<std::vector<double>> shapes; ///< per mode, Nm entries, phi^T M phi = 1
    std::vector<double> residuals;           ///< per mode |A psi - lambda psi| / lambda (error)
    EigenMethod method = EigenMethod::dense; ///< solver used
    /// converged: (sparse) every residual within what the Lanczos tolerance promises,
    /// max(tolerance, tolerance (spectrum width) / lambda, 64 eps lambda_max / lambda);
    /// not_converged where Spectra did not converge or a residual is beyond that;
    /// numerical_issue as Spectra reports it
    ModalStatus status = ModalStatus::converged;
    /// Lanczos restarts (sparse: over every shift tried), 0 for dense
    long iterations = 0;
    double wall_time_s = 0.0; ///< [s]
};

/// Paper eq (26): f_ka = sqrt(1 + fc (k/Nm)^2 (4.935 - 2.935 (k/Nm)^1.81)), 1 <= k <= Nm.
double approx_frequency(int k, int Nm, double fc);

/// Paper eq (34): the first mode's amplitude at the first body, Phi_1(1) ~ pi / Nm, for the
/// mode normalised as sin(pi i / Nm) (eq 33).
double approx_first_mode_end_amplitude(int Nm);

/// Natural frequencies and mode shapes of the linear chain. The chain's clearances are ignored
/// (the linear chain has e_r = 0). Throws std::invalid_argument on bad options.
ModalResult modal_analysis(const Chain& chain, const ModalOptions& options);

/// The error of eq (26) at one (Nm, fc).
struct ApproximationError {
    int Nm = 1;         ///< bodies, >= 1
    double fc = 1.0;    ///< contact to structural stiffness ratio K_c / K, > 0
    double first = 0.0; ///< (f_1a - f_1) / f_1
    double other = 0.0; ///< the largest |(f_ka - f_k) / f_k| over k >= 2 (0 when Nm = 1)
    int other_mode = 0; ///< the k where it occurs (0 when Nm = 1)
};

/// Eq (26) against the exact frequencies over a grid of rows.
struct ApproximationGrid {
    std::vector<ApproximationError> points; ///< Nm-major order
    ApproximationError worst_first;         ///< where |first| is largest
    ApproximationError worst_other;         ///< where other is largest
    double wall_time_s = 0.0;               ///< [s]
    bool cancelled = false; ///< progress stopped it: points holds the rows done before
};

/// Largest work of approximation_grid(): the sum of Nm^3 over its rows, 1e13 (measured 1.5e9
/// a second: about 2 hours; Nm up to 2000 at 2 values of fc).
constexpr double max_grid_work = 1e13;

/// Evaluates eq (26) on every homogeneous row (Nm, fc) of the grid (every Nm >= 1, fc > 0).
/// progress reports the fraction of rows done (weighted by Nm^3, the dense solver's work);
/// answering false stops it (cancelled). Throws std::invalid_argument naming fc_values where
/// the grid's work exceeds max_grid_work.
ApproximationGrid approximation_grid(const std::vector<int>& Nm_values,
                                     const std::vector<double>& fc_values,
                                     const ProgressCallback& progress = {});

} // namespace gapchain
