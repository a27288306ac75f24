#include "vpsim/plan/scan_plan.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim::plan {
namespace {

double positive(const ConfigNode& node, const std::string& key, Dimension dimension) {
    double value = node.quantity(key, dimension);
    if (!(value > 0)) throw node.error(key, "must be positive");
    return value;
}

double nonNegative(const ConfigNode& node, const std::string& key, Dimension dimension) {
    double value = node.quantity(key, dimension);
    if (!(value >= 0)) throw node.error(key, "must not be negative");
    return value;
}

MaskImage maskFromConfig(const ConfigNode& node) {
    MaskImage mask;
    mask.width = int(node.integer("width"));
    mask.height = int(node.integer("height"));
    if (mask.width <= 0 || mask.height <= 0)
        throw node.error("width", "mask size must be positive");
    mask.originX = node.quantity("origin_x", dim::LENGTH);
    mask.originY = node.quantity("origin_y", dim::LENGTH);
    mask.pixelPitch = positive(node, "pixel_pitch", dim::LENGTH);
    const nlohmann::json& dose = node.raw("dose_mJ_per_mm2");
    if (!dose.is_array() || dose.size() != size_t(mask.width) * mask.height)
        throw node.error("dose_mJ_per_mm2", "expected width*height numbers");
    for (const auto& value : dose) {
        if (!value.is_number() || !(value.get<double>() >= 0))
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

nlohmann::json toJson(const ScanPlan& plan) {
    nlohmann::json layers = nlohmann::json::array();
    for (const auto& layer : plan.layers) {
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
        layers.push_back(std::move(entry));
    }
    return {{"units", "mm, s, mW, mJ"},
            {"machine",
             {{"process", processName(plan.machine.process)},
              {"layer_thickness", plan.machine.layerThickness},
              {"laser_power", plan.machine.laserPower},
              {"beam_radius", plan.machine.beamRadius},
              {"pixel_pitch", plan.machine.pixelPitch}}},
            {"layers", layers}};
}

ScanPlan scanPlanFromJson(const nlohmann::json& json, const std::string& file) {
    ConfigNode root(json, file);
    root.string("units", std::string("mm, s, mW, mJ"));
    ScanPlan plan;
    ConfigNode machine = root.child("machine");
    plan.machine.process =
        processFromName(machine.choice("process", {"laser", "dlp"}, std::string("laser")));
    plan.machine.layerThickness = positive(machine, "layer_thickness", dim::LENGTH);
    plan.machine.laserPower = nonNegative(machine, "laser_power", dim::POWER);
    plan.machine.beamRadius = positive(machine, "beam_radius", dim::LENGTH);
    plan.machine.pixelPitch = positive(machine, "pixel_pitch", dim::LENGTH);
    for (const ConfigNode& node : root.children("layers")) {
        LayerPlan layer;
        layer.z = node.quantity("z", dim::LENGTH);
        for (const auto& p : node.raw("points_x_y_energy")) {
            if (!p.is_array() || p.size() != 3 || !(p[2].get<double>() >= 0))
                throw node.error("points_x_y_energy", "each point is [x, y, energy >= 0]");
            layer.points.push_back({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
        }
        for (const auto& v : node.raw("vectors_x0_y0_x1_y1_power_speed")) {
            if (!v.is_array() || v.size() != 6 || !(v[4].get<double>() >= 0) ||
                !(v[5].get<double>() > 0))
                throw node.error("vectors_x0_y0_x1_y1_power_speed",
                                 "each vector is [x0, y0, x1, y1, power >= 0, speed > 0]");
            layer.vectors.push_back({v[0].get<double>(), v[1].get<double>(), v[2].get<double>(),
                                     v[3].get<double>(), v[4].get<double>(), v[5].get<double>()});
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
    writeFileAtomic(path, toJson(plan).dump(1));
}

ScanPlan loadScanPlan(const std::string& path) {
    try {
        return scanPlanFromJson(loadJsonFile(path), path);
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed scan plan: ") + e.what(), path);
    }
}

}  // namespace vpsim::plan
