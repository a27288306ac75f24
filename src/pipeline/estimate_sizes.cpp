#include <algorithm>
#include <cmath>

#include "vpsim/geometry/slicer.h"
#include "vpsim/kernel/beam_kernel.h"

#include "estimate_sizes.h"

namespace vpsim::pipeline::estimate_detail {

const char* const COARSER =
    "a coarser simulation.voxel, fewer simulation.slices_per_layer, thicker layers or a "
    "smaller part";

namespace {

/// The exposure grid as stages.cpp's exposureGrid() will make it. The Monte Carlo kernel's
/// fitted radius is not known yet: scattering widens the beam, so the guess is 1.5 x w0.
void gridSizes(const Job& job, Sizes& s) {
    const bool mc = job.machine.process == plan::Process::Laser &&
                    job.kernel.source == kernel::KernelSource::MonteCarlo;
    s.beamRadius = job.machine.process == plan::Process::Laser &&
                           job.kernel.source == kernel::KernelSource::Given
                       ? job.kernel.given.radius
                       : job.machine.beamRadius * (mc ? 1.5 : 1.0);
    const SimulationSpec& sim = job.simulation;
    const double margin =
        sim.margin >= 0 ? sim.margin : 3.0 * std::max(s.beamRadius, job.machine.beamRadius);
    const glm::dvec3 size = s.bounds.size();
    s.nx = std::ceil((size.x + 2 * margin) / sim.voxel);
    s.ny = std::ceil((size.y + 2 * margin) / sim.voxel);
    s.cells = s.nx * s.ny;
    s.slices = double(s.layers) * sim.slicesPerLayer;
    s.voxels = s.cells * s.slices;
    s.voxelHeight = job.machine.layerThickness / sim.slicesPerLayer;
    // Stored: the part grown by the exposure's reach (1.5 W in x-y, where the Gaussian tail
    // falls under 2% of Ec; print-through a few attenuation lengths down) plus a leaf of
    // partial leaves on each side of the surface.
    const double depth = job.cure->hasPenetrationDepth() ? job.cure->penetrationDepth() : 0.0;
    const double reach =
        std::max(1.5 * s.beamRadius, 4.0 * depth) + VDB_LEAF * std::max(sim.voxel, s.voxelHeight);
    const double grown = s.volume + s.area * reach;
    s.activeVoxels = std::min(s.voxels, grown / (sim.voxel * sim.voxel * s.voxelHeight));
    s.surfaceVoxels = 2.0 * s.area / (sim.voxel * std::min(sim.voxel, s.voxelHeight));
}

/// Edges of the grid of cells dx x dx x dz that the part's surface crosses: each triangle's
/// area projected on the x, y and z planes over the cell face it crosses edges through (a
/// staircase of layers projects as the slope it follows, so the count holds for the cured part).
double crossedEdges(const geometry::Mesh& part, double dx, double dz) {
    double edges = 0;
    for (size_t t = 0; t < part.triangles.size(); ++t) {
        const glm::dvec3 n = part.triangleNormal(t);  // twice the area, so halves below
        edges += 0.5 * ((std::abs(n.x) + std::abs(n.y)) / (dx * dz) + std::abs(n.z) / (dx * dx));
    }
    return edges;
}

}  // namespace

void tileSizes(const Job& job, double side, Sizes& s) {
    const double pitch = job.simulation.voxel;
    const bool tabulated = tabulatedEngine(job);
    const double reach =
        tabulated ? std::ceil(kernel::kernelTableRadius(job.machine.beamRadius) / pitch + 0.5)
                  : std::ceil(1.75 * s.beamRadius / pitch);
    const double halo = reach + 1;
    s.tileCells = side > 0 ? std::ceil(side / pitch - 1e-9) : 0;
    const double t = s.tileCells > 0 ? s.tileCells : std::max(s.nx, s.ny);
    const double across = std::ceil(s.nx / t), down = std::ceil(s.ny / t);
    s.tiles = across * down;
    const double coreX = std::min(t, s.nx), coreY = std::min(t, s.ny);
    s.coreCells = coreX * coreY;
    if (s.tiles == 1) {
        s.windowCells = s.computedCells = s.cells;
        return;
    }
    s.windowCells = std::min(s.nx, coreX + 2 * halo) * std::min(s.ny, coreY + 2 * halo);
    s.computedCells = std::min(s.nx + 2 * halo * (across - 1), across * (coreX + 2 * halo)) *
                      std::min(s.ny + 2 * halo * (down - 1), down * (coreY + 2 * halo));
}

Sizes sizesOf(const Job& job, const geometry::Mesh& part) {
    Sizes s;
    s.bounds = part.bounds();
    s.volume = std::abs(part.volume());
    s.area = part.area();
    geometry::SliceOptions slicing;
    slicing.layerThickness = job.machine.layerThickness;
    slicing.zStart = 0.0;
    s.layers = geometry::layerCount(part, slicing);
    s.contourVertices = contourVertexCount(part, s.layers, job.machine.layerThickness, 0.0, 0.5);
    gridSizes(job, s);
    s.surfaceEdges = crossedEdges(part, job.simulation.voxel, s.voxelHeight);
    return s;
}

void add(JobEstimate& e, std::string name, double bytes, Stage first, Stage last,
         std::string detail, std::string hint, bool perTile) {
    e.items.push_back(
        {std::move(name), bytes, first, last, std::move(detail), std::move(hint), perTile});
}

std::string gridText(const Job& job, const Sizes& s) {
    return fmt(s.nx) + " x " + fmt(s.ny) + " cells x " + fmt(s.slices) + " slices at " +
           fmt(job.simulation.voxel * 1e3) + " um x " + fmt(s.voxelHeight * 1e3) + " um";
}

std::string tileText(const Sizes& s) {
    if (s.tiles == 1) return "";
    return ", per tile of " + fmt(s.tiles) + " (" + fmt(s.coreCells) + " cells and a halo)";
}

}  // namespace vpsim::pipeline::estimate_detail
