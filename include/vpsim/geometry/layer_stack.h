#pragma once
/// @file
/// LayerStack: the geometry stage's saved output (docs/ARCHITECTURE.md, "typed stages"): the
/// sliced layers of one part with the slicing parameters, as JSON so a user can stop, inspect
/// and resume, and a planner test can start from a stored stack.
///
/// File format (JSON, lengths in mm):
///   {"format": "vpsim-layer-stack", "version": 1, "source": "part.stl",
///    "layer_thickness_mm": 0.05, "plane_position": 0.5, "z_start_mm": 0.0,
///    "layers": [{"index": 0, "z": 0.025, "z_bottom": 0.0,
///                "parts": [{"outer": [[x, y], ...], "holes": [[[x, y], ...], ...]}]}]}
/// Coordinates are written with full double precision, so a saved stack loads back exactly.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/geometry/slicer.h"

namespace vpsim::geometry {

/// The sliced layers of a part.
struct LayerStack {
    std::string source;           ///< where the part came from (file name or test part)
    double layerThickness = 0.0;  ///< mm
    double planePosition = 0.5;   ///< slicing plane within each layer, [0, 1]
    double zStart = 0.0;          ///< bottom of layer 0 (mm)
    std::vector<Layer> layers;    ///< in index order (all layers, or a chosen subset)

    nlohmann::json toJson() const;
    /// @throw InputError naming `file` and the key for a malformed document
    static LayerStack fromJson(const nlohmann::json& document, const std::string& file = "");
    /// Writes the JSON atomically. @throw InputError when the file cannot be written
    void save(const std::string& path) const;
    /// @throw InputError naming the file for a missing file, bad JSON or a malformed stack
    static LayerStack load(const std::string& path);
};

/// Slices a mesh into a LayerStack (see sliceMesh()).
LayerStack sliceToStack(const Mesh& mesh, const SliceOptions& options, const std::string& source,
                        const std::vector<int>& onlyLayers = {});

}  // namespace vpsim::geometry
