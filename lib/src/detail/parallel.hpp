#pragma once
// The one parallel loop of the library: bifurcation diagrams, regime maps and sweeps run their
// independent points through it, so that they cancel, fail and report progress the same way.

#include <omp.h>

#include <atomic>
#include <exception>
#include <mutex>

namespace gapchain::detail {

/// How a parallel loop ended.
enum class LoopEnd {
    completed, ///< every index ran
    cancelled, ///< the finish callback asked to stop; the indices not started never ran
};

/// Runs body(k) for every k in [0, count) on `threads` OpenMP threads (>= 1), one index at a
/// time (dynamic schedule), each writing its own result slot so that results do not depend on
/// the thread count or the completion order. After each index, finish(k) runs under a lock,
/// one call at a time in completion order; returning false cancels the loop: no index starts
/// after that, so it stops within one index per thread. The first exception thrown by body or
/// finish also stops the loop and is rethrown after it as itself (a std::invalid_argument stays
/// one, so bad input found inside a worker is still reported as bad input).
template <class Body, class Finish>
LoopEnd parallel_for(long count, int threads, Body&& body, Finish&& finish) {
    std::atomic<bool> stop{false};
    bool cancelled = false;
    std::exception_ptr failure;
    std::mutex lock;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (long k = 0; k < count; ++k) {
        if (stop.load(std::memory_order_relaxed)) continue;
        try {
            body(k);
            const std::lock_guard<std::mutex> guard(lock);
            if (!stop.load(std::memory_order_relaxed) && !finish(k)) {
                cancelled = true;
                stop.store(true, std::memory_order_relaxed);
            }
        } catch (...) {
            const std::lock_guard<std::mutex> guard(lock);
            if (!failure) failure = std::current_exception();
            stop.store(true, std::memory_order_relaxed);
        }
    }
    if (failure) std::rethrow_exception(failure);
    return cancelled ? LoopEnd::cancelled : LoopEnd::completed;
}

/// The thread count a driver runs with: `requested` if positive, else all of OpenMP's.
inline int thread_count(int requested) {
    return requested > 0 ? requested : omp_get_max_threads();
}

} // namespace gapchain::detail
