// vpsim.expose, vpsim.cure, vpsim.validate: the exposure of a job's plan as a 3D float32 array
// in C order with axes (x, y, z), so that array[ix, iy, iz] is exposure.vdb's voxel (ix, iy, iz)
// (cell corner origin + (ix pitch, iy pitch, iz h), h the voxel slice height), filled by the
// engine straight into numpy's buffer; beyond a memory bound, a stream of (x, y) slices instead.
#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <thread>

#include "bind_plan.h"
#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/text.h"
#include "vpsim/cure/cure_field.h"
#include "vpsim/gpu/context.h"
#include "vpsim/validate/slice_validator.h"

namespace vpsim::python {
namespace {

/// Everything an exposure needs, made without the GIL.
struct Prepared {
    JobFront front;
    plan::ScanPlan plan;
    nlohmann::json plannerSummary = nlohmann::json::object();
    std::string strategy;
    exposure::ExposureGrid grid;
    std::unique_ptr<exposure::ExposureModel> model;
    double voxelHeight = 0, criticalDose = 0;
    int layers = 0;
    std::string backend;
};

/// The voxel index of a slice, as DoseVolume::add places it (zBottom 0).
int sliceIndex(const exposure::ExposureSlice& s, double h) {
    return int(std::lround(s.z / h - 0.5));
}

py::dict gridDict(const Prepared& p) {
    py::dict g;
    g["nx"] = p.grid.nx;
    g["ny"] = p.grid.ny;
    g["nz"] = p.layers * p.grid.slicesPerLayer;
    g["origin"] = py::make_tuple(p.grid.originX, p.grid.originY, 0.0);
    g["voxel_size"] = py::make_tuple(p.grid.pitch, p.grid.pitch, p.voxelHeight);
    g["slices_per_layer"] = p.grid.slicesPerLayer;
    g["layers"] = p.layers;
    g["layer_thickness"] = p.voxelHeight * p.grid.slicesPerLayer;
    return g;
}

/// Streams the slices of an exposure too large for one array: the engine runs on its own
/// thread and waits while two slices are not yet taken.
class SliceStream {
public:
    explicit SliceStream(std::shared_ptr<Prepared> p) : mPrepared(std::move(p)) {}
    ~SliceStream() { close(); }

    py::dict next() {
        if (!mStarted) start();
        Item item;
        {
            py::gil_scoped_release release;
            std::unique_lock<std::mutex> lock(mMutex);
            mReady.wait(lock, [&] { return !mQueue.empty() || mDone; });
            if (!mQueue.empty()) {
                item = std::move(mQueue.front());
                mQueue.pop_front();
                mReady.notify_all();
            }
        }
        if (item.values.empty()) {
            if (mError) std::rethrow_exception(std::exchange(mError, nullptr));
            throw py::stop_iteration();
        }
        const Prepared& p = *mPrepared;
        py::dict out;
        out["index"] = item.index;
        out["layer"] = item.layer;
        out["slice"] = item.slice;
        out["z"] = item.z;
        out["values"] = ownedArray(std::move(item.values), {p.grid.nx, p.grid.ny});
        return out;
    }

    void close() {
        {
            std::lock_guard<std::mutex> lock(mMutex);
            mCancelled = true;
            mReady.notify_all();
        }
        if (mThread.joinable()) {
            py::gil_scoped_release release;
            mThread.join();
        }
    }

    const Prepared& prepared() const { return *mPrepared; }

private:
    struct Item {
        int index = 0, layer = 0, slice = 0;
        double z = 0;
        std::vector<float> values;  ///< array[ix, iy]
    };
    struct Cancelled {};

    void start() {
        mStarted = true;
        mThread = std::thread([this] {
            try {
                Prepared& p = *mPrepared;
                p.model->run(p.plan, [&](const exposure::ExposureSlice& s) { push(s); });
            } catch (const Cancelled&) {
            } catch (...) {
                mError = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mMutex);
            mDone = true;
            mReady.notify_all();
        });
    }

    void push(const exposure::ExposureSlice& s) {
        const exposure::SurfaceGrid& g = *s.values;
        Item item{sliceIndex(s, mPrepared->voxelHeight), s.layer, s.slice, s.z,
                  std::vector<float>(g.values.size())};
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) item.values[size_t(i) * g.ny + j] = g.at(i, j);
        std::unique_lock<std::mutex> lock(mMutex);
        mReady.wait(lock, [&] { return mQueue.size() < 2 || mCancelled; });
        if (mCancelled) throw Cancelled{};
        mQueue.push_back(std::move(item));
        mReady.notify_all();
    }

    std::shared_ptr<Prepared> mPrepared;
    std::thread mThread;
    std::mutex mMutex;
    std::condition_variable mReady;
    std::deque<Item> mQueue;
    bool mStarted = false, mDone = false, mCancelled = false;
    std::exception_ptr mError;
};

std::shared_ptr<Prepared> prepare(const py::handle& jobArg, const std::string& baseDir,
                                  const std::vector<std::string>& overrides, const py::handle& part,
                                  const py::handle& planArg, const py::dict& settings,
                                  const py::object& progress) {
    auto job = std::make_shared<pipeline::Job>(loadJob(jobArg, baseDir, overrides, part));
    const RunContext context = runContext(settingsFrom(settings));
    const PlanObject* given = planArg.is_none() ? nullptr : &planArg.cast<const PlanObject&>();
    return withoutGil(progress, [&] {
        auto p = std::make_shared<Prepared>();
        p->front = jobFront(*job, context, false, given != nullptr);
        JobFront& f = p->front;
        if (given) {
            pipeline::checkPlanFitsJob(given->plan, *job, f.layers, "plan");
            p->plan = given->plan;
            p->strategy = given->strategy;
        } else {
            pipeline::PlanResult planned =
                pipeline::planStage(*job, f.layers, f.bounds, f.beam, context);
            p->plan = std::move(planned.plan);
            p->plannerSummary = std::move(planned.summary);
            p->strategy = job->strategy;
        }
        pipeline::scanStage(*job, f.layers, p->plan);
        p->grid = pipeline::exposureGrid(*job, f.bounds, f.beam);
        p->model = pipeline::exposureModel(*job, p->grid, f.beam, context);
        p->layers = int(f.layers.layers.size());
        p->voxelHeight = job->machine.layerThickness / job->simulation.slicesPerLayer;
        p->criticalDose = job->cure->criticalDose();
        p->backend = p->model->usesGpu() && context.gpu ? context.gpu->info().name : "cpu";
        return p;
    });
}

py::dict describe(const Prepared& p) {
    py::dict out;
    out["grid"] = gridDict(p);
    out["model"] = p.model->name();
    out["backend"] = p.backend;
    out["critical_dose"] = p.criticalDose;
    out["vdb_threshold"] = float(0.02 * p.criticalDose);  // what `vpsim run` leaves out of the .vdb
    out["beam"] = fromJson(p.front.beam.beam.toJson());
    out["kept_energy_fraction"] = p.model->keptEnergyFraction();
    out["plan"] = py::cast(PlanObject{p.plan, p.plannerSummary, p.strategy});
    return out;
}

py::dict expose(const py::handle& job, const std::string& baseDir,
                const std::vector<std::string>& overrides, const py::handle& part,
                const py::handle& planArg, double maxBytes, const py::dict& settings,
                const py::object& progress) {
    std::shared_ptr<Prepared> p =
        prepare(job, baseDir, overrides, part, planArg, settings, progress);
    py::dict out = describe(*p);
    const size_t nx = size_t(p->grid.nx), ny = size_t(p->grid.ny),
                 nz = size_t(p->layers) * size_t(p->grid.slicesPerLayer);
    const double bytes = double(nx) * double(ny) * double(nz) * sizeof(float);
    if (bytes > maxBytes) {
        out["slices"] = py::cast(std::make_unique<SliceStream>(p));
        return out;
    }
    checkMemory(RunContext{}, bytes, "the exposure array",
                "give max_bytes below it to stream slices");
    py::array_t<float> array({py::ssize_t(nx), py::ssize_t(ny), py::ssize_t(nz)});
    float* data = array.mutable_data();
    const double h = p->voxelHeight;
    const double seconds = withoutGil(progress, [&] {
        std::memset(data, 0, size_t(bytes));
        return p->model->run(p->plan, [&](const exposure::ExposureSlice& s) {
            const int k = sliceIndex(s, h);
            if (k < 0 || size_t(k) >= nz)
                throw ResourceError("exposure slice at z = " + formatQuantity(s.z) +
                                    " mm lies outside the array");
            const exposure::SurfaceGrid& g = *s.values;
            for (size_t i = 0; i < nx; ++i) {
                float* column = data + i * ny * nz + size_t(k);
                for (size_t j = 0; j < ny; ++j) column[j * nz] = g.values[j * nx + i];
            }
        });
    });
    out["array"] = array;
    out["engine_seconds"] = seconds;
    return out;
}

cure::CureLaw* lawFrom(const py::handle& law, std::unique_ptr<cure::CureLaw>& owner) {
    const nlohmann::json section = toJson(law, "<cure dict>");
    owner = cure::cureLawFromJson(builtins().cureLaws, section, "<cure dict>", "cure");
    return owner.get();
}

py::dict cure(const py::handle& law,
              const py::array_t<float, py::array::c_style | py::array::forcecast>& dose) {
    std::unique_ptr<cure::CureLaw> owner;
    const cure::CureLaw& l = *lawFrom(law, owner);
    std::vector<py::ssize_t> shape(dose.shape(), dose.shape() + dose.ndim());
    py::array_t<uint8_t> cured(shape);
    py::dict out;
    const float* in = dose.data();
    const size_t count = size_t(dose.size());
    uint8_t* mask = cured.mutable_data();
    {
        py::gil_scoped_release release;
        cure::cureMask(l, in, count, mask);
    }
    out["cured"] = cured;
    if (l.hasConversion()) {
        py::array_t<float> conversion(shape);
        float* c = conversion.mutable_data();
        {
            py::gil_scoped_release release;
            cure::conversionField(l, in, count, c);
        }
        out["conversion"] = conversion;
    }
    out["critical_dose"] = l.criticalDose();
    out["law"] = fromJson(l.toJson());
    return out;
}

py::dict validateExposure(const py::handle& jobArg, const std::string& baseDir,
                          const std::vector<std::string>& overrides, const py::handle& part,
                          const py::array_t<float, py::array::c_style | py::array::forcecast>& a,
                          const py::dict& grid, const py::object& progress) {
    const pipeline::Job job = loadJob(jobArg, baseDir, overrides, part);
    exposure::ExposureGrid g;
    g.nx = grid["nx"].cast<int>();
    g.ny = grid["ny"].cast<int>();
    const auto origin = grid["origin"].cast<std::vector<double>>();
    const auto voxel = grid["voxel_size"].cast<std::vector<double>>();
    g.originX = origin.at(0);
    g.originY = origin.at(1);
    g.pitch = voxel.at(0);
    g.slicesPerLayer = grid["slices_per_layer"].cast<int>();
    const double h = voxel.at(2);
    if (a.ndim() != 3 || a.shape(0) != g.nx || a.shape(1) != g.ny)
        throw InputError("the exposure array does not match its grid", "", "exposure");
    const int nz = int(a.shape(2));
    if (nz % g.slicesPerLayer != 0)
        throw InputError("the exposure's slices are not whole layers", "", "exposure");
    const float* data = a.data();
    nlohmann::json summary = withoutGil(progress, [&] {
        const geometry::Mesh mesh = pipeline::partStage(job);
        validate::SliceValidator validator(mesh, g, *job.cure, h);
        exposure::SurfaceGrid slice = g.surface();
        const int n = g.slicesPerLayer;
        for (int k = nz - 1; k >= 0; --k) {  // top down, as the engine emits them
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i)
                    slice.at(i, j) = data[(size_t(i) * g.ny + j) * nz + k];
            exposure::ExposureSlice s;
            s.layer = k / n;
            s.slice = n - 1 - k % n;
            s.z = (k + 0.5) * h;
            s.values = &slice;
            validator.add(s);
        }
        return validator.summary().toJson();
    });
    py::dict out = fromJson(summary);
    return out;
}

}  // namespace

void bindExposure(py::module_& m) {
    py::class_<SliceStream>(m, "ExposureSlices",
                            "The exposure slice by slice, top layer first: each item a dict "
                            "{index (iz), layer, slice (0 = top of the layer), z (mm, centre), "
                            "values (mJ/mm^2, array[ix, iy])}")
        .def("__iter__", [](py::object self) { return self; })
        .def("__next__", &SliceStream::next)
        .def("close", &SliceStream::close, "stops the engine (also when the iterator goes)");
    m.def("_expose", &expose, py::arg("job"), py::arg("base_dir"), py::arg("overrides"),
          py::arg("part"), py::arg("plan"), py::arg("max_bytes"), py::arg("settings"),
          py::arg("progress"));
    m.def("_cure", &cure, py::arg("law"), py::arg("dose"));
    m.def("_validate", &validateExposure, py::arg("job"), py::arg("base_dir"), py::arg("overrides"),
          py::arg("part"), py::arg("array"), py::arg("grid"), py::arg("progress"));
}

}  // namespace vpsim::python
