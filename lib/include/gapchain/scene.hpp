#pragma once
/// \file scene.hpp
/// Scene I/O: JSON scene -> parameters and options; results -> JSON. The only library code
/// that knows about files and formats.
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

#include <fstream>
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

/// A simulation result as JSON: F_m, F_m_error, contact, per_body, per_contact,
/// steady_state_period (null if none), wall_time_s, and the run's provenance.
std::string to_json(const SimulationResult& result, const Scene& scene);

/// Writes a file so that readers never see it half-written and a failure leaves nothing:
/// the text goes to a temporary file next to path, which is renamed over path on commit().
/// Destroying an uncommitted OutputFile removes the temporary.
class OutputFile {
public:
    /// Opens path + ".tmp.<pid>" for writing; throws SceneError if it cannot.
    explicit OutputFile(std::string path);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;
    /// The stream to write to.
    std::ostream& stream() { return m_stream; }
    /// Flushes, closes and renames onto the final path; throws SceneError on I/O failure.
    void commit();

private:
    std::string m_path;
    std::string m_temp;
    std::ofstream m_stream;
    bool m_committed = false;
};

/// Writes text to path through an OutputFile.
void write_file_atomically(const std::string& path, const std::string& text);

} // namespace gapchain
