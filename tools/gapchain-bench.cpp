// gapchain-bench: the benchmarks of docs/performance.md. Prints figures; never part of CTest
// (only its --help is). Machines are shared and noisy: compare ratios measured in one run.
//   gapchain-bench sim           the three reference scenes against a plain fixed-step RK4 loop
//   gapchain-bench bifurcation   the 500-value Fig 13 diagram (200 + 100 periods per value)
//   gapchain-bench modes         the lowest 10 modes of a 10^6-body chain (Spectra)
//   gapchain-bench peer          a stiff chaotic row against Boost.Odeint's dopri5 (libboost-dev)
//   gapchain-bench relaxed CSV   the relaxed plan's F_m error on the periodic rows of a sweep
#include "common/cli.hpp"
#ifdef GAPCHAIN_WITH_ODEINT
#include "bench/odeint_peer.hpp"
#endif

#include "gapchain/bifurcation.hpp"
#include "gapchain/model.hpp"
#include "gapchain/modes.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace {

using namespace gapchain;

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The baseline a user would write first: fixed-step RK4 on the right-hand side, F_m read at
// the step points from period `transient` on (the window gapchain records), every period
// integrated (no steady-state stop, no peak location).
double plain_rk4_fm(const Dynamics& dyn, double h_omega, long periods, long transient) {
    const int dim = dyn.dimension();
    const int spp =
        static_cast<int>(std::ceil(dyn.period() * dyn.max_angular_frequency() / h_omega));
    const double h = dyn.period() / spp;
    std::vector<double> y(dim, 0.0), k1(dim), k2(dim), k3(dim), k4(dim), tmp(dim);
    double fm = 0.0;
    for (long s = 0; s < periods * spp; ++s) {
        const double t = s * h;
        dyn.rhs(t, y.data(), k1.data());
        for (int i = 0; i < dim; ++i)
            tmp[i] = y[i] + 0.5 * h * k1[i];
        dyn.rhs(t + 0.5 * h, tmp.data(), k2.data());
        for (int i = 0; i < dim; ++i)
            tmp[i] = y[i] + 0.5 * h * k2[i];
        dyn.rhs(t + 0.5 * h, tmp.data(), k3.data());
        for (int i = 0; i < dim; ++i)
            tmp[i] = y[i] + h * k3[i];
        dyn.rhs(t + h, tmp.data(), k4.data());
        for (int i = 0; i < dim; ++i)
            y[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
        if (s + 1 < transient * spp) continue;
        for (int j = 0; j < dyn.gaps(); ++j)
            fm = std::max(fm, dyn.force(j, y.data()));
    }
    return fm;
}

struct Case {
    const char* name;
    ReducedParameters p;
};

void bench_sim(long periods, double tolerance) {
    const Case cases[] = {{"(a) smooth", {5, 100, 0.5, 0.5, 1.0}},
                          {"(b) stiff", {20, 2000, 0.5, 0.24, 1.0}},
                          {"(c) chaotic", {46, 559, 0.1, 0.22, 1.0}}};
    std::printf("periods %ld, tolerance %g (relative F_m)\n", periods, tolerance);
    double plain_h_omega = 0.5;
    for (const Case& c : cases) {
        const Dynamics dyn = Dynamics::paper_row(c.p);
        RunOptions o;
        o.periods = periods;
        o.tolerance = tolerance;
        const SimulationResult r = simulate(dyn, o);
        const double body_steps = static_cast<double>(r.steps) * c.p.Nm;
        std::printf(
            "%-12s gapchain %-5s: F_m %.8f +- %.2e  %8.4f s  %6ld periods  %.3g body-steps/s"
            "  %s\n",
            c.name, std::string(to_string(r.scheme)).c_str(), r.F_m, r.F_m_error, r.wall_time_s,
            r.periods_simulated, body_steps / r.wall_time_s,
            r.steady_state_period ? "periodic" : "not periodic");
        const bool periodic = r.steady_state_period.has_value();
        if (periodic) {
            // Equal accuracy: the plain loop's step is halved until its F_m (read at step points)
            // is within the tolerance of a tight gapchain reference; the search runs on 60
            // periods (the maxima settle well before), the timing on the full length.
            RunOptions tight = o;
            tight.tolerance = 1e-10;
            tight.scheme =
                Scheme::rk8pd; // independent of the scheme under test (auto may pick exact)
            tight.estimate_error = false;
            const double ref = simulate(dyn, tight).F_m;
            plain_h_omega = 0.5;
            while (std::abs(plain_rk4_fm(dyn, plain_h_omega, 60, r.transient_periods_used) - ref) >
                       tolerance * ref &&
                   plain_h_omega > 1e-4)
                plain_h_omega /= 2;
            std::printf("%-12s reference F_m %.10f; gapchain true error %.2e (relative %.2e)\n", "",
                        ref, std::abs(r.F_m - ref), std::abs(r.F_m - ref) / ref);
        }
        // For the chaotic scene, whose F_m has no converged value to search against, the plain
        // loop keeps the h * omega_max the periodic scenes needed.
        const auto start = std::chrono::steady_clock::now();
        const double plain = plain_rk4_fm(dyn, plain_h_omega, periods, r.transient_periods_used);
        const double plain_s = seconds_since(start);
        const double per_period_ratio =
            (plain_s / static_cast<double>(periods)) / (r.wall_time_s / r.periods_simulated);
        std::printf("%-12s plain rk4 (h*omega %.4g): F_m %.8f  %8.4f s   -> %.1fx faster per "
                    "simulation, %.1fx per simulated period\n",
                    "", plain_h_omega, plain, plain_s, plain_s / r.wall_time_s, per_period_ratio);
    }
}

/// Issue 16's stiff chaotic row (Nm = 20, fc = 2000, eps = 0.2, e_r = 0.02, f_r = 1): gapchain
/// in auto and strict mode, and the Odeint peer at tolerances 1e-4 and 1e-6, in one run.
void bench_peer(long periods) {
#ifdef GAPCHAIN_WITH_ODEINT
    const ReducedParameters p{20, 2000, 0.2, 0.02, 1.0};
    const Dynamics dyn = Dynamics::paper_row(p);
    std::printf("stiff chaotic row Nm=20 fc=2000 eps=0.2 e_r=0.02 f_r=1, %ld periods\n", periods);
    RunOptions o;
    o.periods = periods;
    const SimulationResult automatic = simulate(dyn, o);
    // Like for like with the peer, which has no multistability check: F_m alone (a relaxed run
    // whose halves agree still runs the twin that tells chaos from a torus).
    RunOptions bare = o;
    bare.multistability_check = false;
    const SimulationResult alone = simulate(dyn, bare);
    o.accuracy_mode = AccuracyMode::strict;
    const SimulationResult strict = simulate(dyn, o);
    const struct {
        const char* name;
        const SimulationResult& r;
    } rows[] = {{"auto", automatic}, {"auto, no check", alone}, {"strict", strict}};
    for (const auto& row : rows)
        std::printf("gapchain %-14s: F_m %.4f +- %.4f (%s, multistability check %s)  %8.4f s\n",
                    row.name, row.r.F_m, row.r.F_m_error,
                    std::string(to_string(row.r.accuracy_mode_used)).c_str(),
                    row.r.twin_checked ? "run" : "off", row.r.wall_time_s);
    for (double tolerance : {1e-4, 1e-6}) {
        const bench::PeerRun peer =
            bench::odeint_dopri5(dyn, periods, automatic.transient_periods_used, tolerance);
        const bool inside = std::abs(peer.F_m - automatic.F_m) <= automatic.F_m_error;
        std::printf("odeint dopri5 %g: F_m %.4f (%s gapchain auto's spread)  %ld steps  %8.4f s"
                    "  -> gapchain auto %.2fx, without its check %.2fx faster\n",
                    tolerance, peer.F_m, inside ? "inside" : "outside", peer.steps, peer.seconds,
                    peer.seconds / automatic.wall_time_s, peer.seconds / alone.wall_time_s);
    }
#else
    (void)periods;
    throw std::invalid_argument("peer: this gapchain-bench was built without Boost.Odeint "
                                "(install libboost-dev: bash tools/dev/deps.sh, and rebuild)");
#endif
}

/// The periodic rows (status steady_state, F_m > 1e-3) of a gapchain-sweep CSV, up to count.
std::vector<ReducedParameters> periodic_rows(const std::string& path, int count) {
    std::ifstream in(path);
    if (!in) throw std::invalid_argument("relaxed: cannot read " + path);
    const auto fields = [](const std::string& line) {
        std::vector<std::string> cell;
        std::stringstream in_line(line);
        for (std::string f; std::getline(in_line, f, ',');)
            cell.push_back(f);
        // getline drops an empty last field (an empty steady_state_period of a row that did
        // not settle).
        if (!line.empty() && line.back() == ',') cell.emplace_back();
        return cell;
    };
    std::string line;
    std::getline(in, line);
    std::map<std::string, std::size_t> column;
    const std::vector<std::string> header = fields(line);
    for (std::size_t i = 0; i < header.size(); ++i)
        column[header[i]] = i;
    for (const char* name : {"Nm", "fc", "eps", "e_r", "f_r", "F_m", "status"})
        if (!column.count(name))
            throw std::invalid_argument("relaxed: " + path + " has no column " + name);
    std::vector<ReducedParameters> rows;
    long line_number = 1;
    while (static_cast<int>(rows.size()) < count && std::getline(in, line)) {
        ++line_number;
        const std::vector<std::string> cell = fields(line);
        const std::string where = "relaxed: " + path + " line " + std::to_string(line_number);
        if (cell.size() < header.size())
            throw std::invalid_argument(where + ": " + std::to_string(cell.size()) +
                                        " fields, the header has " + std::to_string(header.size()));
        // A malformed number is named, not skipped or read up to its junk ("2.9xyz" was Nm 2).
        const auto number = [&](const char* name) {
            const std::string& text = cell[column[name]];
            const std::string error = number_text_error(text, name == std::string("Nm"));
            if (!error.empty()) throw std::invalid_argument(where + ", " + name + ": " + error);
            return std::strtod(text.c_str(), nullptr);
        };
        if (cell[column["status"]] != "steady_state" || number("F_m") <= 1e-3) continue;
        const double Nm = number("Nm");
        if (Nm < 1 || Nm > 1'000'000)
            throw std::invalid_argument(where + ", Nm: must be in 1 to 1000000, got " +
                                        cell[column["Nm"]]);
        const ReducedParameters row{static_cast<int>(Nm), number("fc"), number("eps"),
                                    number("e_r"), number("f_r")};
        // Checked here, where the file and line are known (fc = -60 was refused without them).
        try {
            validate(row);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(where + ", " + e.what());
        }
        rows.push_back(row);
    }
    return rows;
}

/// relaxed_plan()'s F_m on periodic rows against strict runs at tolerance 1e-6, each run to the
/// strict run's steady state and 50 periods beyond.
void bench_relaxed(const std::string& path, int count) {
    double sum = 0.0, sum2 = 0.0, largest = 0.0;
    int n = 0;
    for (const ReducedParameters& p : periodic_rows(path, count)) {
        const Dynamics dyn = Dynamics::paper_row(p);
        RunOptions o;
        o.accuracy_mode = AccuracyMode::strict;
        o.tolerance = 1e-6;
        o.multistability_check = false;
        o.estimate_error = false;
        const SimulationResult strict = simulate(dyn, o);
        if (!strict.steady_state_period || strict.F_m <= 0.0) continue;
        const StepPlan plan = relaxed_plan(dyn);
        const auto stepper = make_stepper(plan, dyn);
        std::vector<double> y(dyn.dimension(), 0.0);
        MaxForceTracker forces(dyn);
        Observer* observers[] = {&forces};
        run(dyn, *stepper, plan,
            RunSpan{strict.periods_simulated + 50, strict.transient_periods_used, 0.0, 0}, y,
            observers);
        const double e = (forces.max_force() - strict.F_m) / strict.F_m;
        sum += e;
        sum2 += e * e;
        largest = std::max(largest, std::abs(e));
        ++n;
    }
    if (n == 0) throw std::invalid_argument("relaxed: no periodic rows in " + path);
    const double mean = sum / n;
    std::printf("relaxed plan (rk4, h omega 0.4, no switch splitting) vs strict at 1e-6 on %d "
                "periodic rows: relative F_m error mean %+.2e, rms %.2e, largest %.2e\n",
                n, mean, std::sqrt(sum2 / n), largest);
}

/// Per-period maxima of a run: one MaxForceTracker per forcing period.
class PeriodMaxima final : public Observer {
public:
    explicit PeriodMaxima(const Dynamics& dyn)
        : m_dyn(dyn), m_tracker(std::make_unique<MaxForceTracker>(dyn)) {}
    void on_step(const StepView& step) override { m_tracker->on_step(step); }
    bool on_period(long n, double, const double*) override {
        if (n == 0) return false;
        maxima.push_back(m_tracker->max_force());
        m_tracker = std::make_unique<MaxForceTracker>(m_dyn);
        return false;
    }
    std::vector<double> maxima;

private:
    const Dynamics& m_dyn;
    std::unique_ptr<MaxForceTracker> m_tracker;
};

/// Mean and standard deviation (n - 1) of values.
std::pair<double, double> mean_sd(const std::vector<double>& v) {
    const double m = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
    double s = 0.0;
    for (const double x : v)
        s += (x - m) * (x - m);
    return {m, std::sqrt(s / static_cast<double>(v.size() - 1))};
}

/// relaxed_plan() against the strict rk4 plan at 1e-4 on one row: F_m, the mean of the top 20
/// per-period maxima and the mean per-period maximum over 1000 periods (100 discarded), from
/// `starts` starts u_1(0) = k 1.3e-7, as mean +- standard deviation over the starts.
void bench_plans(const ReducedParameters& p, int starts) {
    const Dynamics dyn = Dynamics::paper_row(p);
    // Refused up front, as a run is (run.max_work's default, about an hour): Nm = 1e6 ran for
    // minutes with nothing printed.
    const double work =
        static_cast<double>(p.Nm) * 1000.0 * starts *
        (plan_step(dyn, Scheme::rk4, 1e-4).steps_per_period + relaxed_plan(dyn).steps_per_period);
    if (work > RunOptions{}.max_work) {
        char text[320];
        std::snprintf(text, sizeof text,
                      "--row: this benchmark takes about %.2g body-steps (Nm x steps per period of "
                      "both plans x 1000 periods x --starts), above the limit of %.2g (about an "
                      "hour); take a shorter row or fewer --starts",
                      work, RunOptions{}.max_work);
        throw std::invalid_argument(text);
    }
    for (const bool relaxed : {false, true}) {
        const StepPlan plan = relaxed ? relaxed_plan(dyn) : plan_step(dyn, Scheme::rk4, 1e-4);
        std::vector<double> means, tops, maxima;
        for (int k = 0; k < starts; ++k) {
            const auto stepper = make_stepper(plan, dyn);
            PeriodMaxima per_period(dyn);
            Observer* observers[] = {&per_period};
            std::vector<double> y(dyn.dimension(), 0.0);
            y[0] = k * 1.3e-7;
            run(dyn, *stepper, plan, RunSpan{1000, 0, 0.0, 0}, y, observers);
            std::vector<double> w(per_period.maxima.begin() + 100, per_period.maxima.end());
            means.push_back(mean_sd(w).first);
            std::sort(w.begin(), w.end(), std::greater<>());
            tops.push_back(std::accumulate(w.begin(), w.begin() + 20, 0.0) / 20.0);
            maxima.push_back(w.front());
        }
        const auto [m, m_sd] = mean_sd(means);
        const auto [t, t_sd] = mean_sd(tops);
        const auto [f, f_sd] = mean_sd(maxima);
        std::printf("%s: F_m %.5f +- %.5f  top-20 per-period maxima %.5f +- %.5f  mean "
                    "per-period maximum %.5f +- %.5f\n",
                    relaxed ? "relaxed plan    " : "strict rk4 1e-4 ", f, f_sd, t, t_sd, m, m_sd);
    }
}

// The diagram with and without Newton's confirmation of its periodic rows, in the same run.
void bench_bifurcation(int threads) {
    const ReducedParameters fig13{5, 60, 0.5, 0.06, 3.0};
    double plain_time = 0.0;
    for (const bool newton : {false, true}) {
        BifurcationOptions o;
        o.threads = threads;
        o.confirm_by_newton = newton;
        const BifurcationResult r = bifurcation(fig13, o);
        int periodic = 0, confirmed = 0;
        for (const auto& row : r.rows) {
            periodic += row.period > 0;
            confirmed += row.newton_confirmed;
        }
        std::printf("Fig 13 diagram: %d values x (%ld + %ld) periods, %d threads: %.3f s wall "
                    "(%d periodic rows, %d confirmed by Newton)",
                    o.steps, o.transient_periods, o.record_periods, r.threads_used, r.wall_time_s,
                    periodic, confirmed);
        if (newton)
            std::printf(", %.2fx the time without\n", r.wall_time_s / plain_time);
        else
            std::printf("\n");
        plain_time = r.wall_time_s;
    }
}

void bench_modes(int Nm, int count) {
    for (double fc : {1.0, 100.0, 2000.0}) {
        ModalOptions o;
        o.count = count;
        o.method = EigenMethod::sparse;
        const ModalResult r = modal_analysis(Chain::homogeneous({Nm, fc, 0.5, 0.0, 1.0}), o);
        double worst = 0.0;
        for (double res : r.residuals)
            worst = std::max(worst, res);
        std::printf(
            "Nm = %d, fc = %g: lowest %d modes in %.3f s (%ld restarts, max residual %.1e), "
            "f_1 - 1 = %.6e\n",
            Nm, fc, count, r.wall_time_s, r.iterations, worst, r.frequencies.front() - 1.0);
    }
}

/// gapchain-bench relaxed: its subcommand and options.
struct RelaxedArguments {
    std::string sample; ///< a gapchain-sweep CSV
    int points = 300;
    CLI::App* command = nullptr;
};

void add_relaxed(CLI::App& app, RelaxedArguments& a) {
    a.command = app.add_subcommand("relaxed", "The relaxed plan's F_m error on periodic rows");
    a.command->add_option("sample", a.sample, "gapchain-sweep CSV (its periodic rows are used)")
        ->required()
        ->check(CLI::ExistingFile);
    a.command->add_option("--points", a.points, "Periodic rows to use")
        ->check(cli::range(1, 1'000'000))
        ->capture_default_str();
}

/// gapchain-bench plans: its subcommand and options.
struct PlansArguments {
    std::vector<double> row; ///< Nm, fc, eps, e_r, f_r
    int starts = 6;
    CLI::App* command = nullptr;
};

void add_plans(CLI::App& app, PlansArguments& a) {
    a.command = app.add_subcommand(
        "plans", "The relaxed plan against the strict one on one row, over several starts");
    a.command->add_option("--row", a.row, "Nm,fc,eps,e_r,f_r")
        ->required()
        ->delimiter(',')
        ->expected(5);
    a.command->add_option("--starts", a.starts, "Starts per plan")
        ->check(cli::range(2, 1000))
        ->capture_default_str();
}

void run_plans(const PlansArguments& a) {
    const ReducedParameters p{static_cast<int>(a.row[0]), a.row[1], a.row[2], a.row[3], a.row[4]};
    if (p.Nm != a.row[0]) throw std::invalid_argument("--row: Nm must be an integer");
    validate(p);
    bench_plans(p, a.starts);
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Benchmarks of docs/performance.md (prints figures; not a test).",
                 "gapchain-bench"};
    app.require_subcommand(0, 1);
    app.allow_extras(false);
    long periods = 1000;
    double tolerance = 1e-4;
    int threads = 0;
    auto* sim = app.add_subcommand("sim", "The three reference scenes against a plain RK4 loop");
    sim->add_option("--periods", periods, "Forcing periods per simulation")
        ->check(cli::range(1L, 1'000'000'000L))
        ->capture_default_str();
    sim->add_option("--tolerance", tolerance, "Relative F_m tolerance")
        ->check(cli::range(1e-12, 0.1))
        ->capture_default_str();
    auto* bif = app.add_subcommand("bifurcation", "The 500-value Fig 13 bifurcation diagram");
    bif->add_option("--threads", threads, "OpenMP threads (0: all)")
        ->check(cli::range(0, 4096))
        ->capture_default_str();
    int Nm = 1'000'000, modes = 10;
    auto* mod = app.add_subcommand("modes", "The lowest modes of a long chain (Spectra)");
    mod->add_option("--Nm", Nm, "Bodies")->check(cli::range(3, 1'000'000))->capture_default_str();
    mod->add_option("--modes", modes, "Modes")->check(cli::range(1, 1000))->capture_default_str();
    long peer_periods = 200;
    auto* peer = app.add_subcommand("peer", "A stiff chaotic row against Boost.Odeint's dopri5");
    peer->add_option("--periods", peer_periods, "Forcing periods")
        ->check(cli::range(20L, 1'000'000L))
        ->capture_default_str();
    RelaxedArguments relaxed;
    add_relaxed(app, relaxed);
    PlansArguments plans;
    add_plans(app, plans);
    return gapchain::cli::run(
        app, argc, argv,
        [&] {
            // A benchmark writes no file and the calls it times take no progress callback:
            // an interrupt ends it at once instead of waiting for a second one.
            std::signal(SIGINT, SIG_DFL);
            std::signal(SIGTERM, SIG_DFL);
            // Each finished figure reaches a file or pipe before an interrupt can end the run.
            std::setvbuf(stdout, nullptr, _IOLBF, 0);
            if (app.get_subcommands().empty())
                throw std::invalid_argument(
                    "a benchmark is required: sim, bifurcation, modes, peer, relaxed or plans");
            if (peer->parsed()) bench_peer(peer_periods);
            if (relaxed.command->parsed()) bench_relaxed(relaxed.sample, relaxed.points);
            if (plans.command->parsed()) run_plans(plans);
            if (mod->parsed()) bench_modes(Nm, modes);
            if (sim->parsed()) bench_sim(periods, tolerance);
            if (bif->parsed()) {
                bench_bifurcation(1);
                bench_bifurcation(threads);
            }
        },
        {{"count", "--modes"}});
}
