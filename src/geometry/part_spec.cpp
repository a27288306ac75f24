#include "vpsim/geometry/part_spec.h"

#include <filesystem>

#include "vpsim/core/checks.h"
#include "vpsim/core/config.h"
#include "vpsim/geometry/stl_io.h"

namespace vpsim::geometry {

PartSpec partSpecFromConfig(const ConfigNode& part) {
    if (part.has("stl") == part.has("test_part"))
        throw part.error("stl", "give exactly one of 'stl' or 'test_part'");
    PartSpec spec;
    if (part.has("stl")) {
        spec.stl = resolvePath(part, "stl");
        spec.scale = part.number("scale", 1.0);
        requirePositive(spec.scale, part.keyPath("scale"));
        return spec;
    }
    spec.testPart = part.choice("test_part", testPartNames());
    TestPartOptions& o = spec.testPartOptions;
    for (auto [key, value] : {std::pair<const char*, std::optional<double>*>{"size", &o.size},
                              {"height", &o.height},
                              {"top_size", &o.topSize},
                              {"depth", &o.depth},
                              {"spacing", &o.spacing}})
        if (part.has(key)) *value = positiveQuantity(part, key, dim::LENGTH);
    if (part.has("count")) o.count = int(part.integer("count"));
    if (part.has("segments")) o.segments = int(part.integer("segments"));
    return spec;
}

Mesh loadPart(const PartSpec& spec) {
    Mesh part;
    if (spec.mesh) {
        part = *spec.mesh;
    } else if (!spec.stl.empty()) {
        part = readStl(spec.stl, spec.scale);
    } else {
        part = makeTestPart(spec.testPart, spec.testPartOptions);
    }
    part.translate({0, 0, -part.bounds().lo.z});  // the build platform is z = 0
    return part;
}

}  // namespace vpsim::geometry
