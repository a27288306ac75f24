#include "vpsim/plan/machine/machine.h"

#include "vpsim/core/checks.h"
#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim::plan {

std::string processName(Process process) {
    return process == Process::Dlp ? "dlp" : "laser";
}

Process processFromName(const std::string& name) {
    if (name == "laser") return Process::Laser;
    if (name == "dlp") return Process::Dlp;
    throw InputError("unknown process '" + name + "' (known: laser, dlp)");
}

Machine machineFromConfig(const ConfigNode& section) {
    Machine machine;
    machine.process =
        processFromName(section.choice("process", {"laser", "dlp"}, std::string("laser")));
    machine.layerThickness = positiveQuantity(section, "layer_thickness", dim::LENGTH, 0.05);
    if (machine.process == Process::Laser) {
        machine.laserPower = positiveQuantity(section, "laser_power", dim::POWER, 10.0);
        machine.laserPowerMin = section.quantity("laser_power_min", dim::POWER, 0.0);
        if (!(machine.laserPowerMin >= 0) || !(machine.laserPowerMin <= machine.laserPower))
            throw section.error("laser_power_min", "must lie between 0 and laser_power (" +
                                                       formatQuantity(machine.laserPower) + " mW)");
        machine.beamRadius = positiveQuantity(section, "beam_radius", dim::LENGTH, 0.05);
    } else {
        machine.pixelPitch = positiveQuantity(section, "pixel_pitch", dim::LENGTH, 0.0625);
        machine.beamRadius = positiveQuantity(section, "blur_radius", dim::LENGTH, 0.02);
        if (section.has("grey_levels"))
            machine.greyLevels = std::make_shared<const GreyLevels>(greyLevelsFromConfig(section));
    }
    if (section.has("scanner")) machine.scanner = scannerFromConfig(section.child("scanner"));
    machine.recoatTime = section.quantity("recoat_time", dim::TIME, 0.0);
    if (!(machine.recoatTime >= 0)) throw section.error("recoat_time", "must not be negative");
    machine.projectorIrradiance = section.quantity("projector_irradiance", dim::IRRADIANCE, 0.0);
    if (!(machine.projectorIrradiance >= 0))
        throw section.error("projector_irradiance", "must not be negative");
    return machine;
}

}  // namespace vpsim::plan
