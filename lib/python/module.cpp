// The Python module gapchain._gapchain: the library in-process (gapchain/__init__.py imports
// it). Each group of functions registers itself from its own source file.
#include "call.hpp"

PYBIND11_MODULE(_gapchain, m) {
    // Each docstring starts with the call as the README writes it (keyword defaults, **keys).
    pybind11::options options;
    options.disable_function_signatures();
    m.doc() = "gapchain's compiled library functions (use the package gapchain).";
    m.attr("__version__") = GAPCHAIN_VERSION;
    gapchain::python::register_simulate(m);
    gapchain::python::register_analyses(m);
    gapchain::python::register_regimes(m);
    gapchain::python::register_orbits(m);
    gapchain::python::register_attractors(m);
}
