#pragma once
// Shared by the bind_*.cpp files of the `_vpsim` extension: JSON <-> Python conversion, quantities
// with units, the run context from the frontend's settings, the progress callback, numpy helpers.
// The frontend (vpsim/__init__.py) reads the environment and passes plain arguments in.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/run_context.h"
#include "vpsim/core/units.h"
#include "vpsim/pipeline/builtins.h"
#include "vpsim/pipeline/job.h"

namespace py = pybind11;

namespace vpsim::python {

/// A Python value (dict, list, tuple, str, int, float, bool, None, numpy arrays and scalars,
/// os.PathLike) as JSON, at most MAX_JSON_DEPTH deep. @throw InputError naming `what`
nlohmann::json toJson(const py::handle& value, const std::string& what = "value");
/// JSON as Python dicts, lists and scalars.
py::object fromJson(const nlohmann::json& value);

/// A number in base units, or a string with units ("50 um"). @throw InputError naming `key`
double quantity(const py::handle& value, Dimension dimension, const std::string& key);

/// A number (base units, or a count) or a string with units as text, as the library's
/// argument structs (transport::McArguments, kernel::KernelArguments) take them: numbers are
/// written with all 17 digits. @throw InputError naming `key` for anything else
std::string argumentText(const py::handle& value, const std::string& key);

/// The settings the frontend passes to every call that may run physics.
struct Settings {
    std::string backend = "auto";  ///< auto | vulkan | cpu
    std::string device;            ///< Vulkan device index or name part
    std::string cacheDirectory;    ///< beam-kernel cache ("" disables)
    bool validation = false;
};
/// The run context of `settings`: its Vulkan context is made once per (backend, device) and
/// kept until releaseContexts().
RunContext runContext(const Settings& settings);
/// Drops the kept Vulkan contexts (atexit, before the interpreter goes).
void releaseContexts();
/// Settings from the keyword arguments every physics call takes.
Settings settingsFrom(const py::dict& options);

/// The builtins (every registered planner, cure law, exporter), made once.
const pipeline::Builtins& builtins();

/// A part from an STL path or (vertices (N, 3) mm, triangles (M, 3)) arrays; the arrays are
/// checked and repaired as readStl() does an STL file's triangles.
/// @throw InputError naming the file or the key "part"
geometry::Mesh partMesh(const py::handle& part, double scale = 1.0);

/// A job from a path or a dict (`baseDir` resolves a dict's relative paths; "" = the working
/// directory), with `overrides` ("key.path=value") applied first; `part` (None, or vertex and
/// triangle arrays) replaces the job's part section, which must then be absent.
pipeline::Job loadJob(const py::handle& job, const std::string& baseDir,
                      const std::vector<std::string>& overrides,
                      const py::handle& part = py::none());

/// While alive, vpsim's Progress reports go to `callback(label, done, total)` (None: nowhere),
/// called with the GIL held from whichever thread advances; an exception the callback raises
/// is kept and raised by check() once the work has returned.
class ProgressScope {
public:
    explicit ProgressScope(py::object callback);
    ~ProgressScope();
    /// Raises the callback's exception, if it raised one.
    void check();

private:
    struct State;
    std::shared_ptr<State> mState;
};

/// Runs `work` without the GIL, under the progress callback, then raises the callback's
/// exception if any.
template <class Work>
auto withoutGil(const py::object& progress, Work&& work) {
    ProgressScope scope(progress);
    if constexpr (std::is_void_v<decltype(work())>) {
        {
            py::gil_scoped_release release;
            work();
        }
        scope.check();
    } else {
        decltype(work()) result = [&] {
            py::gil_scoped_release release;
            return work();
        }();
        scope.check();
        return result;
    }
}

/// A numpy array that owns `data` (moved into a capsule: no copy), with `shape` and strides in
/// elements (C order when `strides` is empty).
template <class T>
py::array_t<T> ownedArray(std::vector<T>&& data, std::vector<py::ssize_t> shape,
                          std::vector<py::ssize_t> strides = {}) {
    auto* owner = new std::vector<T>(std::move(data));
    py::capsule capsule(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    if (strides.empty()) return py::array_t<T>(shape, owner->data(), capsule);
    for (auto& s : strides) s *= py::ssize_t(sizeof(T));
    return py::array_t<T>(shape, strides, owner->data(), capsule);
}

void bindErrors(py::module_& m);
void bindOptics(py::module_& m);
void bindKernel(py::module_& m);
void bindGeometry(py::module_& m);
void bindPlan(py::module_& m);
void bindExposure(py::module_& m);
void bindRun(py::module_& m);
void bindComponents(py::module_& m);
void bindComponentsVdb(py::module_& m);

}  // namespace vpsim::python
