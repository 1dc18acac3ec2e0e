// gapchain-sweep: a parametric study on all cores; results stream to a CSV that survives
// kill -9 and resumes where it stopped.
#include "common/cli.hpp"

#include "gapchain/report.hpp"
#include "gapchain/sweep.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
    using namespace gapchain;
    CLI::App app{"Run a study (data/studies/*.json): every point's F_m (and what the study keeps), "
                 "in parallel, streamed to a CSV. Rerunning the same command after an interruption "
                 "continues where it stopped.",
                 "gapchain-sweep"};
    std::string study_path, out = "results.csv", shard_text = "0/1";
    int threads = 0;
    long subset = 0;
    unsigned long long seed = 1;
    app.add_option("study", study_path, "Study file (JSON)")->required();
    app.add_option("--out", out, "Results CSV (a .json sidecar is written next to it)")
        ->capture_default_str();
    app.add_option("--threads", threads, "OpenMP threads (0: all cores)")->capture_default_str();
    app.add_option("--shard", shard_text, "Run shard i of n (index % n == i), e.g. for job arrays")
        ->capture_default_str();
    app.add_option(
           "--subset", subset,
           "Run only K points, one drawn at random in each of K equal strata of the index range")
        ->capture_default_str();
    app.add_option("--seed", seed, "Seed of --subset")->capture_default_str();
    return cli::run(app, argc, argv, [&] {
        const Study study = load_study(study_path);
        const long total = point_count(study);
        SweepSelection sel;
        sel.threads = threads;
        if (std::sscanf(shard_text.c_str(), "%d/%d", &sel.shard, &sel.shards) != 2 ||
            sel.shards < 1 || sel.shard < 0 || sel.shard >= sel.shards)
            throw std::invalid_argument("--shard: must be i/n with 0 <= i < n, got \"" +
                                        shard_text + "\"");
        if (subset < 0 || subset > total)
            throw std::invalid_argument("--subset: must be in [0, " + std::to_string(total) +
                                        "], got " + std::to_string(subset));
        for (long k = 0; k < subset; ++k) {
            const long lo = k * total / subset, hi = (k + 1) * total / subset;
            std::uint64_t h = seed * 0x9e3779b97f4a7c15ULL +
                              static_cast<std::uint64_t>(k) * 0xbf58476d1ce4e5b9ULL;
            h ^= h >> 31;
            sel.subset.push_back(lo + static_cast<long>(h % static_cast<std::uint64_t>(hi - lo)));
        }
        ResultLog log(out, sweep_csv_header(study), total);
        sel.done = log.done();
        if (!std::filesystem::exists(out + ".json"))
            write_file_atomically(out + ".json", study_json(study));
        const std::vector<long> pending = pending_points(study, sel);
        std::fprintf(stderr,
                     "gapchain-sweep: %ld points in the study, %ld already in %s, %zu to run\n",
                     total, log.rows_found(), out.c_str(), pending.size());
        double seconds_periodic = 0, seconds_other = 0;
        long periodic = 0, other = 0;
        cli::Progress progress("gapchain-sweep", true, true);
        const auto start = std::chrono::steady_clock::now();
        run_sweep(
            study, sel,
            [&](const SweepPointResult& r) {
                log.append(sweep_csv_row(study, r));
                if (r.simulation.steady_state_period) {
                    ++periodic;
                    seconds_periodic += r.simulation.wall_time_s;
                } else {
                    ++other;
                    seconds_other += r.simulation.wall_time_s;
                }
            },
            progress.callback());
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const long ran = periodic + other;
        std::printf("gapchain-sweep: %ld points in %.2f s wall (%.3g points/s)\n", ran, wall,
                    wall > 0 ? ran / wall : 0.0);
        if (ran > 0) {
            std::printf("  periodic (stopped at steady state): %ld points, mean %.4f s each\n",
                        periodic, periodic ? seconds_periodic / periodic : 0.0);
            std::printf("  not periodic (full length):         %ld points, mean %.4f s each\n",
                        other, other ? seconds_other / other : 0.0);
            if (subset > 0)
                std::printf("  estimate for all %ld points at this rate: %.0f s (%.1f h)\n", total,
                            wall * total / ran, wall * total / ran / 3600.0);
        }
        std::printf("results in %s (sidecar %s.json)\n", out.c_str(), out.c_str());
    });
}
