#include "gapchain/sweep.hpp"

#include "gapchain/design_value.hpp"

#include "detail/check.hpp"
#include "detail/parallel.hpp"
#include "detail/random.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <stdexcept>

namespace gapchain {

namespace {

using detail::hash3;

/// Position of `index` in axis `axis`'s Latin-hypercube permutation of [0, n) (Fisher-Yates
/// driven by the hash, so it is the same everywhere).
long latin_stratum(const Study& s, long index, std::size_t axis) {
    const long n = s.samples;
    std::vector<long> perm(n);
    for (long i = 0; i < n; ++i)
        perm[i] = i;
    for (long i = n - 1; i > 0; --i) {
        const long j =
            static_cast<long>(hash3(s.seed, axis, i) % static_cast<std::uint64_t>(i + 1));
        std::swap(perm[i], perm[j]);
    }
    return perm[index];
}

} // namespace

long point_count(const Study& s) {
    if (s.sampling != Sampling::grid) return s.samples;
    long n = 1;
    for (const auto& a : s.axes)
        n *= static_cast<long>(a.values.size());
    return n;
}

std::vector<double> point_values(const Study& s, long index) {
    if (index < 0 || index >= point_count(s))
        throw std::invalid_argument("point index " + std::to_string(index) + " outside [0, " +
                                    std::to_string(point_count(s)) + ")");
    std::vector<double> v(s.axes.size());
    switch (s.sampling) {
    case Sampling::grid: {
        long rest = index;
        for (std::size_t a = s.axes.size(); a-- > 0;) {
            const auto size = static_cast<long>(s.axes[a].values.size());
            v[a] = s.axes[a].values[rest % size];
            rest /= size;
        }
        break;
    }
    case Sampling::random:
        for (std::size_t a = 0; a < s.axes.size(); ++a)
            v[a] = s.axes[a].values[hash3(s.seed, a + 1, index) % s.axes[a].values.size()];
        break;
    case Sampling::latin_hypercube:
        for (std::size_t a = 0; a < s.axes.size(); ++a) {
            const auto size = s.axes[a].values.size();
            const long stratum = latin_stratum(s, index, a);
            v[a] = s.axes[a].values[static_cast<std::size_t>(stratum) * size / s.samples];
        }
        break;
    }
    return v;
}

std::vector<long> stratified_subset(long total, long count, std::uint64_t seed) {
    if (total < 0 || count < 0 || count > total)
        throw std::invalid_argument("subset: must be in [0, " + std::to_string(total) + "], got " +
                                    std::to_string(count));
    std::vector<long> subset;
    for (long k = 0; k < count; ++k) {
        const long lo = k * total / count, hi = (k + 1) * total / count;
        // A light multiplicative hash: kept as it is so that published subsets stay the same.
        std::uint64_t h =
            seed * 0x9e3779b97f4a7c15ULL + static_cast<std::uint64_t>(k) * 0xbf58476d1ce4e5b9ULL;
        h ^= h >> 31;
        subset.push_back(lo + static_cast<long>(h % static_cast<std::uint64_t>(hi - lo)));
    }
    return subset;
}

std::vector<long> pending_points(const Study& s, const SweepSelection& sel) {
    detail::require_range("shard", sel.shard, 0, std::max(0, sel.shards - 1));
    detail::require_range("shard_count", sel.shards, 1, 1'000'000);
    const long n = point_count(s);
    std::vector<long> pending;
    const auto consider = [&](long i) {
        if (i < 0 || i >= n) throw std::invalid_argument("subset index outside the study");
        if (i % sel.shards != sel.shard) return;
        if (static_cast<std::size_t>(i) < sel.done.size() && sel.done[i]) return;
        pending.push_back(i);
    };
    if (sel.subset.empty()) {
        // No list of all n indices first: 8 bytes a point, 0.8 GB for the largest study.
        for (long i = 0; i < n; ++i)
            consider(i);
        return pending;
    }
    std::vector<long> candidates = sel.subset;
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    for (long i : candidates)
        consider(i);
    return pending;
}

namespace {

/// A regime (or an attractor search) needs the five reduced numbers and a forcing period.
void require_classifiable(const SweepPointInput& in, const std::string& what) {
    if (!in.harmonic)
        throw std::invalid_argument(what + " needs harmonic forcing (a forcing period); "
                                           "drop it for record and Kanai-Tajimi scenes");
    if (!in.uniform)
        throw std::invalid_argument(what + " needs the paper's uniform row with the linear "
                                           "contact law; drop it, or the model arrays, scatter "
                                           "and contact_law");
}

SweepPointResult run_point(const Study& s, const SweepPointFactory& make_point, long index,
                           const ProgressCallback& keep_going) {
    SweepPointResult r;
    r.index = index;
    r.values = point_values(s, index);
    const SweepPointInput in = make_point(index);
    r.parameters = in.reduced;
    r.harmonic = in.harmonic;
    SimulationHooks hooks;
    hooks.progress = keep_going;
    r.simulation = simulate(in.dynamics, in.run, in.initial, hooks);
    r.multistable = r.simulation.multistable;
    if (in.physical) {
        r.F_m_newton = force_in_newtons(r.simulation.F_m, *in.physical);
        if (has_error_estimate(r.simulation))
            r.F_m_error_newton = force_in_newtons(r.simulation.F_m_error, *in.physical);
    }
    if (s.keep.regime) {
        require_classifiable(in, "keep: \"regime\"");
        ClassifyOptions co;
        co.scheme = in.run.scheme;
        co.tolerance = in.run.tolerance;
        // Its runs (and a twin's, on an unsettled label) can be long: a cancel stops them too;
        // a point stopped so is not written (run_sweep()).
        r.regime = classify(in.reduced, co, keep_going);
    }
    if (s.attractor_starts > 0) {
        require_classifiable(in, "attractors");
        AttractorOptions ao;
        ao.samples = s.attractor_starts;
        ao.seed = static_cast<std::uint64_t>(index);
        ao.run = in.run;
        ao.threads = 1; // the sweep is already parallel over points
        const DesignValue design = design_value(in.reduced, ao, r.simulation, keep_going);
        r.F_m_max = design.F_m_max;
        r.F_m_max_error = design.F_m_max_error;
        r.multistable = multistable(r.simulation, design);
        r.attractors_found = design.search.attractor_count();
        r.attractors_unsettled = design.search.unsettled;
        if (in.physical) {
            r.F_m_max_newton = force_in_newtons(design.F_m_max, *in.physical);
            r.F_m_max_error_newton = force_in_newtons(design.F_m_max_error, *in.physical);
        }
    }
    return r;
}

} // namespace

SweepEnd run_sweep(const Study& s, const SweepSelection& sel, const SweepPointFactory& make_point,
                   const std::function<void(const SweepPointResult&)>& sink,
                   const ProgressCallback& progress) {
    detail::require_range("threads", sel.threads, 0, 4096);
    const std::vector<long> pending = pending_points(s, sel);
    const long total = static_cast<long>(pending.size());
    // A finished point waits here only until the sink has taken it (right after, on its own
    // thread): one slot per point in flight. A slot for every point cost 630 bytes a point up
    // front, 6.3 GB for a study of 1e7 (the documented limit is 1e8).
    std::map<long, SweepPointResult> finished;
    std::mutex finished_lock;
    detail::SharedProgress shared(progress, std::max(total, 1L));
    const auto end = detail::parallel_for(
        total, detail::thread_count(sel.threads),
        [&](long k) {
            SweepPointResult r = run_point(s, make_point, pending[k], shared.item_callback());
            const std::lock_guard<std::mutex> guard(finished_lock);
            finished.emplace(k, std::move(r));
        },
        [&](long k) {
            std::optional<SweepPointResult> r;
            {
                const std::lock_guard<std::mutex> guard(finished_lock);
                const auto it = finished.find(k);
                r = std::move(it->second);
                finished.erase(it);
            }
            // A point stopped by the cancel is not done: it is not written (a resume runs it).
            if (shared.cancelled()) return false;
            sink(*r);
            return shared.finished();
        });
    return end == detail::LoopEnd::cancelled ? SweepEnd::cancelled : SweepEnd::completed;
}

} // namespace gapchain
