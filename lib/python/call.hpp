#pragma once
// What every binding shares: Python arguments -> a Scene (through the library's scene
// parsing, so validation and messages are the tools'), a long call run with the GIL released
// that reports progress and stops on KeyboardInterrupt, and NumPy arrays of results.

#include "gapchain/attractors.hpp"
#include "gapchain/observers.hpp"
#include "gapchain/run.hpp"
#include "gapchain/scene.hpp"
#include "gapchain/study.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gapchain::python {

namespace py = pybind11;

// The scene of a call: scene is None (the paper's defaults), a dict (a scene as JSON) or a
// path (str or os.PathLike) to a scene file; keys are scene keys, short (fc, f_r, periods)
// or dotted (run.tolerance), applied as overrides. Bad input throws SceneError.
Scene to_scene(const py::object& scene, const py::kwargs& keys);

// to_scene() for a function that varies param (f_r, e_r, fc or eps) itself, from from_ to to:
// a keyword for that scene key is refused (it would be silently replaced), as the tools refuse
// its --set. function names the caller in the message.
Scene to_swept_scene(const py::object& scene, const std::string& param, const py::kwargs& keys,
                     const std::string& function);

// Refuses a keyword for a scene key that function replaces by varying param itself (over: how,
// "from from_ to to" or "over e_r"): std::invalid_argument naming it.
void refuse_swept_keys(const py::kwargs& keys, const std::string& param,
                       const std::string& function, const std::string& over);

// Functions that run the row their own way (orbit and continuation shoot with their scheme,
// classify and bifurcation run transient + record periods) refuse a run.* or output.* keyword
// they would silently ignore, every one but those in `read` ("run." for every run key):
// std::invalid_argument naming it, with `instead` saying how the function runs.
void refuse_run_keys(const py::kwargs& keys, const std::string& function,
                     const std::vector<std::string>& read, const std::string& instead,
                     const std::vector<std::string>& unread = {});

// Runs body; a std::invalid_argument whose advice names a library key in parentheses ("fewer
// periods (run.periods)") is raised naming instead what the function takes (`keywords`, e.g.
// "transient, record"): classify() advised run.periods, a keyword it refuses.
template <class Body>
auto advising_keywords(const std::string& key, const std::string& keywords, Body&& body)
    -> decltype(body()) {
    try {
        return body();
    } catch (const std::invalid_argument& e) {
        std::string message = e.what();
        const std::string from = "(" + key + ")", to = "(" + keywords + ")";
        for (auto at = message.find(from); at != std::string::npos;
             at = message.find(from, at + to.size()))
            message.replace(at, from.size(), to);
        throw std::invalid_argument(message);
    }
}

// The run keys take_run_settings() reads (scene.hpp): all that classify(), regime_map() and
// bifurcation() read of the run section.
inline const std::vector<std::string> run_settings_keys{"run.scheme", "run.tolerance",
                                                        "run.max_work"};

// Why poincare(), spectrum() and lyapunov() read no run key but once_through_run_keys.
inline const char* plain_run_reason = "it runs every period strict, with no steady-state stop, "
                                      "error estimate or start check, and returns no trajectory";

// The paper's row at one point, as the analyses of the five reduced numbers need it
// (require_paper_row(), naming function()); SceneError otherwise.
const ReducedParameters& paper_row(const Scene& scene, const std::string& function);

// A study: a dict (the study as JSON) or a path to a study file. Bad input throws SceneError.
Study to_study(const py::object& study);

// One long library call: run() releases the GIL around it; callback() is the library's
// ProgressCallback, which takes the GIL, checks for signals (KeyboardInterrupt) and calls the
// user's progress(fraction) if given, and cancels the run on a Python exception, which run()
// raises once the library has returned.
class Call {
public:
    explicit Call(py::object progress = py::none()) : m_progress(std::move(progress)) {}
    [[nodiscard]] ProgressCallback callback();
    template <class F>
    auto run(F&& body) {
        auto result = [&] {
            py::gil_scoped_release release;
            return body();
        }();
        if (m_error) throw std::move(*m_error);
        return result;
    }
    // As run(body), returning to_python(result). Where a Python exception cancelled the run
    // (KeyboardInterrupt, or one progress raised), what it had done, to_python(result) (its
    // "cancelled" true), is set as the exception's `partial` attribute before it is raised: an
    // interrupted diagram lost every row it had finished.
    template <class F, class Convert>
    py::dict run(F&& body, Convert&& to_python) {
        auto result = [&] {
            py::gil_scoped_release release;
            return body();
        }();
        if (!m_error) return to_python(result);
        keep_partial([&] { return py::object(to_python(result)); });
        throw std::move(*m_error);
    }

private:
    // Sets m_error's `partial` attribute to partial(); a conversion that fails leaves the
    // exception as it was (the interruption, not the conversion, is what the caller sees).
    void keep_partial(const std::function<py::object()>& partial);
    py::object m_progress;
    std::optional<py::error_already_set> m_error;
};

// The index of value among names (a keyword's choices, for enums the library has no parser
// for); std::invalid_argument naming the keyword otherwise.
int choice(const std::string& value, const std::string& keyword,
           const std::vector<std::string>& names);

// 1-D float64 array of values.
py::array_t<double> array(const std::vector<double>& values);
// rows x cols float64 array of row-major data.
py::array_t<double> matrix(const std::vector<double>& data, std::size_t rows, std::size_t cols);

// One column of a table: field(item) of every item, as a 1-D array of R.
template <class R, class T, class F>
py::array_t<R> column(const std::vector<T>& items, F field) {
    py::array_t<R> out(static_cast<py::ssize_t>(items.size()));
    auto view = out.template mutable_unchecked<1>();
    for (std::size_t i = 0; i < items.size(); ++i)
        view(static_cast<py::ssize_t>(i)) = static_cast<R>(field(items[i]));
    return out;
}

// One column of strings (a NumPy array of str).
template <class T, class F>
py::array strings(const std::vector<T>& items, F field) {
    py::list out;
    for (const auto& item : items)
        out.append(py::str(std::string(field(item))));
    return py::module_::import("numpy").attr("array")(out, py::arg("dtype") = "str");
}

// Contact maxima as a dict of arrays force, time, impacts (one entry per contact j = 0..Nm).
py::dict per_contact_dict(const std::vector<ContactMaximum>& contacts);

// The run options of a scene as a dict (periods, transient_periods, scheme, tolerance), for
// results to say how they were made.
py::dict run_dict(const Scene& scene);

// Registration of each group of functions (one source file each).
// The attractor search of simulate(attractors=N) and classify(attractors=N), checked before the
// run: each start runs as run; function names the caller in messages. Unused where attractors
// is 0, and then no seed, box or threads may be given.
AttractorOptions design_search(const Scene& scene, const RunOptions& run,
                               const std::string& function, long attractors,
                               std::optional<std::uint64_t> seed, std::optional<double> box,
                               std::optional<int> threads);

void register_simulate(py::module_& m);
void register_analyses(py::module_& m);
void register_regimes(py::module_& m);
void register_orbits(py::module_& m);
void register_attractors(py::module_& m);

} // namespace gapchain::python
