#pragma once
/// @file
/// A job file: material, cure law, part, machine, beam kernel, plan strategy and simulation grid
/// for `vpsim plan` and `vpsim run`. Paths inside are relative to the job file. Example:
/// examples/default.json; every key is listed in examples/README.md.
///
/// The job owns only its top-level keys; each section is parsed and checked by the component
/// that owns it (geometry: part; plan: machine and the planner created by name from `plan`;
/// kernel: kernel; cure: the cure law created by name; validate: features), and unknown keys
/// anywhere stay errors that name the file and key.

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "vpsim/core/config.h"
#include "vpsim/cure/cure_law.h"
#include "vpsim/exporters/exporter.h"
#include "vpsim/geometry/part_spec.h"
#include "vpsim/kernel/kernel_spec.h"
#include "vpsim/pipeline/builtins.h"
#include "vpsim/plan/machine/machine.h"
#include "vpsim/plan/machine/part_order.h"
#include "vpsim/planners/planner.h"
#include "vpsim/validate/feature_probe.h"

namespace vpsim::pipeline {

/// The `simulation` section: the grid the exposure is computed on.
struct SimulationSpec {
    double voxel = 0.01;     ///< mm, x-y cell size
    int slicesPerLayer = 5;  ///< voxel slices per layer (1 .. 100)
    double margin = -1;      ///< mm around the part; < 0: 3 beam radii
    bool writeVdb = true;    ///< write exposure.vdb and reference.vdb
    /// mm, the side of an x-y tile's core (simulation.tile); 0: chosen by the estimate to fit
    /// the memory budget (the whole grid in one tile when it fits).
    double tile = 0;
    /// The optional files a run writes (simulation.outputs, from OUTPUT_NAMES); report.json,
    /// index.html, part.stl, the plan and its exports are always written. Default: all, the
    /// .vdb files only with write_vdb (which then follows "exposure.vdb").
    std::set<std::string> outputs{"cured.stl", "exposure.vdb", "reference.vdb", "figures",
                                  "viewer"};
    bool writes(const std::string& output) const { return outputs.count(output) > 0; }
};

/// The names simulation.outputs accepts: cured.stl, exposure.vdb, reference.vdb, figures (the
/// pictures), viewer (the 3D view).
extern const std::vector<std::string> OUTPUT_NAMES;

struct Job {
    std::string file;         ///< the job file itself
    nlohmann::json document;  ///< the job as read, --set overrides applied (report.json's inputs)
    std::string name;
    std::string materialFile;  ///< optics material (resolved path); "" when the kernel is given
    std::unique_ptr<cure::CureLaw> cure;
    geometry::PartSpec part;
    plan::Machine machine;
    kernel::KernelSpec kernel;
    std::string strategy;  ///< the planner's registered name
    std::unique_ptr<planners::Planner> planner;
    SimulationSpec simulation;
    /// How each layer's parts are ordered in the trajectories (the planner's partOrder())
    plan::OrderMethod scanOrder = plan::OrderMethod::Auto;
    std::vector<validate::FeatureProbe> features;  ///< Z dimensions to measure (seed 001 Table 2)
    /// Machine-file exporters run with the job, by name: those named in the `export` section
    /// ({"sl1": {options}, "cli": {}}), or every registered one when it is absent; each writes
    /// the plan when it can express it (a CLI file for laser plans, an SL1 archive for masks).
    std::vector<std::pair<std::string, std::unique_ptr<exporters::Exporter>>> exporters;
};

/// Reads and checks a job file (unknown keys, units, ranges, referenced files), creating its
/// cure law and planner from `builtins`.
/// @param overrides "key.path=value" settings applied before reading (--set)
/// @throw InputError naming the file and key
Job loadJob(const std::string& path, const Builtins& builtins,
            const std::vector<std::string>& overrides = {});
/// The same from a document already read (the Python module's job dicts): `root.file()` names
/// it in messages and its directory resolves the relative paths inside ("" = the working
/// directory). `part`, a mesh made in code (the module's arrays), replaces the part section,
/// which must then be absent. @throw InputError naming root.file() and the key
Job loadJob(const ConfigNode& root, const Builtins& builtins,
            std::shared_ptr<const geometry::Mesh> part = nullptr);

/// The files the job names and a run reads (the material, the part's STL): resolved paths.
std::vector<std::string> jobInputFiles(const Job& job);

}  // namespace vpsim::pipeline
