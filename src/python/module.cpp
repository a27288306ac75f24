// The compiled half of the `vpsim` Python package (vpsim/__init__.py is the other): one bind_*
// file per stage. Functions here take plain arguments; the package's frontend fills the CLI's
// defaults from the environment.
#include "bind_common.h"

PYBIND11_MODULE(_vpsim, m) {
    m.doc() = "vpsim's stages from Python (use the `vpsim` package, not this module)";
    m.attr("__version__") = VPSIM_VERSION;
    using namespace vpsim::python;
    bindErrors(m);
    bindOptics(m);
    bindKernel(m);
    bindGeometry(m);
    bindPlan(m);
    bindExposure(m);
    bindRun(m);
    bindComponents(m);
    bindComponentsVdb(m);
    m.def("_release_contexts", &releaseContexts, "drop the kept Vulkan contexts (atexit)");
}
