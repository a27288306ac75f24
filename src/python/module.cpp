// The compiled half of the `vpsim` Python package (vpsim/__init__.py is the other): one bind_*
// file per stage. Functions here take plain arguments; the package's frontend fills the CLI's
// defaults from the environment.
#include <future>

#include <tbb/task_arena.h>

#include "bind_common.h"
#include "vpsim/core/progress.h"

namespace {

/// A Progress advanced and finished on a TBB worker thread (an enqueued arena task runs on a
/// worker, never on the caller): the test of the callback's GIL handling from threads Python
/// did not create, independent of how a parallel loop happens to share its work.
void progressOnTbbWorker(const pybind11::object& progress, int steps) {
    vpsim::python::withoutGil(progress, [steps] {
        tbb::task_arena arena;
        std::promise<void> finished;
        arena.enqueue([&] {
            vpsim::Progress bar("progress check on a TBB worker", uint64_t(steps));
            for (int i = 0; i < steps; ++i) bar.advance();
            bar.finish();
            finished.set_value();
        });
        finished.get_future().wait();
    });
}

}  // namespace

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
    m.def("_progress_on_tbb_worker", &progressOnTbbWorker, pybind11::arg("progress"),
          pybind11::arg("steps") = 3, "test hook: a Progress advanced on a TBB worker thread");
    m.def("_release_contexts", &releaseContexts, "drop the kept Vulkan contexts (atexit)");
}
