#pragma once
/// \file transient_lifetime.hpp
/// How long the transients before an attractor last: the survival statistics of transient
/// lengths over many starts (a median that counts runs still going, the exponential tail's
/// lifetime and a test of its constant rate), as escape from a chaotic saddle gives them.

#include <limits>
#include <string_view>
#include <vector>

namespace gapchain {

/// Whether the transients end at a constant rate beyond TransientLifetime::from_period.
enum class ConstantRate {
    untested,   ///< fewer than 5 endings in either half of the lengths beyond it
    consistent, ///< the two halves' rates agree within 3 standard errors of their log ratio
    rejected    ///< they do not: no single exponential escape
};

/// "untested", "consistent" or "rejected".
std::string_view to_string(ConstantRate r);

/// How long the transients before the periodic attractors last, over the random starts that
/// reach one. Escape from a saddle (a chaotic saddle, or an unstable orbit on a basin boundary)
/// is memoryless: beyond some length the transients end at a constant rate 1 / lifetime, and
/// the share still in the transient after n periods falls as exp(-n / lifetime). Measured
/// beyond from_period, the median length, where the start-up's own relaxation is over:
/// lifetime = (periods spent beyond it) / (transients ending beyond it), the maximum-likelihood
/// estimate for an exponential tail, which counts a transient still going when its run ended
/// (right-censored) as lasting at least that long; consistent, biased by about lifetime / n for
/// n endings. Lengths are whole periods (a cycle entry), which adds about half a period.
struct TransientLifetime {
    /// The median transient length (Kaplan-Meier, so censored ones count as lasting at least
    /// their censoring time) [forcing periods]; NaN if the survival stays above 1/2 within the
    /// observed lengths, or no start reached a periodic attractor.
    double from_period = std::numeric_limits<double>::quiet_NaN();
    /// The lifetime beyond from_period [forcing periods]; NaN with fewer than 10 endings beyond.
    double lifetime = std::numeric_limits<double>::quiet_NaN();
    /// lifetime / sqrt(ended) [forcing periods]
    double lifetime_error = std::numeric_limits<double>::quiet_NaN();
    long ended = 0;    ///< transients that end beyond from_period
    long censored = 0; ///< transients still going when their runs ended (all of them)
    /// The ending rate of the later half of the endings beyond from_period over that of the
    /// earlier half (1 for a constant rate), and its standard error; NaN when untested.
    double rate_ratio = std::numeric_limits<double>::quiet_NaN();
    double rate_ratio_error = std::numeric_limits<double>::quiet_NaN(); ///< of rate_ratio
    /// The two-bin test of a constant rate. It is weak against mixtures of similar lifetimes
    /// (two lifetimes 20 and 80 in equal shares, 400 starts: rejected about 1 time in 3), so
    /// consistent means "no evidence against", not proof of a single saddle.
    ConstantRate constant_rate = ConstantRate::untested;
    /// How long until only `share` (in (0, 1/2)) of the starts are still in their transient
    /// [forcing periods]: from_period + lifetime ln(1 / (2 share)), the exponential tail
    /// extended; what a run must discard (run.transient_periods) to record the attractor's F_m
    /// from all but that share of starts. NaN unless the rate is consistent with a constant
    /// one. Throws std::invalid_argument for a share outside (0, 1/2).
    [[nodiscard]] double periods_until(double share) const;
};

/// The TransientLifetime of transient lengths [forcing periods]: ended lists the lengths of
/// those that ended, censored the lengths so far of those still going when their runs ended
/// (each >= 0). Throws std::invalid_argument on a negative length.
TransientLifetime transient_lifetime(std::vector<long> ended, std::vector<long> censored);

} // namespace gapchain
