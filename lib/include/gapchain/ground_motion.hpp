#pragma once
/// \file ground_motion.hpp
/// What shakes the ground: the paper's harmonic acceleration, a recorded accelerogram, or a
/// synthetic seismic motion (Kanai-Tajimi filtered white noise under an envelope).
///
/// In the reduced equations every body feels -4 pi^2 a(t) with a the ground acceleration in
/// units of a0 and t reduced time (t_phys f0). For a harmonic motion a(t) = A cos(2 pi f_r t);
/// for a record, a0 is the record's peak ground acceleration (PGA), so max |a| = 1.

#include <cstdint>
#include <memory>
#include <vector>

namespace gapchain {

/// A ground acceleration history in SI units.
struct Accelerogram {
    std::vector<double> time;         ///< [s], >= 0, strictly increasing, finite, >= 2 samples
    std::vector<double> acceleration; ///< [m/s^2], finite, one per time
};

/// Throws std::invalid_argument (naming `key`) unless the accelerogram has >= 2 samples,
/// equal lengths, finite values and strictly increasing times from 0 s on, and is not
/// identically zero.
void validate(const Accelerogram& record, const char* key = "excitation.file");

/// Peak ground acceleration max |a| [m/s^2].
double peak_ground_acceleration(const Accelerogram& record);

/// A synthetic seismic motion: white noise through the Kanai-Tajimi soil filter
/// (Kanai 1957, Tajimi 1960), x'' + 2 zeta_g w_g x' + w_g^2 x = -w(t), a = 2 zeta_g w_g x' +
/// w_g^2 x, multiplied by the Jennings-Housner-Tsai (1968) envelope: (t / rise)^2 while
/// t < rise, 1 for the next `hold` seconds, then exp(-decay (t - rise - hold)).
struct KanaiTajimi {
    double ground_frequency = 2.5;  ///< f_g = w_g / 2 pi [Hz], 0.01 .. 100 (firm soil ~2.5)
    double ground_damping = 0.6;    ///< zeta_g, 0.01 .. 5 (firm soil ~0.6)
    double duration = 20.0;         ///< record length [s], (0, 1e5]
    double sample_interval = 0.005; ///< [s], (0, 1], at most duration / 16 and 1/(8 f_g)
    double rise = 2.0;              ///< envelope ramp [s], [0, 1e5]
    double hold = 8.0;              ///< envelope plateau [s], [0, 1e5]
    double decay = 0.5;             ///< envelope decay rate after the plateau [1/s], [0, 1e3]
    std::uint64_t seed = 1;         ///< noise seed; equal seeds give equal records everywhere
};

/// Throws std::invalid_argument naming the first field (excitation.*) outside its range.
void validate(const KanaiTajimi& p);

/// The envelope of p at time t [s], in [0, 1].
double envelope(const KanaiTajimi& p, double t);

/// The Kanai-Tajimi spectral shape at frequency f [Hz] relative to the white-noise level:
/// (w_g^4 + 4 zeta_g^2 w_g^2 w^2) / ((w_g^2 - w^2)^2 + 4 zeta_g^2 w_g^2 w^2), w = 2 pi f.
double kanai_tajimi_shape(const KanaiTajimi& p, double f);

/// A seeded realisation of p scaled to peak ground acceleration `pga` [m/s^2] (> 0).
/// Samples at k * sample_interval, k = 0 .. floor(duration / sample_interval). The filter
/// starts in its stationary state (a warm-up of 10 / (zeta_g w_g) before t = 0), so the
/// spectral shape holds from the first sample.
Accelerogram kanai_tajimi_accelerogram(const KanaiTajimi& p, double pga);

/// The ground acceleration of a run in reduced units: what Dynamics::ground() evaluates.
/// Cheap to copy (a record's interpolant is shared, immutable) and safe to share between threads.
class GroundMotion {
public:
    /// A(cos 2 pi f_r t): f_r in (0, 1e4] reduced, amplitude in [0, 1e6] (multiple of a0).
    static GroundMotion harmonic(double f_r, double amplitude = 1.0);
    /// A record in reduced units: times t (reduced, strictly increasing, >= 2 samples) and
    /// accelerations a (units of a0), interpolated by a natural cubic spline (GSL) between
    /// samples and 0 outside [t_front, t_back] (the ground at rest before and after).
    static GroundMotion record(std::vector<double> time, std::vector<double> acceleration);
    /// A record in SI units seen by a row of natural frequency f0 [Hz] (> 0) with a0 [m/s^2]
    /// (> 0; the record's PGA makes max |a| = 1): t = f0 t_phys, a = acceleration / a0.
    static GroundMotion from_accelerogram(const Accelerogram& accelerogram, double f0, double a0);

    /// Whether the motion is harmonic (has a forcing period for sections and steady states).
    [[nodiscard]] bool is_harmonic() const { return !m_record; }
    /// Reduced forcing frequency of a harmonic motion (1 for a record: the loop's time unit).
    [[nodiscard]] double f_r() const { return m_f_r; }
    /// Amplitude A of a harmonic motion (multiple of a0); 1 for a record.
    [[nodiscard]] double amplitude() const { return m_amplitude; }
    /// The time loop's period: 1 / f_r (harmonic) or one natural period, 1 (record).
    [[nodiscard]] double period() const { return 1.0 / m_f_r; }
    /// Highest frequency the steps must resolve [1 / reduced time]: f_r (harmonic) or a
    /// quarter of the sampling rate (record).
    [[nodiscard]] double resolved_frequency() const { return m_resolved_frequency; }
    /// Reduced time at which the record ends (infinite for a harmonic motion).
    [[nodiscard]] double end_time() const;

    /// Ground acceleration a(t) in units of a0 at reduced time t.
    [[nodiscard]] double acceleration(double t) const;
    /// Its time derivative da/dt.
    [[nodiscard]] double acceleration_rate(double t) const;

    struct Interpolant; ///< the record's spline (defined in the source file)

private:
    GroundMotion() = default;
    double m_f_r = 1.0;
    double m_amplitude = 1.0;
    double m_resolved_frequency = 1.0;
    std::shared_ptr<const Interpolant> m_record;
};

} // namespace gapchain
