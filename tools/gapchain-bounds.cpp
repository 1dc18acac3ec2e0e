// gapchain-bounds: the paper's analytic estimates for one row, or the Table 2-3 comparison.
#include "common/cli.hpp"

#include "gapchain/bounds.hpp"
#include "gapchain/modes.hpp"
#include "gapchain/report.hpp"

#include <cstdio>

int main(int argc, char** argv) {
    using namespace gapchain;
    CLI::App app{
        "Analytic estimates of the paper for a row: eq (20) response and no-impact "
        "clearance, eq (24)-(25) smooth-region maximum and bound, eq (36)-(37) chaotic-region "
        "estimate and bound. --table prints Tables 2 and 3.",
        "gapchain-bounds"};
    cli::SceneArguments scene_args;
    cli::add_scene_arguments(app, scene_args, false);
    bool table = false;
    app.add_flag("--table", table, "Tables 2 and 3: the bounds against eps = 0.1, 0.2, 0.3, 0.5");
    return cli::run(app, argc, argv, [&] {
        if (table) {
            // The paper's simulated maxima (Tables 2 and 3), quoted for comparison.
            const double eps[] = {0.1, 0.2, 0.3, 0.5};
            const double smooth_paper[] = {3.75, 2.46, 1.45, 0.93};
            const double chaotic_paper[] = {7.02, 3.88, 2.65, 1.86};
            std::printf("%-34s %8s %8s %8s %8s\n", "eps", "0.1", "0.2", "0.3", "0.5");
            std::printf("%-34s", "Table 2: paper max F_m, smooth");
            for (double v : smooth_paper)
                std::printf(" %8.2f", v);
            std::printf("\n%-34s", "1/(2 eps)  eq (25)");
            for (double e : eps)
                std::printf(" %8.3f", smooth_bound(e));
            std::printf("\n%-34s", "Table 3: paper max F_m, chaotic");
            for (double v : chaotic_paper)
                std::printf(" %8.2f", v);
            std::printf("\n%-34s", "pi/(2 eps sqrt(4.935))  eq (37)");
            for (double e : eps)
                std::printf(" %8.3f", chaotic_bound(e));
            std::printf("\n");
            return;
        }
        const Scene scene = cli::load(scene_args);
        const ReducedParameters& p = scene.reduced;
        ModalOptions o;
        o.count = 1;
        o.shapes = false;
        const double f1 = modal_analysis(scene.chain(), o).frequencies.front();
        const double amplitude = single_body_amplitude(p.f_r, p.eps);
        std::printf("gapchain-bounds: Nm=%d fc=%g eps=%g e_r=%g f_r=%g\n", p.Nm, p.fc, p.eps, p.e_r,
                    p.f_r);
        std::printf("  eq (20) free response amplitude at f_r:   %.6g  (%s: e_r %s %.6g)\n",
                    amplitude, p.e_r < amplitude ? "impacts" : "no impact",
                    p.e_r < amplitude ? "<" : ">=", amplitude);
        std::printf("  eq (21) wall-contact frequency sqrt(1+fc): %.6g\n",
                    wall_contact_frequency(p.fc));
        auto show = [&](const char* label, double reduced) {
            std::printf("  %-42s %.6g", label, reduced);
            if (scene.physical)
                std::printf("  (%.6g N)", force_in_newtons(reduced, *scene.physical));
            std::printf("\n");
        };
        if (p.eps > 0) {
            show("eq (24) smooth-region max F_m:", smooth_max_force(p.fc, p.eps));
            show("eq (25) smooth-region bound 1/(2 eps):", smooth_bound(p.eps));
            show("eq (36) chaotic estimate, f_1a of eq (26):",
                 chaotic_max_force_approx(p.Nm, p.fc, p.eps));
            if (f1 > p.eps)
                show("eq (32)+(34) chaotic estimate, exact f_1:",
                     chaotic_max_force(p.Nm, p.fc, p.eps, f1));
            show("eq (37) chaotic bound:", chaotic_bound(p.eps));
        } else {
            std::printf("  eps = 0: the force estimates of eqs (24)-(37) are unbounded\n");
        }
        std::printf("  first linear-chain frequency f_1 = %.8g, f_1a = %.8g (eq 26)\n", f1,
                    approx_frequency(1, p.Nm, p.fc));
    });
}
