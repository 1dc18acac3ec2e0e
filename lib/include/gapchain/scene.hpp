#pragma once
/// \file scene.hpp
/// Scene input: JSON scene -> parameters and options (report.hpp writes the results). With
/// report.hpp, the only library code that knows about files and formats.
///
/// A scene (every key optional; left-out keys take the paper's defaults):
///   {"units": "reduced",
///    "model": {"Nm": 5, "fc": 100, "eps": 0.5, "e_r": 0.5},
///    "excitation": {"f_r": 1.0},
///    "run": {"periods": 1000, "transient_periods": "auto", "scheme": "auto", "tolerance": 1e-4},
///    "initial": {"u": [...], "v": [...]},
///    "output": {"trajectory_every": 1}}
/// With "units": "physical", model holds Nm, M, K, C, Kc, e and excitation holds a0, f (SI).
///
/// Ground motion (physical scenes): excitation.type is "harmonic" (default; a0, f), "record"
/// ({"file": path relative to the scene, "unit": "m/s2" | "g", "a0": PGA to scale to
/// [m/s^2] (default: the record's own), "tail": seconds of free vibration after it}) or
/// "kanai_tajimi" (a0 = PGA and the fields of KanaiTajimi: ground_frequency, ground_damping,
/// duration, sample_interval, rise, hold, decay, seed). For both, a0 is the PGA, run.periods
/// is set from the record's length (in natural periods) and sections, spectra and Lyapunov
/// exponents refuse the scene. Physical scenes may also give the relative arrays mass,
/// stiffness, contact, the clearance array in metres, and scatter.
///
/// Non-uniform rows (reduced scenes): model may also give per-body arrays "mass" (M_i / M),
/// "stiffness" (K_i / K), "damping" (eps_i), Nm entries each, and per-gap arrays "clearance"
/// (reduced e_r of gap j = 0..Nm, 0 the left wall) and "contact" (factor on the nominal contact
/// stiffness, fc at the walls and fc / 2 between bodies), Nm + 1 entries each; and "scatter":
/// {"clearance": s, "contact": s, "mass": s, "stiffness": s, "seed": n}, a seeded normal
/// scatter of relative standard deviation s around those values.

#include "gapchain/dynamics.hpp"
#include "gapchain/run.hpp"

#include <array>
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
    std::optional<Chain> row;                   ///< set for a non-uniform row (arrays, scatter)
    /// model.clearance (model.damping) gives every gap's clearance (body's damping): the
    /// reduced e_r (eps) did not run.
    bool clearance_array = false, damping_array = false;
    /// The model keys that made the row non-uniform, as the scene wrote them ("model.mass",
    /// "model.clearance, model.scatter"; "model.contact_law" for a nonlinear law); empty for the
    /// paper's row. Refusals name them.
    std::string non_uniform_keys;
    std::optional<GroundMotion> ground_record; ///< set for record / kanai_tajimi excitation
    double record_duration = 0.0; ///< [s] record length plus tail (non-harmonic scenes)
    std::string ground_motion_type =
        "harmonic";          ///< excitation.type: harmonic, record, kanai_tajimi
    std::string record_file; ///< excitation.file as read (resolved against the scene), else empty

    /// The row: the non-uniform one if the scene gave arrays or a scatter, else the
    /// homogeneous chain of the reduced parameters.
    [[nodiscard]] Chain chain() const { return row ? *row : Chain::homogeneous(reduced); }
    /// Whether the row is the paper's homogeneous one (tools that take only the five reduced
    /// parameters refuse other rows).
    [[nodiscard]] bool uniform() const { return !row.has_value(); }
    /// The equations of motion of the scene.
    [[nodiscard]] Dynamics dynamics() const {
        return ground_record ? Dynamics(chain(), *ground_record)
                             : Dynamics(chain(), HarmonicForcing{reduced.f_r, 1.0});
    }
    /// Whether the ground motion is the paper's harmonic one.
    [[nodiscard]] bool harmonic() const { return !ground_record.has_value(); }
};

/// Reads a ground-acceleration record: two columns (time [s], acceleration) separated by
/// commas, semicolons or blanks; '#' comment lines, blank lines and one header line are skipped.
/// Accelerations are multiplied by `unit` (1 for m/s^2, 9.80665 for g). Throws SceneError
/// naming the file and line.
Accelerogram read_accelerogram(const std::string& path, double unit = 1.0);

/// Reads and validates a scene file; overrides are "section.key=value" strings applied first
/// (value parsed as JSON, else taken as a string; nan/inf are numbers). Throws SceneError.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// The dotted scene key ("section.key") of key. A dotted key is returned as it is; a short key
/// gets its section: Nm, fc, eps, e_r (model.), f_r (excitation.), periods, transient_periods,
/// scheme, tolerance, step, steady_state, steady_tolerance, max_steady_period, estimate_error,
/// max_work, multistability_check, accuracy_mode (run.) and trajectory_every (output.). Any other
/// key throws SceneError naming it (prefixed by context if not empty).
std::string scene_key(const std::string& key, const std::string& context = "");

/// Whether a dotted scene key sets what a row's linear-chain modes do not depend on: the
/// forcing and the start (excitation.*, initial.*), the damping (model.eps, C, damping,
/// contact_damping) and the clearances (model.e_r, e, clearance, scatter.clearance).
/// gapchain-modes and Python's modes() refuse them.
bool key_unread_by_modes(const std::string& dotted_key);

/// The dotted scene keys whose value a sweep or continuation of `which` replaces: the reduced
/// key (excitation.f_r, model.e_r, model.fc, model.eps) and the physical scene's key that enters
/// that number alone (excitation.f, model.e, model.Kc, model.C; MODEL.md section 1). A tool or
/// function that varies `which` refuses an override of either.
std::array<std::string, 2> keys_replaced_by(SweptParameter which);

/// Analyses that take the paper's five reduced numbers and a forcing period (bifurcation,
/// classify, continuation, the attractor search) refuse other scenes with the rule, naming the
/// key: a record or Kanai-Tajimi excitation, model arrays or scatter, a nonlinear contact law.
/// `user` names the tool or function in the message. Throws SceneError.
void require_paper_row(const Scene& scene, const std::string& user);

/// Analyses built on the exact propagator or the tangent flow (orbits, the work-precision
/// study) refuse a non-harmonic excitation or a nonlinear contact law (any row of them), with
/// the reason `why`. Throws SceneError.
void require_linear_harmonic(const Scene& scene, const std::string& user, const std::string& why);

/// Copies what a scene says of how to run and where to start into the options of an analysis
/// that runs the row itself (BifurcationOptions, ClassifyOptions): run.scheme, run.tolerance,
/// run.max_work and the initial state. The options' own validate() checks them.
template <class AnalysisOptions>
void take_run_settings(const Scene& scene, AnalysisOptions& o) {
    o.scheme = scene.run.scheme;
    o.tolerance = scene.run.tolerance;
    o.max_work = scene.run.max_work;
    o.initial = scene.initial;
}

/// Why `text` is not a number as gapchain reads the numbers it is given (scene values, --set
/// values, command-line flags): plain decimal (an integer when `integer`: digits alone, no
/// leading zeros; CLI11 read 010 as octal 8, 0x10 as hex 16 and an empty text as 0), finite,
/// and 0 or at least 2.2e-308 in magnitude (1e-999 reads as 0; a subnormal loses digits).
/// Empty when it is one. The message starts "must be" and ends with the text.
std::string number_text_error(std::string_view text, bool integer = false);

/// The run keys an analysis reads that runs the row once over its whole length (PlannedRun:
/// poincare, spectrum, lyapunov; no steady-state stop, error estimate or start check, every
/// step strict): the tools refuse a --set, and Python a keyword, of any other run key.
inline const std::vector<std::string> once_through_run_keys{"run.periods", "run.transient_periods",
                                                            "run.scheme",  "run.tolerance",
                                                            "run.step",    "run.max_work"};

/// Whether text spells NaN or an infinity (nan, inf or infinity, any case, with a sign): what
/// --set and the command-line flags read as those values, and JSON lacks.
bool spells_non_finite(std::string_view text);

/// Parses and validates scene text (see load_scene). Throws SceneError.
Scene parse_scene(std::string_view text, const std::vector<std::string>& overrides = {},
                  const std::string& source = "<string>");

} // namespace gapchain
