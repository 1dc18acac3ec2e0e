#pragma once
// The one parallel loop of the library: bifurcation diagrams, regime maps and sweeps run their
// independent points through it, so that they cancel, fail and report progress the same way.

#include "gapchain/run.hpp"

#include <omp.h>

#include <atomic>
#include <chrono>
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

/// A parallel driver's progress, shared by its items: finished() after each item reports the
/// fraction done (parallel_for's finish); item_callback() goes into an item's own long run, so
/// that a cancel (SIGINT through the tools' progress, Ctrl-C in Python) also stops a run that is
/// still going. Calls to progress are serialised; an item asks it at most every 0.2 s (other
/// calls only read the cancel flag, so short items cost nothing); once it answered false,
/// every later call answers false too.
class SharedProgress {
public:
    /// progress may be empty (never cancels); total > 0 items.
    SharedProgress(const ProgressCallback& progress, long total)
        : m_progress(progress), m_total(static_cast<double>(total)) {}
    /// One more item finished: reports done / total; false once cancelled.
    bool finished() {
        const std::lock_guard<std::mutex> guard(m_lock);
        return ask(static_cast<double>(++m_done) / m_total);
    }
    /// Whether the progress callback has cancelled the loop.
    [[nodiscard]] bool cancelled() const { return m_cancelled.load(std::memory_order_relaxed); }
    /// For one item's run: true to go on.
    [[nodiscard]] ProgressCallback item_callback() {
        if (!m_progress) return {};
        return [this](double) {
            if (cancelled()) return false;
            const auto now = std::chrono::steady_clock::now();
            const std::unique_lock<std::mutex> guard(m_lock, std::try_to_lock);
            if (!guard.owns_lock() || now - m_last_ask < std::chrono::milliseconds(200))
                return !cancelled();
            m_last_ask = now;
            return ask(static_cast<double>(m_done) / m_total);
        };
    }

private:
    // Under m_lock.
    bool ask(double fraction) {
        if (cancelled()) return false;
        if (m_progress && !m_progress(fraction)) m_cancelled.store(true, std::memory_order_relaxed);
        return !cancelled();
    }
    const ProgressCallback& m_progress;
    double m_total;
    long m_done = 0;
    std::chrono::steady_clock::time_point m_last_ask{};
    std::atomic<bool> m_cancelled{false};
    std::mutex m_lock;
};

/// The thread count a driver runs with: `requested` if positive, else all of OpenMP's.
inline int thread_count(int requested) {
    return requested > 0 ? requested : omp_get_max_threads();
}

} // namespace gapchain::detail
