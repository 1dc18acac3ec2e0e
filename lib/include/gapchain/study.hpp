#pragma once
/// \file study.hpp
/// Study input (scene I/O layer): a study file -> Study, and the scene of each of its points.
/// The base scene is parsed once; each point sets its values on the parsed scene, as --set
/// would, and validates it.
///
/// A study (docs/sweep.md):
///   {"scene": {...base scene...},
///    "parameters": {"fc": [1, 10, 100], "e_r": {"lin": [0, 1.5, 61]}, "f_r": {"log": [...]}},
///    "sample": "grid" | {"method": "random" | "latin_hypercube", "samples": N, "seed": S},
///    "keep": ["F_m", "multistable", "per_body", "regime", "steady_state_period", "wall_time",
///             "F_m_orbit"],
///    "attractors": N}
/// Parameter keys are dotted scene keys; Nm, fc, eps, e_r (model), f_r (excitation) and the run
/// keys (periods, tolerance, ...) may be given short (scene_key()).

#include "gapchain/scene.hpp"
#include "gapchain/sweep.hpp"

#include <memory>
#include <string>

namespace gapchain {

/// Reads and validates a study file. Throws SceneError naming the key.
Study load_study(const std::string& path);
/// Parses and validates study text (every axis value must make a valid scene on its own).
/// Throws SceneError naming the key.
Study parse_study(const std::string& text, const std::string& source = "<string>");

/// The scenes of a study's points, from its base scene parsed once. Reentrant: scene() may be
/// called from several threads at once.
class StudyScenes {
public:
    /// study must outlive this object.
    explicit StudyScenes(const Study& study);
    ~StudyScenes();
    StudyScenes(const StudyScenes&) = delete;
    StudyScenes& operator=(const StudyScenes&) = delete;
    /// The scene of point index (0 <= index < point_count): the base scene with the point's
    /// values set. A bad value throws SceneError naming the key.
    [[nodiscard]] Scene scene(long index) const;

private:
    struct BaseScene;
    const Study& m_study;
    std::unique_ptr<BaseScene> m_base;
};

/// The scene of point index of study (parses the base scene; StudyScenes parses it once).
Scene point_scene(const Study& study, long index);

/// What a sweep point runs, taken from its scene.
SweepPointInput sweep_point_input(const Scene& scene);

/// Runs the study's pending points (run_sweep with the points' scenes).
SweepEnd run_study(const Study& study, const SweepSelection& selection,
                   const std::function<void(const SweepPointResult&)>& sink,
                   const ProgressCallback& progress = {});

} // namespace gapchain
