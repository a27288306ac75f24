#pragma once
/// @file
/// The printer as planners and the exposure engine need it: the process (laser scanning or mask
/// projection), the layer thickness and the light source. Read from a job's `machine` section.
/// Units: mm, mW.

#include <memory>
#include <string>

#include "vpsim/plan/grey_levels.h"
#include "vpsim/plan/machine/scanner.h"

namespace vpsim {
class ConfigNode;
}

namespace vpsim::plan {

enum class Process { Laser, Dlp };

/// "laser" or "dlp".
std::string processName(Process process);
/// @throw InputError for another name
Process processFromName(const std::string& name);

struct Machine {
    Process process = Process::Laser;
    double layerThickness = 0.05;  ///< mm
    /// mW (SLA): the laser's full power, the most a plan may use (`laser_power`)
    double laserPower = 10.0;
    /// mW: the least power the laser runs at stably when on (`laser_power_min`, default 0: any
    /// power down to nothing); plans use powers in [laserPowerMin, laserPower]
    double laserPowerMin = 0.0;
    /// mm: the 1/e^2 intensity radius W0 of the focused laser beam, or the projector's blur
    /// radius at the resin (DLP)
    double beamRadius = 0.05;
    double pixelPitch = 0.0625;  ///< mm (DLP projector pixel at the resin)
    /// DLP: the projector's grey-level calibration ("grey_levels" + "exposure_time"), or null
    std::shared_ptr<const GreyLevels> greyLevels;
    /// `scanner`: kinematic limits and delays of the galvanometer scanner (laser build time)
    ScannerConfig scanner;
    double recoatTime = 0;           ///< s per layer (`recoat_time`, default 0)
    double projectorIrradiance = 0;  ///< mW/mm^2 at the resin (`projector_irradiance`, DLP)
};

/// Reads a job's `machine` section: "process" (laser | dlp, default laser), "layer_thickness"
/// (default 50 um); laser: "laser_power" (10 mW, the full power), "laser_power_min" (0 mW, at
/// most laser_power), "beam_radius" (50 um); DLP: "pixel_pitch"
/// (62.5 um), "blur_radius" (20 um), optional "grey_levels" with "exposure_time" (grey_levels.h).
/// @throw InputError naming the file and key
Machine machineFromConfig(const ConfigNode& section);

}  // namespace vpsim::plan
