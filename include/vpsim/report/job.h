#pragma once
/// @file
/// A job file: material, cure law, part, machine, beam kernel, plan strategy and simulation grid
/// for `vpsim run`. Paths inside are relative to the job file. Example: examples/default.json;
/// every key is listed in examples/README.md.

#include <optional>
#include <string>
#include <vector>

#include "vpsim/cure/cure_model.h"
#include "vpsim/geometry/test_parts.h"
#include "vpsim/validate/feature_probe.h"

namespace vpsim::report {

enum class Process { Laser, Dlp };
enum class KernelSource { MonteCarlo, Given };
enum class PlanStrategy { Aces, UniformMask };

struct Job {
    std::string file;  ///< the job file itself
    std::string name;

    std::string materialFile;  ///< optics material (resolved path); "" when the kernel is given
    cure::CureModel cure = cure::CureModel::threshold(0.1);

    std::string partStl;  ///< resolved STL path, or "" for a test part
    double partScale = 1.0;
    std::string testPart;  ///< test part name when partStl is ""
    geometry::TestPartOptions testPartOptions;

    Process process = Process::Laser;
    double layerThickness = 0.05;  ///< mm
    double laserPower = 10.0;      ///< mW
    double beamRadius = 0.05;      ///< W0, mm (laser) or projector blur radius (DLP), mm
    double pixelPitch = 0.0625;    ///< mm (DLP)

    KernelSource kernelSource = KernelSource::MonteCarlo;
    bool tabulatedKernel = false;  ///< expose with the Monte Carlo table instead of the Eq. 12 fit
    uint64_t photons = 300000;
    uint32_t seed = 1;
    double givenWe3d = 0.05, givenDe3d = 0.1, givenZmax = 0.0, givenEfficiency = 1.0;  ///< mm, -

    PlanStrategy strategy = PlanStrategy::Aces;
    double homogeneity = 0.01;    ///< ACES Srlt
    bool edgeFivePercent = true;  ///< ACES edge rule (seed App. A) or cure-at-contour
    double maskDose = 0.78;       ///< mJ/mm^2 per layer (uniform masks)
    bool greyscaleMask = false;

    double voxel = 0.01;  ///< mm, x-y cell size of the simulation
    int slicesPerLayer = 5;
    double margin = -1;  ///< mm around the part; < 0: 3 beam radii
    bool writeVdb = true;

    std::vector<validate::FeatureProbe> features;  ///< Z dimensions to measure (seed 001 Table 2)
};

/// Reads and checks a job file (unknown keys, units, ranges, referenced files).
/// @throw InputError naming the file and key
Job loadJob(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace vpsim::report
