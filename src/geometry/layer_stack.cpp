#include "vpsim/geometry/layer_stack.h"

#include <cmath>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim::geometry {
namespace {

constexpr const char* FORMAT = "vpsim-layer-stack";
constexpr int VERSION = 1;

nlohmann::json contourJson(const Contour& contour) {
    nlohmann::json points = nlohmann::json::array();
    for (const auto& p : contour) points.push_back({p.x, p.y});
    return points;
}

/// Reads a JSON value that must exist and be a number.
double numberAt(const nlohmann::json& j, const char* key, const std::string& file,
                const std::string& where) {
    if (!j.contains(key) || !j[key].is_number()) {
        throw InputError("missing or non-numeric value", file,
                         where.empty() ? key : where + "." + key);
    }
    return j[key].get<double>();
}

Contour contourFromJson(const nlohmann::json& j, const std::string& file,
                        const std::string& where) {
    if (!j.is_array()) throw InputError("expected an array of [x, y] points", file, where);
    Contour contour;
    for (const auto& p : j) {
        if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
            throw InputError("expected [x, y] numbers", file, where);
        }
        contour.emplace_back(p[0].get<double>(), p[1].get<double>());
        if (!std::isfinite(contour.back().x) || !std::isfinite(contour.back().y)) {
            throw InputError("non-finite coordinate", file, where);
        }
    }
    return contour;
}

}  // namespace

nlohmann::json LayerStack::toJson() const {
    nlohmann::json j{{"format", FORMAT},
                     {"version", VERSION},
                     {"source", source},
                     {"layer_thickness_mm", layerThickness},
                     {"plane_position", planePosition},
                     {"z_start_mm", zStart}};
    nlohmann::json list = nlohmann::json::array();
    for (const Layer& layer : layers) {
        nlohmann::json parts = nlohmann::json::array();
        for (const auto& part : layer.region.parts()) {
            nlohmann::json holes = nlohmann::json::array();
            for (const auto& h : part.holes) holes.push_back(contourJson(h));
            parts.push_back({{"outer", contourJson(part.outer)}, {"holes", holes}});
        }
        list.push_back({{"index", layer.index},
                        {"z", layer.z},
                        {"z_bottom", layer.zBottom},
                        {"parts", parts}});
    }
    j["layers"] = list;
    return j;
}

LayerStack LayerStack::fromJson(const nlohmann::json& j, const std::string& file) {
    if (!j.is_object() || j.value("format", "") != FORMAT) {
        throw InputError(std::string("not a layer stack (expected \"format\": \"") + FORMAT + "\")",
                         file, "format");
    }
    if (j.value("version", 0) != VERSION) {
        throw InputError("unsupported layer stack version (this vpsim reads version 1)", file,
                         "version");
    }
    LayerStack stack;
    stack.source = j.value("source", "");
    stack.layerThickness = numberAt(j, "layer_thickness_mm", file, "");
    stack.planePosition = numberAt(j, "plane_position", file, "");
    stack.zStart = numberAt(j, "z_start_mm", file, "");
    if (!(stack.layerThickness > 0.0))
        throw InputError("must be positive", file, "layer_thickness_mm");
    if (!j.contains("layers") || !j["layers"].is_array())
        throw InputError("expected an array", file, "layers");
    for (size_t k = 0; k < j["layers"].size(); ++k) {
        const nlohmann::json& l = j["layers"][k];
        const std::string where = "layers[" + std::to_string(k) + "]";
        Layer layer;
        layer.index = int(numberAt(l, "index", file, where));
        layer.z = numberAt(l, "z", file, where);
        layer.zBottom = numberAt(l, "z_bottom", file, where);
        if (!l.contains("parts") || !l["parts"].is_array())
            throw InputError("expected an array", file, where + ".parts");
        std::vector<Contour> contours;
        for (size_t p = 0; p < l["parts"].size(); ++p) {
            const nlohmann::json& part = l["parts"][p];
            const std::string at = where + ".parts[" + std::to_string(p) + "]";
            if (!part.is_object() || !part.contains("outer"))
                throw InputError("expected {\"outer\", \"holes\"}", file, at);
            contours.push_back(contourFromJson(part["outer"], file, at + ".outer"));
            for (const auto& hole : part.value("holes", nlohmann::json::array())) {
                contours.push_back(contourFromJson(hole, file, at + ".holes"));
            }
        }
        // Outers CCW and holes CW: non-zero winding rebuilds exactly the stored region.
        layer.region = PolygonSet::fromContours(contours, FillRule::NonZero);
        stack.layers.push_back(std::move(layer));
    }
    return stack;
}

void LayerStack::save(const std::string& path) const {
    writeFileAtomic(path, toJson().dump() + "\n");
}

LayerStack LayerStack::load(const std::string& path) {
    return fromJson(loadJsonFile(path), path);
}

LayerStack sliceToStack(const Mesh& mesh, const SliceOptions& options, const std::string& source,
                        const std::vector<int>& onlyLayers) {
    LayerStack stack;
    stack.source = source;
    stack.layerThickness = options.layerThickness;
    stack.planePosition = options.planePosition;
    stack.zStart = options.zStart.value_or(mesh.bounds().lo.z);
    stack.layers = sliceMesh(mesh, options, onlyLayers);
    return stack;
}

}  // namespace vpsim::geometry
