#pragma once
// Input checks shared by the library boundary: each throws std::invalid_argument with a
// one-line message naming the key, the accepted range and the bad value.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace gapchain::detail {

enum class Bound { closed, open_low };

inline std::string format_number(double x) {
    std::ostringstream s;
    s.precision(10);
    s << x;
    // Ten digits unless they lose the value (f_r = 10000.000000000002 was refused as "got
    // 10000"); then the fewest that keep it, as the user likely wrote it.
    for (int digits = 15;
         digits <= 17 && std::isfinite(x) && std::strtod(s.str().c_str(), nullptr) != x; ++digits) {
        s.str("");
        s.precision(digits);
        s << x;
    }
    return s.str();
}

inline void require_range(const std::string& key, double value, double lo, double hi,
                          Bound bound = Bound::closed) {
    const bool low_ok = bound == Bound::open_low ? value > lo : value >= lo;
    if (!std::isfinite(value) || !low_ok || value > hi) {
        const char* open = bound == Bound::open_low ? "(" : "[";
        throw std::invalid_argument(key + ": must be a finite number in " + open +
                                    format_number(lo) + ", " + format_number(hi) + "], got " +
                                    format_number(value));
    }
}

inline void require_range(const std::string& key, int value, int lo, int hi) {
    if (value < lo || value > hi)
        throw std::invalid_argument(key + ": must be an integer in [" + std::to_string(lo) + ", " +
                                    std::to_string(hi) + "], got " + std::to_string(value));
}

/// Refuses work (body-steps: bodies x steps) above run.max_work, in the one wording every
/// refusal uses: "run.max_work: <what> W body-steps (<breakdown>), about H h at 1e7
/// body-steps/s; above run.max_work = M: <remedy>". Returns if work <= max_work.
inline void require_work(double work, double max_work, const std::string& what,
                         const std::string& breakdown, const std::string& remedy) {
    if (work <= max_work) return;
    std::ostringstream hours;
    hours.precision(3);
    hours << work / 1e7 / 3600.0;
    throw std::invalid_argument(
        "run.max_work: " + what + " " + format_number(std::ceil(work)) + " body-steps (" +
        breakdown + "), about " + hours.str() +
        " h at 1e7 body-steps/s; above run.max_work = " + format_number(max_work) + ": " + remedy);
}

/// Refuses a list of values (an axis of a study or a map) that holds one twice: the same point
/// ran twice.
inline void require_distinct(const std::string& key, std::vector<double> values) {
    std::sort(values.begin(), values.end());
    if (const auto twice = std::adjacent_find(values.begin(), values.end()); twice != values.end())
        throw std::invalid_argument(key + ": the value " + format_number(*twice) +
                                    " is given twice; give each value once");
}

/// The same for a count held in a long (samples, starts).
inline void require_count(const std::string& key, long value, long lo, long hi) {
    if (value < lo || value > hi)
        throw std::invalid_argument(key + ": must be an integer in [" + std::to_string(lo) + ", " +
                                    std::to_string(hi) + "], got " + std::to_string(value));
}

/// A run of transient + recorded periods (bifurcation values, classification) is a run of
/// run.periods, at most 1e9: refused under the name of the option the user gave.
inline void require_run_length(long transient_periods, long record_periods) {
    const double total =
        static_cast<double>(transient_periods) + static_cast<double>(record_periods);
    if (total > 1e9)
        throw std::invalid_argument("record_periods: transient + recorded periods must be at most "
                                    "1e9, got " +
                                    format_number(total));
}

inline void require_length(const std::string& key, std::size_t got, std::size_t expected) {
    if (got != expected)
        throw std::invalid_argument(key + ": must have " + std::to_string(expected) +
                                    " entries, got " + std::to_string(got));
}

/// A line's end refused: e again, prefixed with the option that set the end ("from: ...") where
/// it refuses the row itself (its message names a model. or excitation. key; "excitation.f_r:
/// one forcing period would take 1.7e302 steps" did not say it was --from's 1e-300), else e
/// unchanged (the options' own rules, run.max_work, read alike at every value). option may be
/// null: a value inside the line.
[[noreturn]] inline void rethrow_naming_end(const std::invalid_argument& e, const char* option) {
    const std::string message = e.what();
    if (!option || (message.rfind("excitation.", 0) != 0 && message.rfind("model.", 0) != 0))
        throw e;
    throw std::invalid_argument(std::string(option) + ": " + message);
}

} // namespace gapchain::detail
