// `vpsim part make NAME --out FILE.stl`: parametric test parts (geometry/test_parts.h).
// `vpsim part check FILE.stl`: the mesh checks and safe repairs every reader applies
// (geometry/mesh_check.h), printed as a table or JSON; exits non-zero on an unrepairable defect.

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"
#include "vpsim/geometry/level_set.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/geometry/test_parts.h"

namespace {

using namespace vpsim;
using namespace vpsim::geometry;

struct MakeOptions {
    std::string name, out, size, height, topSize, depth, spacing;
    int count = -1, segments = -1;  // -1: not given
    bool ascii = false, json = false;
};

struct LevelSetCliOptions {
    std::string file, out, voxel = "20um";
    double halfWidth = 3.0, scale = 1.0;
    bool json = false;
};

struct CheckOptions {
    std::string file, out;
    double scale = 1.0;
    bool noRepair = false, json = false;
};

/// Test-part sizes: 0.1 um to 1 km. Outside that the mesh is degenerate in float or the size is
/// a unit mistake.
std::optional<double> lengthOption(const std::string& text, const std::string& option) {
    if (text.empty()) return std::nullopt;
    const double value = parseQuantity(text, dim::LENGTH, option);
    if (!(value >= 1e-4 && value <= 1e6))
        throw InputError("must be between 0.1 um and 1 km, got " + quoteUser(text), "", option);
    return value;
}

/// Counts that size the mesh (pillars, cylinder sides), bounded so a typo cannot hang the
/// command: 100000 pillars or sides is already far beyond any test part.
int countOption(int value, int lo, const std::string& option) {
    if (value < lo || value > 100000)
        throw InputError(
            "must be from " + std::to_string(lo) + " to 100000, got " + std::to_string(value), "",
            option);
    return value;
}

nlohmann::json boundsJson(const Bounds& b) {
    return {{b.lo.x, b.lo.y, b.lo.z}, {b.hi.x, b.hi.y, b.hi.z}};
}

void runMake(const MakeOptions& o) {
    TestPartOptions p;
    p.size = lengthOption(o.size, "--size");
    p.height = lengthOption(o.height, "--height");
    p.topSize = lengthOption(o.topSize, "--top-size");
    p.depth = lengthOption(o.depth, "--depth");
    p.spacing = lengthOption(o.spacing, "--spacing");
    if (o.count != -1) p.count = countOption(o.count, 1, "--count");
    if (o.segments != -1) p.segments = countOption(o.segments, 3, "--segments");
    const Mesh mesh = makeTestPart(o.name, p);
    if (o.ascii) {
        writeStlAscii(o.out, mesh, o.name);
    } else {
        writeStl(o.out, mesh, o.name);
    }
    nlohmann::json out{{"part", o.name},
                       {"file", o.out},
                       {"triangles", mesh.triangles.size()},
                       {"volume_mm3", mesh.volume()},
                       {"area_mm2", mesh.area()},
                       {"bounds_mm", boundsJson(mesh.bounds())}};
    if (o.json) {
        cli::printJson(out);
        return;
    }
    const Bounds b = mesh.bounds();
    std::printf(
        "%s -> %s: %zu triangles, volume %.6g mm^3, bounds (%g, %g, %g) .. (%g, %g, %g) mm\n",
        o.name.c_str(), o.out.c_str(), mesh.triangles.size(), mesh.volume(), b.lo.x, b.lo.y, b.lo.z,
        b.hi.x, b.hi.y, b.hi.z);
}

void runCheck(const CheckOptions& o) {
    StlReadOptions options;
    options.scale = o.scale;
    options.check.repair = !o.noRepair;
    options.check.throwOnProblem = false;
    Mesh mesh = readStlSoup(o.file, o.scale);
    const MeshReport report = checkMesh(mesh, o.file, options.check);
    if (o.json) {
        cli::printJson(report.toJson());
    } else {
        std::printf("%s\n  triangles          %zu (%zu vertices after merging %zu duplicates)\n",
                    o.file.c_str(), report.trianglesIn,
                    report.verticesIn - report.duplicateVerticesMerged,
                    report.duplicateVerticesMerged);
        std::printf(
            "  shells             %zu\n  open edges         %zu\n  non-manifold edges %zu\n",
            report.shells, report.openEdges, report.nonManifoldEdges);
        std::printf("  volume             %.6g mm^3\n  area               %.6g mm^2\n",
                    report.volume, report.area);
        if (!report.bounds.empty()) {
            const Bounds& b = report.bounds;
            std::printf("  bounds             (%g, %g, %g) .. (%g, %g, %g) mm\n", b.lo.x, b.lo.y,
                        b.lo.z, b.hi.x, b.hi.y, b.hi.z);
        }
        for (const auto& r : report.repairs) std::printf("  repaired: %s\n", r.c_str());
        for (const auto& p : report.problems) std::printf("  PROBLEM: %s\n", p.c_str());
        if (report.ok()) std::printf("  ok\n");
    }
    if (!report.ok()) throw InputError(report.problems.front(), o.file);
    if (!o.out.empty()) writeStl(o.out, mesh, "repaired");
}

void runLevelSet(const LevelSetCliOptions& o, const RunContext& context) {
    const Mesh mesh = readStl(o.file, o.scale);
    LevelSetOptions options;
    options.voxelSize = parseQuantity(o.voxel, dim::LENGTH, "--voxel");
    const Bounds b = mesh.bounds();
    const double largest = std::max({b.hi.x - b.lo.x, b.hi.y - b.lo.y, b.hi.z - b.lo.z});
    if (options.voxelSize > largest)
        throw InputError("voxel " + formatQuantity(options.voxelSize) +
                             " mm is larger than the part (" + formatQuantity(largest) + " mm)",
                         "", "--voxel");
    options.halfWidthVoxels = o.halfWidth;
    // In bytes against this run's budget (the library's default is a fixed 8 GiB).
    checkMemory(context, LevelSet::estimateBytes(mesh, options),
                "level set at --voxel " + o.voxel + " (half-width " +
                    std::to_string(int(o.halfWidth)) + " voxels)",
                "use a larger --voxel or a smaller --half-width");
    const LevelSet levelSet = LevelSet::fromMesh(mesh, options);
    levelSet.save(o.out);
    nlohmann::json out{{"file", o.out},
                       {"voxel_mm", levelSet.voxelSize()},
                       {"half_width_mm", levelSet.halfWidth()},
                       {"active_voxels", levelSet.activeVoxelCount()},
                       {"memory_bytes", levelSet.memoryBytes()},
                       {"bounds_mm", boundsJson(levelSet.activeBounds())}};
    if (o.json) {
        cli::printJson(out);
        return;
    }
    std::printf("%s -> %s: %zu active voxels of %g um, band +-%g um, %s\n", o.file.c_str(),
                o.out.c_str(), levelSet.activeVoxelCount(), levelSet.voxelSize() * 1000.0,
                levelSet.halfWidth() * 1000.0, formatBytes(double(levelSet.memoryBytes())).c_str());
}

vpsim::cli::CommandRegistration registerPart{
    "part", [](CLI::App& app, const vpsim::cli::Globals& g) {
        auto* part = app.add_subcommand("part", "test parts and mesh checks");
        part->require_subcommand(1);

        auto* make =
            part->add_subcommand("make",
                                 "write a parametric, watertight test part as STL (mm; footprint "
                                 "centred on x = y = 0, standing on z = 0)");
        auto m = std::make_shared<MakeOptions>();
        std::string names;
        for (const auto& n : testPartNames()) names += (names.empty() ? "" : ", ") + n;
        make->add_option("name", m->name, "part: " + names)->required();
        make->add_option("--out", m->out, "output STL file")->required();
        make->add_option("--size", m->size,
                         "main horizontal size (mm or with unit): box/l-shape side 10; tapered "
                         "bottom side 10; bottom-narrow top side 10; holes x 10; overhangs x 16; "
                         "pillars side 1; cylinder diameter 10");
        make->add_option(
            "--height", m->height,
            "height: 10 (pillars 2); holes (11) and overhangs (10) are fixed by seed 001");
        make->add_option("--top-size", m->topSize,
                         "frustums: side of the smaller face (default size/2)");
        make->add_option("--depth", m->depth, "holes, overhangs: extent along y (default 5 mm)");
        make->add_option("--spacing", m->spacing,
                         "pillars: centre-to-centre distance (default 3 mm)");
        make->add_option("--count", m->count, "pillars: number of pillars (default 4)");
        make->add_option("--segments", m->segments, "cylinder: number of sides (default 64)");
        make->add_flag("--ascii", m->ascii, "write ASCII STL instead of binary");
        make->add_flag("--json", m->json, "print a JSON summary");
        make->callback([m] { runMake(*m); });

        auto* check =
            part->add_subcommand("check",
                                 "check an STL: truncation, NaN, degenerate triangles, open and "
                                 "non-manifold edges, orientation; report the safe repairs");
        auto c = std::make_shared<CheckOptions>();
        check->add_option("file", c->file, "STL file (binary or ASCII, detected from content)")
            ->required();
        check->add_option("--scale", c->scale, "multiply coordinates (25.4 for inches)");
        check->add_flag("--no-repair", c->noRepair,
                        "report repairable defects as problems instead of repairing");
        check->add_option("--out", c->out, "write the repaired mesh as binary STL");
        check->add_flag("--json", c->json, "print the report as JSON");
        check->callback([c] { runCheck(*c); });

        auto* levelSet =
            part->add_subcommand("levelset",
                                 "write the part's reference signed distance field as .vdb "
                                 "(OpenVDB narrow band; negative inside, mm)");
        auto l = std::make_shared<LevelSetCliOptions>();
        levelSet->add_option("file", l->file, "STL file")->required();
        levelSet->add_option("--out", l->out, "output .vdb file")->required();
        levelSet->add_option("--voxel", l->voxel, "voxel size (default 20um)");
        levelSet->add_option("--half-width", l->halfWidth,
                             "narrow-band half-width in voxels (default 3)");
        levelSet->add_option("--scale", l->scale, "multiply STL coordinates (25.4 for inches)");
        levelSet->add_flag("--json", l->json, "print a JSON summary");
        levelSet->callback([l, &g] { runLevelSet(*l, g.hostContext()); });
    }};

}  // namespace
