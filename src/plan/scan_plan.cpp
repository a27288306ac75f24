#include "vpsim/plan/scan_plan.h"

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "vpsim/core/checks.h"
#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"

namespace vpsim::plan {
namespace {

constexpr long long MAX_MASK_SIDE = 1 << 16;  // pixels; a DLP chip has a few thousand

/// A machine length: positive and at most 10 mm (layers, beams and pixels are microns to a
/// millimetre; larger values are unit mistakes that would make grids of one cell).
double machineLength(const ConfigNode& node, const std::string& key) {
    const double value = positiveQuantity(node, key, dim::LENGTH);
    if (value > 10.0)
        throw node.error(key, "must be at most 10 mm, got " + formatQuantity(value) + " mm");
    return value;
}

double nonNegative(const ConfigNode& node, const std::string& key, Dimension dimension) {
    double value = node.quantity(key, dimension);
    if (!(value >= 0)) throw node.error(key, "must not be negative");
    return value;
}

/// Reads an array of `count` finite numbers ([x, y, energy] ...) or throws naming the key and
/// element; json's own get<double>() would throw a type_error with no file or key.
bool readNumbers(const nlohmann::json& array, size_t count, double* out) {
    if (!array.is_array() || array.size() != count) return false;
    for (size_t i = 0; i < count; ++i) {
        if (!array[i].is_number()) return false;
        out[i] = array[i].get<double>();
        if (!std::isfinite(out[i])) return false;
    }
    return true;
}

int maskSide(const ConfigNode& node, const std::string& key) {
    const long long side = node.integer(key);
    if (side <= 0 || side > MAX_MASK_SIDE)
        throw node.error(key, "mask size must be in [1, " + std::to_string(MAX_MASK_SIDE) +
                                  "] pixels, got " + std::to_string(side));
    return int(side);
}

MaskImage maskFromConfig(const ConfigNode& node) {
    MaskImage mask;
    mask.width = maskSide(node, "width");
    mask.height = maskSide(node, "height");
    mask.originX = node.quantity("origin_x", dim::LENGTH);
    mask.originY = node.quantity("origin_y", dim::LENGTH);
    mask.pixelPitch = positiveQuantity(node, "pixel_pitch", dim::LENGTH);
    const nlohmann::json& dose = node.raw("dose_mJ_per_mm2");
    if (!dose.is_array() || dose.size() != size_t(mask.width) * mask.height)
        throw node.error("dose_mJ_per_mm2", "expected width*height numbers");
    for (const auto& value : dose) {
        if (!value.is_number() || !(value.get<double>() >= 0) ||
            !(value.get<double>() <= double(std::numeric_limits<float>::max())))
            throw node.error("dose_mJ_per_mm2", "doses must be non-negative numbers");
        mask.dose.push_back(value.get<float>());
    }
    return mask;
}

// Trajectory moves as compact rows (a plan may hold millions of them).
const char* const TRAJECTORY_KEY = "trajectory_on_x0_y0_x1_y1_power_speed_dwell_part";

nlohmann::json trajectoryJson(const std::vector<ScanMove>& moves) {
    nlohmann::json rows = nlohmann::json::array();
    for (const ScanMove& m : moves)
        rows.push_back(
            {m.laserOn ? 1 : 0, m.x0, m.y0, m.x1, m.y1, m.power, m.speed, m.dwell, m.part});
    return rows;
}

std::vector<ScanMove> trajectoryFromJson(const ConfigNode& node) {
    std::vector<ScanMove> moves;
    for (const auto& r : node.raw(TRAJECTORY_KEY)) {
        bool ok = r.is_array() && r.size() == 9;
        for (size_t i = 0; ok && i < 9; ++i) ok = r[i].is_number();
        if (!ok || !(r[5].get<double>() >= 0) || !(r[6].get<double>() >= 0) ||
            !(r[7].get<double>() >= 0))
            throw node.error(TRAJECTORY_KEY,
                             "each move is [on 0|1, x0, y0, x1, y1, power >= 0, "
                             "speed >= 0, dwell >= 0, part]");
        ScanMove m;
        m.laserOn = r[0].get<double>() != 0;
        m.x0 = r[1].get<double>(), m.y0 = r[2].get<double>();
        m.x1 = r[3].get<double>(), m.y1 = r[4].get<double>();
        m.power = r[5].get<double>(), m.speed = r[6].get<double>(), m.dwell = r[7].get<double>();
        m.part = r[8].get<int>();
        if (m.laserOn && !(m.speed > 0) && !(m.dwell > 0) && (m.x0 != m.x1 || m.y0 != m.y1))
            throw node.error(TRAJECTORY_KEY, "a mark that moves needs a positive speed");
        moves.push_back(m);
    }
    return moves;
}

}  // namespace

double ScanPlan::totalEnergy() const {
    double energy = 0;
    for (const auto& layer : layers) {
        for (const auto& p : layer.points) energy += p.energy;
        for (const auto& v : layer.vectors)
            energy += v.power * std::hypot(v.x1 - v.x0, v.y1 - v.y0) / v.speed;
        for (const auto& m : layer.masks)
            for (float d : m.dose) energy += double(d) * m.pixelPitch * m.pixelPitch;
    }
    return energy;
}

namespace {

nlohmann::json layerJson(const LayerPlan& layer) {
    nlohmann::json points = nlohmann::json::array(), vectors = nlohmann::json::array(),
                   masks = nlohmann::json::array();
    for (const auto& p : layer.points) points.push_back({p.x, p.y, p.energy});
    for (const auto& v : layer.vectors)
        vectors.push_back({v.x0, v.y0, v.x1, v.y1, v.power, v.speed});
    for (const auto& m : layer.masks)
        masks.push_back({{"width", m.width},
                         {"height", m.height},
                         {"origin_x", m.originX},
                         {"origin_y", m.originY},
                         {"pixel_pitch", m.pixelPitch},
                         {"dose_mJ_per_mm2", m.dose}});
    nlohmann::json entry = {{"z", layer.z},
                            {"points_x_y_energy", points},
                            {"vectors_x0_y0_x1_y1_power_speed", vectors},
                            {"masks", masks}};
    if (!layer.trajectory.empty()) entry[TRAJECTORY_KEY] = trajectoryJson(layer.trajectory);
    return entry;
}

/// The plan without its layers.
nlohmann::json headerJson(const ScanPlan& plan) {
    return {{"units", "mm, s, mW, mJ"},
            {"machine",
             {{"process", processName(plan.machine.process)},
              {"layer_thickness", plan.machine.layerThickness},
              {"laser_power", plan.machine.laserPower},
              {"beam_radius", plan.machine.beamRadius},
              {"pixel_pitch", plan.machine.pixelPitch}}},
            {"layers", nlohmann::json::array()}};
}

}  // namespace

nlohmann::json toJson(const ScanPlan& plan) {
    nlohmann::json json = headerJson(plan);
    for (const auto& layer : plan.layers) json["layers"].push_back(layerJson(layer));
    return json;
}

ScanPlan scanPlanFromJson(const nlohmann::json& json, const std::string& file) {
    ConfigNode root(json, file);
    root.string("units", std::string("mm, s, mW, mJ"));
    ScanPlan plan;
    ConfigNode machine = root.child("machine");
    plan.machine.process =
        processFromName(machine.choice("process", {"laser", "dlp"}, std::string("laser")));
    plan.machine.layerThickness = machineLength(machine, "layer_thickness");
    plan.machine.laserPower = nonNegative(machine, "laser_power", dim::POWER);
    plan.machine.beamRadius = machineLength(machine, "beam_radius");
    plan.machine.pixelPitch = machineLength(machine, "pixel_pitch");
    for (const ConfigNode& node : root.children("layers")) {
        LayerPlan layer;
        layer.z = node.quantity("z", dim::LENGTH);
        const nlohmann::json& points = node.raw("points_x_y_energy");
        if (!points.is_array()) throw node.error("points_x_y_energy", "expected an array");
        for (size_t i = 0; i < points.size(); ++i) {
            double p[3];
            if (!readNumbers(points[i], 3, p) || !(p[2] >= 0))
                throw node.error("points_x_y_energy[" + std::to_string(i) + "]",
                                 "each point is [x, y, energy >= 0]");
            layer.points.push_back({p[0], p[1], p[2]});
        }
        const nlohmann::json& vectors = node.raw("vectors_x0_y0_x1_y1_power_speed");
        if (!vectors.is_array())
            throw node.error("vectors_x0_y0_x1_y1_power_speed", "expected an array");
        for (size_t i = 0; i < vectors.size(); ++i) {
            double v[6];
            if (!readNumbers(vectors[i], 6, v) || !(v[4] >= 0) || !(v[5] > 0))
                throw node.error("vectors_x0_y0_x1_y1_power_speed[" + std::to_string(i) + "]",
                                 "each vector is [x0, y0, x1, y1, power >= 0, speed > 0]");
            layer.vectors.push_back({v[0], v[1], v[2], v[3], v[4], v[5]});
        }
        for (const ConfigNode& mask : node.children("masks"))
            layer.masks.push_back(maskFromConfig(mask));
        if (node.has(TRAJECTORY_KEY)) layer.trajectory = trajectoryFromJson(node);
        plan.layers.push_back(std::move(layer));
    }
    root.checkUnknownKeys();
    return plan;
}

void saveScanPlan(const ScanPlan& plan, const std::string& path) {
    // One layer's JSON tree at a time: the whole plan's tree (about 1.8 kB per laser vector, tens
    // of MB for a DLP plan's masks) would be the largest structure of a large part's run. Each
    // layer is one compact line: indented, a mask's doses or a layer's vectors took one line per
    // number, twice to three times the bytes (68 MB of a 10 mm DLP part's 205 MB of outputs).
    // Parsed, the file is toJson(plan) (keys in nlohmann's sorted order: layers, machine, units).
    Progress progress("plan.json: layers written", plan.layers.size());
    const nlohmann::json header = headerJson(plan);
    writeStreamAtomic(path, [&](std::ostream& out) {
        out << "{\"layers\": [";
        for (size_t k = 0; k < plan.layers.size(); ++k) {
            out << (k ? ",\n" : "\n") << layerJson(plan.layers[k]).dump();
            progress.advance();
        }
        out << (plan.layers.empty() ? "],\n" : "\n],\n");
        out << "\"machine\": " << header["machine"].dump() << ",\n";
        out << "\"units\": " << header["units"].dump() << "}\n";
    });
    progress.finish();
}

ScanPlan loadScanPlan(const std::string& path) {
    try {
        return scanPlanFromJson(loadJsonFile(path), path);
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed scan plan: ") + e.what(), path);
    }
}

ScanPlan emptyPlan(const geometry::LayerStack& layers, const Machine& machine) {
    ScanPlan plan;
    plan.machine = machine;
    for (const geometry::Layer& layer : layers.layers)
        plan.layers.push_back({layer.zBottom + layers.layerThickness, {}, {}, {}, {}});
    return plan;
}

}  // namespace vpsim::plan
