#pragma once
/// \file scene.hpp
/// Scene input: JSON scene -> parameters and options (report.hpp writes the results). With
/// report.hpp, the only library code that knows about files and formats.
///
/// A scene (every key optional; left-out keys take the paper's defaults):
///   {"units": "reduced",
///    "model": {"Nm": 5, "fc": 100, "eps": 0.5, "e_r": 0.5},
///    "excitation": {"f_r": 1.0},
///    "run": {"periods": 1000, "transient_periods": 0, "scheme": "auto", "tolerance": 1e-4},
///    "initial": {"u": [...], "v": [...]},
///    "output": {"trajectory_every": 1}}
/// With "units": "physical", model holds Nm, M, K, C, Kc, e and excitation holds a0, f (SI).

#include "gapchain/dynamics.hpp"
#include "gapchain/simulation.hpp"

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gapchain {

/// Bad scene or command-line input (malformed JSON, unknown key, wrong type, out-of-range or
/// non-finite value, unreadable file). The message is one line naming the key and the range.
class SceneError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

/// Unit system a scene was written in.
enum class Units { reduced, physical };

/// A validated scene.
struct Scene {
    Units units = Units::reduced;               ///< how the scene gave the model
    ReducedParameters reduced;                  ///< always set (converted if physical)
    std::optional<PhysicalParameters> physical; ///< set for physical scenes
    RunOptions run;                             ///< run options
    std::vector<double> initial;                ///< initial state (empty: rest)
    int trajectory_every = 1;                   ///< trajectory decimation in steps, >= 1
    std::string source;                         ///< file it came from, or "<built-in>"

    /// The homogeneous chain of the reduced parameters.
    [[nodiscard]] Chain chain() const { return Chain::homogeneous(reduced); }
    /// The equations of motion of the scene.
    [[nodiscard]] Dynamics dynamics() const { return Dynamics(chain(), {reduced.f_r, 1.0}); }
};

/// Reads and validates a scene file; overrides are "section.key=value" strings applied first
/// (value parsed as JSON, else taken as a string; nan/inf are numbers). Throws SceneError.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Parses and validates scene text (see load_scene). Throws SceneError.
Scene parse_scene(std::string_view text, const std::vector<std::string>& overrides = {},
                  const std::string& source = "<string>");

} // namespace gapchain
