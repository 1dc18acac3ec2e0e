#include "gapchain/sweep.hpp"

#include "detail/check.hpp"
#include "detail/random.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

std::string full_key(const std::string& key) {
    if (key == "Nm" || key == "fc" || key == "eps" || key == "e_r") return "model." + key;
    if (key == "f_r") return "excitation." + key;
    return key;
}

std::string assignment(const std::string& key, double value) {
    char buffer[64];
    if (value == std::floor(value) && std::abs(value) < 1e15)
        std::snprintf(buffer, sizeof buffer, "%.0f", value);
    else
        std::snprintf(buffer, sizeof buffer, "%.17g", value);
    return full_key(key) + "=" + buffer;
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

Scene point_scene(const Study& s, long index) {
    const std::vector<double> v = point_values(s, index);
    std::vector<std::string> sets;
    for (std::size_t a = 0; a < s.axes.size(); ++a)
        sets.push_back(assignment(s.axes[a].key, v[a]));
    return parse_scene(s.scene_json, sets, s.source + " point " + std::to_string(index));
}

std::vector<long> pending_points(const Study& s, const SweepSelection& sel) {
    detail::require_range("--shard", sel.shard, 0, std::max(0, sel.shards - 1));
    detail::require_range("--shard count", sel.shards, 1, 1'000'000);
    const long n = point_count(s);
    std::vector<long> candidates;
    if (sel.subset.empty()) {
        candidates.resize(n);
        for (long i = 0; i < n; ++i)
            candidates[i] = i;
    } else {
        candidates = sel.subset;
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    }
    std::vector<long> pending;
    for (long i : candidates) {
        if (i < 0 || i >= n) throw std::invalid_argument("subset index outside the study");
        if (i % sel.shards != sel.shard) continue;
        if (static_cast<std::size_t>(i) < sel.done.size() && sel.done[i]) continue;
        pending.push_back(i);
    }
    return pending;
}

void run_sweep(const Study& s, const SweepSelection& sel,
               const std::function<void(const SweepPointResult&)>& sink,
               const ProgressCallback& progress) {
    detail::require_range("--threads", sel.threads, 0, 4096);
    const std::vector<long> pending = pending_points(s, sel);
    const int threads = sel.threads > 0 ? sel.threads : omp_get_max_threads();
    const long total = static_cast<long>(pending.size());
    long finished = 0;
    bool stop = false;
    std::string failure;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (long k = 0; k < total; ++k) {
        bool skip = false;
#pragma omp atomic read
        skip = stop;
        if (skip) continue;
        try {
            SweepPointResult r;
            r.index = pending[k];
            r.values = point_values(s, r.index);
            const Scene scene = point_scene(s, r.index);
            r.parameters = scene.reduced;
            r.simulation = simulate(scene.dynamics(), scene.run, scene.initial);
            if (scene.physical) r.F_m_newton = force_in_newtons(r.simulation.F_m, *scene.physical);
            if (s.keep.regime) {
                if (!scene.uniform())
                    throw std::invalid_argument("keep: \"regime\" needs the paper's uniform row; "
                                                "drop it or the model arrays and scatter");
                ClassifyOptions co;
                co.scheme = scene.run.scheme;
                co.tolerance = scene.run.tolerance;
                r.regime = classify(scene.reduced, co);
            }
#pragma omp critical(gapchain_sweep_sink)
            {
                sink(r);
                ++finished;
                if (progress && !progress(static_cast<double>(finished) / total)) {
#pragma omp atomic write
                    stop = true;
                }
            }
        } catch (const std::exception& e) {
#pragma omp critical(gapchain_sweep_failure)
            failure = e.what();
#pragma omp atomic write
            stop = true;
        }
    }
    if (!failure.empty()) throw std::runtime_error(failure);
}

} // namespace gapchain
