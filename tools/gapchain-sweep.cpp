// gapchain-sweep: a parametric study on all cores; results stream to a CSV that survives
// kill -9 and resumes where it stopped.
#include "common/cli.hpp"

#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"
#include "gapchain/study.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <regex>

#ifdef GAPCHAIN_WITH_MPI
#include <mpi.h>
#endif

namespace {

// Across MPI ranks: rank r runs shard r of n, and rank 0 alone owns the results file. Other
// ranks send each finished row to rank 0 (tag row) and a last empty message when they are done
// (tag done); rank 0 appends rows as they come, between its own points and after them.
// Without MPI (or with one rank) this is a single process and every call here is trivial.
class Ranks {
public:
    Ranks(int& argc, char**& argv) {
#ifdef GAPCHAIN_WITH_MPI
        int provided = 0;
        MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
        MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
        MPI_Comm_size(MPI_COMM_WORLD, &m_size);
#else
        (void)argc, (void)argv;
#endif
    }
    ~Ranks() {
#ifdef GAPCHAIN_WITH_MPI
        MPI_Finalize();
#endif
    }
    [[nodiscard]] int rank() const {
        return m_rank;
    }
    [[nodiscard]] int size() const {
        return m_size;
    }

    // Rank 0's done flags to every rank.
    void share_done(std::vector<char>& done) const {
#ifdef GAPCHAIN_WITH_MPI
        if (m_size > 1)
            MPI_Bcast(done.data(), static_cast<int>(done.size()), MPI_CHAR, 0, MPI_COMM_WORLD);
#else
        (void)done;
#endif
    }
    void send_row(const std::string& row) const {
#ifdef GAPCHAIN_WITH_MPI
        MPI_Send(row.data(), static_cast<int>(row.size()), MPI_CHAR, 0, k_row, MPI_COMM_WORLD);
#else
        (void)row;
#endif
    }
    void send_done() const {
#ifdef GAPCHAIN_WITH_MPI
        MPI_Send(nullptr, 0, MPI_CHAR, 0, k_done, MPI_COMM_WORLD);
#endif
    }
    // Rank 0: hands every row received so far to append; with wait, until all ranks are done.
    template <typename Append>
    long collect(Append append, bool wait) {
        long received = 0;
#ifdef GAPCHAIN_WITH_MPI
        while (m_finished < m_size - 1) {
            int flag = 0;
            MPI_Status status;
            if (wait) {
                MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
                flag = 1;
            } else {
                MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
            }
            if (!flag) break;
            int count = 0;
            MPI_Get_count(&status, MPI_CHAR, &count);
            std::string row(static_cast<std::size_t>(count), '\0');
            MPI_Recv(row.data(), count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            if (status.MPI_TAG == k_done) {
                ++m_finished;
            } else {
                append(row);
                ++received;
            }
        }
#else
        (void)append, (void)wait;
#endif
        return received;
    }

private:
    static constexpr int k_row = 1;
    static constexpr int k_done = 2;
    int m_rank = 0;
    int m_size = 1;
    int m_finished = 0;
};

// The command line of a sweep.
struct SweepArguments {
    std::string study_path;
    std::string out = "results.csv";
    std::string shard_text = "0/1";
    int threads = 0;
    long subset = 0;
    unsigned long long seed = 1;
};

void add_arguments(CLI::App& app, SweepArguments& a) {
    app.add_option("study", a.study_path, "Study file (JSON)")->required();
    app.add_option("--out", a.out, "Results CSV (a .json sidecar is written next to it)")
        ->capture_default_str();
    app.add_option("--threads", a.threads, "OpenMP threads (0: all cores)")
        ->check(gapchain::cli::range(0, 4096))
        ->capture_default_str();
    app.add_option("--shard", a.shard_text,
                   "Run shard i of n (index % n == i, 0 <= i < n <= 1000000), e.g. for job arrays")
        ->capture_default_str();
    auto* subset = app.add_option("--subset", a.subset,
                                  "Run only K points, one drawn at random in each of K equal "
                                  "strata of the index range")
                       ->check(gapchain::cli::range(0L, 1'000'000'000L))
                       ->capture_default_str();
    // Without --subset nothing is drawn: a --seed alone was silently ignored.
    app.add_option("--seed", a.seed, "Seed of --subset (a non-negative integer)")
        ->check(gapchain::cli::range(0ULL, 4'294'967'295ULL))
        ->needs(subset)
        ->capture_default_str();
}

// "i/n" with 0 <= i < n <= 1e6, nothing else.
void parse_shard(const std::string& text, gapchain::SweepSelection& sel) {
    // No leading zeros (README): 0/02 was read as 0/2.
    static const std::regex shard(R"((0|[1-9][0-9]{0,6})/([1-9][0-9]{0,6}))");
    std::smatch m;
    if (std::regex_match(text, m, shard)) {
        sel.shard = std::stoi(m[1].str());
        sel.shards = std::stoi(m[2].str());
        if (sel.shards >= 1 && sel.shards <= 1'000'000 && sel.shard < sel.shards) return;
    }
    throw std::invalid_argument("--shard: must be i/n with 0 <= i < n <= 1000000, got \"" + text +
                                "\"");
}

gapchain::SweepSelection selection(const SweepArguments& a, const gapchain::Study& study,
                                   const Ranks& ranks) {
    gapchain::SweepSelection sel;
    sel.threads = a.threads;
    parse_shard(a.shard_text, sel);
    const long total = gapchain::point_count(study);
    if (a.subset > total)
        throw std::invalid_argument("--subset: must be in [0, " + std::to_string(total) +
                                    "], got " + std::to_string(a.subset));
    sel.subset = gapchain::stratified_subset(total, a.subset, a.seed);
    if (ranks.size() > 1) {
        if (sel.shards != 1)
            throw std::invalid_argument(
                "--shard: not with several MPI ranks (each rank is a shard), got \"" +
                a.shard_text + "\"");
        sel.shard = ranks.rank();
        sel.shards = ranks.size();
    }
    sel.done.assign(static_cast<std::size_t>(total), 0);
    return sel;
}

// Periodic and other points, and their compute time, for the closing summary.
struct SweepTally {
    long periodic = 0, other = 0;
    double seconds_periodic = 0.0, seconds_other = 0.0;
    long on_longer_cycle = 0; // not settled, but repeating beyond run.max_steady_period
    int longest_cycle = 0;
    void add(const gapchain::SimulationResult& r) {
        if (r.longer_cycle_period) {
            ++on_longer_cycle;
            longest_cycle = std::max(longest_cycle, *r.longer_cycle_period);
        }
        if (r.steady_state_period) {
            ++periodic;
            seconds_periodic += r.wall_time_s;
        } else {
            ++other;
            seconds_other += r.wall_time_s;
        }
    }
};

void print_summary(const SweepTally& t, double wall, const SweepArguments& a,
                   const gapchain::Study& study, const Ranks& ranks) {
    const long total = gapchain::point_count(study);
    const long ran = t.periodic + t.other;
    std::printf("gapchain-sweep: %ld points in %.2f s wall (%.3g points/s)%s\n", ran, wall,
                wall > 0 ? ran / wall : 0.0,
                ranks.size() > 1 ? " on rank 0; the other ranks' rows are in the file too" : "");
    if (ran > 0) {
        std::printf("  periodic (stopped at steady state): %ld points, mean %.4f s each\n",
                    t.periodic, t.periodic ? t.seconds_periodic / t.periodic : 0.0);
        std::printf("  not periodic (full length):         %ld points, mean %.4f s each\n", t.other,
                    t.other ? t.seconds_other / t.other : 0.0);
        if (t.on_longer_cycle > 0)
            std::printf(
                "  of those, %ld repeat on a cycle longer than run.max_steady_period (up to "
                "%d periods%s): run.max_steady_period = %d (in the scene's run section, or "
                "as an axis value) lets them settle\n",
                t.on_longer_cycle, t.longest_cycle,
                study.keep.steady_state ? "; column longer_cycle_period" : "", t.longest_cycle);
        if (a.subset > 0)
            std::printf("  estimate for all %ld points at this rate: %.0f s (%.1f h)\n", total,
                        wall * total / ran, wall * total / ran / 3600.0);
    }
    std::printf("results in %s (sidecar %s.json)\n", a.out.c_str(), a.out.c_str());
}

// Rank 0's results file: checked against the study, opened (resuming), sidecar written.
std::unique_ptr<gapchain::ResultLog>
open_results(const SweepArguments& a, const gapchain::Study& study, gapchain::SweepSelection& sel) {
    using namespace gapchain;
    check_resume(a.out, study);
    // The sidecar first: a results file is never left without the study that started it. A
    // fresh start (no results, or an empty file) writes it whatever is there: a sidecar left
    // without its CSV, or another file of that name, was kept and then described another study.
    const std::string sidecar = a.out + ".json";
    std::error_code ec;
    const bool fresh =
        !std::filesystem::exists(a.out, ec) || std::filesystem::file_size(a.out, ec) == 0;
    std::optional<std::string> replaced;
    if (fresh) {
        if (std::ifstream old{sidecar, std::ios::binary})
            replaced.emplace(std::istreambuf_iterator<char>(old), std::istreambuf_iterator<char>());
        write_file_atomically(sidecar, study_json(study));
    }
    try {
        auto log = std::make_unique<ResultLog>(a.out, sweep_csv_header(study), point_count(study));
        sel.done = log->done();
        return log;
    } catch (...) {
        if (fresh && replaced)
            write_file_atomically(sidecar, *replaced);
        else if (fresh)
            std::filesystem::remove(sidecar, ec);
        throw;
    }
}

void sweep(const SweepArguments& a, Ranks& ranks) {
    using namespace gapchain;
    const Study study = load_study(a.study_path);
    SweepSelection sel = selection(a, study, ranks);
    cli::Outputs outputs({a.study_path});
    outputs.required_file(a.out, "--out");
    outputs.file(a.out + ".json", "--out (its .json sidecar)");
    std::unique_ptr<ResultLog> log;
    if (ranks.rank() == 0) log = open_results(a, study, sel);
    ranks.share_done(sel.done);
    if (ranks.rank() == 0)
        std::fprintf(stderr,
                     "gapchain-sweep: %ld points in the study, %ld already in %s, %zu to run%s\n",
                     point_count(study), log->rows_found(), a.out.c_str(),
                     pending_points(study, sel).size(), ranks.size() > 1 ? " on rank 0" : "");
    auto append = [&](const std::string& row) { log->append(row); };
    long from_others = 0;
    SweepTally tally;
    cli::Progress progress("gapchain-sweep", ranks.rank() == 0, true);
    const auto start = std::chrono::steady_clock::now();
    const SweepEnd end = run_study(
        study, sel,
        [&](const SweepPointResult& r) {
            if (ranks.rank() == 0) {
                log->append(sweep_csv_row(study, r));
                from_others += ranks.collect(append, false);
            } else {
                ranks.send_row(sweep_csv_row(study, r));
            }
            tally.add(r.simulation);
        },
        progress.callback());
    outputs.keep(); // rows written are done: an interrupted sweep resumes after them
    if (end == SweepEnd::cancelled) cli::throw_if_interrupted();
    if (ranks.rank() != 0) {
        ranks.send_done();
        return;
    }
    from_others += ranks.collect(append, true);
    if (ranks.size() > 1)
        std::printf("gapchain-sweep: rank 0 wrote %ld rows from the other %d ranks\n", from_others,
                    ranks.size() - 1);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    print_summary(tally, wall, a, study, ranks);
}

} // namespace

int main(int argc, char** argv) {
    Ranks ranks(argc, argv);
    CLI::App app{"Run a study (data/studies/*.json): every point's F_m (and what the study keeps), "
                 "in parallel, streamed to a CSV. Rerunning the same command after an interruption "
                 "continues where it stopped.",
                 "gapchain-sweep"};
    SweepArguments arguments;
    add_arguments(app, arguments);
    return gapchain::cli::run(app, argc, argv, [&] { sweep(arguments, ranks); });
}
