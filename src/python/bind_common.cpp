#include "bind_common.h"

#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"
#include "vpsim/geometry/mesh_check.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/gpu/context.h"

namespace vpsim::python {
namespace {

nlohmann::json toJsonAt(const py::handle& v, const std::string& what, int depth) {
    if (depth > MAX_JSON_DEPTH)
        throw InputError("nested more than " + std::to_string(MAX_JSON_DEPTH) + " deep", what);
    if (v.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
    if (py::isinstance<py::int_>(v)) {
        try {
            return v.cast<long long>();
        } catch (const py::cast_error&) {
            throw InputError("integer out of range", what);
        }
    }
    if (py::isinstance<py::float_>(v)) return v.cast<double>();
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    if (py::hasattr(v, "__fspath__"))
        return py::module_::import("os").attr("fspath")(v).cast<std::string>();
    if (py::isinstance<py::dict>(v)) {
        nlohmann::json out = nlohmann::json::object();
        for (auto item : py::reinterpret_borrow<py::dict>(v)) {
            if (!py::isinstance<py::str>(item.first))
                throw InputError("dict keys must be strings, got " +
                                     quoteUser(py::str(item.first).cast<std::string>()),
                                 what);
            const std::string key = item.first.cast<std::string>();
            out[key] = toJsonAt(item.second, what, depth + 1);
        }
        return out;
    }
    if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
        nlohmann::json out = nlohmann::json::array();
        for (auto item : v) out.push_back(toJsonAt(item, what, depth + 1));
        return out;
    }
    if (py::hasattr(v, "tolist"))  // numpy arrays and scalars
        return toJsonAt(v.attr("tolist")(), what, depth);
    throw InputError("cannot be written as JSON: a " +
                         py::str(v.get_type().attr("__name__")).cast<std::string>(),
                     what);
}

struct ContextCache {
    std::mutex mutex;
    std::map<std::string, std::shared_ptr<gpu::Context>> contexts;
};
ContextCache& contextCache() {
    static ContextCache* cache = new ContextCache;  // never destroyed: released by atexit
    return *cache;
}

}  // namespace

nlohmann::json toJson(const py::handle& value, const std::string& what) {
    return toJsonAt(value, what, 0);
}

py::object fromJson(const nlohmann::json& v) {
    switch (v.type()) {
        case nlohmann::json::value_t::null: return py::none();
        case nlohmann::json::value_t::boolean: return py::bool_(v.get<bool>());
        case nlohmann::json::value_t::number_integer: return py::int_(v.get<long long>());
        case nlohmann::json::value_t::number_unsigned: return py::int_(v.get<unsigned long long>());
        case nlohmann::json::value_t::number_float: return py::float_(v.get<double>());
        case nlohmann::json::value_t::string: return py::str(v.get<std::string>());
        case nlohmann::json::value_t::array: {
            py::list out;
            for (const auto& item : v) out.append(fromJson(item));
            return std::move(out);
        }
        case nlohmann::json::value_t::object: {
            py::dict out;
            for (const auto& [key, item] : v.items()) out[py::str(key)] = fromJson(item);
            return std::move(out);
        }
        default: return py::none();
    }
}

double quantity(const py::handle& value, Dimension dimension, const std::string& key) {
    if (py::isinstance<py::str>(value))
        return parseQuantity(value.cast<std::string>(), dimension, key);
    if (py::isinstance<py::bool_>(value) || value.is_none())
        throw InputError("expected a number or a string with units", "", key);
    try {
        return value.cast<double>();
    } catch (const py::cast_error&) {
        throw InputError("expected a number or a string with units", "", key);
    }
}

std::string argumentText(const py::handle& v, const std::string& key) {
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    if (py::isinstance<py::bool_>(v) || v.is_none())
        throw InputError("expected a number or a string with units", "", key);
    try {
        char text[40];
        std::snprintf(text, sizeof text, "%.17g", v.cast<double>());
        return text;
    } catch (const py::cast_error&) {
        throw InputError("expected a number or a string with units", "", key);
    }
}

Settings settingsFrom(const py::dict& o) {
    Settings s;
    if (o.contains("backend") && !o["backend"].is_none())
        s.backend = o["backend"].cast<std::string>();
    if (o.contains("device") && !o["device"].is_none()) s.device = o["device"].cast<std::string>();
    if (o.contains("cache_dir") && !o["cache_dir"].is_none())
        s.cacheDirectory = o["cache_dir"].cast<std::string>();
    if (o.contains("validation")) s.validation = o["validation"].cast<bool>();
    return s;
}

RunContext runContext(const Settings& settings) {
    const gpu::Backend backend = gpu::parseBackend(settings.backend);
    RunContext context;
    {
        ContextCache& cache = contextCache();
        std::lock_guard<std::mutex> lock(cache.mutex);
        const std::string key =
            settings.backend + "|" + settings.device + "|" + (settings.validation ? "1" : "0");
        auto it = cache.contexts.find(key);
        if (it == cache.contexts.end()) {
            gpu::ContextOptions options;
            options.device = settings.device;
            options.validation = settings.validation;
            it = cache.contexts.emplace(key, gpu::contextForBackend(backend, options)).first;
        }
        context.gpu = it->second;
    }
    context.monteCarloOnCpuDevices = backend == gpu::Backend::Vulkan;
    context.cacheDirectory = settings.cacheDirectory;
    return context;
}

void releaseContexts() {
    ContextCache& cache = contextCache();
    std::lock_guard<std::mutex> lock(cache.mutex);
    cache.contexts.clear();
}

const pipeline::Builtins& builtins() {
    static const pipeline::Builtins* made = new pipeline::Builtins(pipeline::makeBuiltins());
    return *made;
}

geometry::Mesh partMesh(const py::handle& part, double scale) {
    using namespace geometry;
    if (!py::isinstance<py::tuple>(part) && !py::isinstance<py::list>(part))
        return readStl(toJson(part, "part").get<std::string>(), scale);
    auto items = py::reinterpret_borrow<py::sequence>(part);
    if (items.size() != 2)
        throw InputError("expected a path or (vertices (N, 3), triangles (M, 3))", "", "part");
    auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(items[0]);
    auto t = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(items[1]);
    if (!v || v.ndim() != 2 || v.shape(1) != 3)
        throw InputError("vertices: expected an (N, 3) array of mm", "", "part");
    if (!t || t.ndim() != 2 || t.shape(1) != 3)
        throw InputError("triangles: expected an (M, 3) integer array", "", "part");
    // A triangle soup, as an STL file gives readStl, so that checkMesh merges and repairs alike.
    Mesh mesh;
    const double* pv = v.data();
    const long long* pt = t.data();
    for (py::ssize_t i = 0; i < t.shape(0); ++i) {
        std::array<uint32_t, 3> tri{};
        for (int c = 0; c < 3; ++c) {
            const long long index = pt[3 * i + c];
            if (index < 0 || index >= v.shape(0))
                throw InputError("triangles: index " + std::to_string(index) + " of triangle " +
                                     std::to_string(i) + " is out of range",
                                 "", "part");
            const glm::dvec3 p(pv[3 * index], pv[3 * index + 1], pv[3 * index + 2]);
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw InputError("vertices: vertex " + std::to_string(index) + " is not finite", "",
                                 "part");
            tri[c] = uint32_t(mesh.vertices.size());
            mesh.vertices.push_back(p * scale);
        }
        mesh.triangles.push_back(tri);
    }
    if (mesh.triangles.empty()) throw InputError("no triangles", "", "part");
    checkMesh(mesh, "part arrays");
    return mesh;
}

pipeline::Job loadJob(const py::handle& job, const std::string& baseDir,
                      const std::vector<std::string>& overrides, const py::handle& part) {
    std::shared_ptr<const geometry::Mesh> mesh;
    if (!part.is_none()) mesh = std::make_shared<const geometry::Mesh>(partMesh(part));
    if (!py::isinstance<py::dict>(job)) {
        const std::string path = toJson(job, "job").get<std::string>();
        return pipeline::loadJob(ConfigNode::load(path, overrides), builtins(), mesh);
    }
    const std::string file = baseDir.empty() ? "<dict>" : baseDir + "/<dict>";
    nlohmann::json document = toJson(job, file);
    for (const auto& assignment : overrides) applyOverride(document, assignment);
    // Through the text reader, so a dict meets the limits a job file meets.
    ConfigNode root(parseJsonText(document.dump(), file), file);
    return pipeline::loadJob(root, builtins(), mesh);
}

struct ProgressScope::State {
    std::atomic<PyObject*> callback{nullptr};
    std::exception_ptr error;
};

ProgressScope::ProgressScope(py::object callback) : mState(std::make_shared<State>()) {
    if (callback.is_none()) return;
    mState->callback = callback.inc_ref().ptr();
    std::shared_ptr<State> state = mState;
    Progress::setObserver([state](const std::string& label, uint64_t done, uint64_t total) {
        if (!state->callback.load()) return;
        py::gil_scoped_acquire gil;
        PyObject* f = state->callback.load();
        if (!f || state->error) return;
        try {
            py::reinterpret_borrow<py::object>(f)(label, done, total);
        } catch (py::error_already_set&) {
            state->error = std::current_exception();
        }
    });
}

ProgressScope::~ProgressScope() {
    PyObject* f = mState->callback.exchange(nullptr);
    if (!f) return;
    Progress::setObserver(nullptr);
    Py_DECREF(f);  // the caller holds the GIL
}

void ProgressScope::check() {
    if (mState->error) std::rethrow_exception(std::exchange(mState->error, nullptr));
}

}  // namespace vpsim::python
