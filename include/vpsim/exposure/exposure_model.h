#pragma once
/// @file
/// The exposure model: what a plan's light does to the resin, as a linear operator from per-layer
/// surface deposits (mJ/mm^2 at the resin surface, before the beam spreads them) to the 3D
/// exposure field, with print-through across layers. Both engines (the fitted separable kernel
/// and the tabulated Monte Carlo kernel) implement it, forward and adjoint, so least-squares
/// planners optimise against the same physics that the simulation uses.
///
/// Indexing: layers from the bottom (k = 0) up; each layer holds `grid().slicesPerLayer` voxel
/// slices, slice s = 0 at its top; slice s of layer k lies at depth (s + 0.5) h / n below the
/// layer's top surface (h: layer thickness). An ExposureField holds slice s of layer k at
/// index k n + s.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vpsim/exposure/surface_grid.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::exposure {

/// A rectangle of a grid's cells, [i0, i1) x [j0, j1).
struct CellWindow {
    int i0 = 0, j0 = 0, i1 = 0, j1 = 0;
    int width() const { return i1 - i0; }
    int height() const { return j1 - j0; }
    bool contains(int i, int j) const { return i >= i0 && i < i1 && j >= j0 && j < j1; }
};

/// The build-volume grid the exposure is computed on.
struct ExposureGrid {
    int nx = 0, ny = 0;               ///< cells in x and y
    double originX = 0, originY = 0;  ///< mm, corner of cell (0, 0) of the whole grid
    double pitch = 0.01;              ///< mm, cell size in x and y
    int slicesPerLayer = 1;           ///< voxel slices per layer thickness (voxel z size h / n)
    /// A tile's window of the whole grid starts at the whole grid's cell (firstI, firstJ)
    /// (SurfaceGrid::firstI); 0 for the whole grid.
    int firstI = 0, firstJ = 0;
    /// The cells of the whole grid this grid holds.
    CellWindow cells() const { return {firstI, firstJ, firstI + nx, firstJ + ny}; }
    /// The window `w` (cells of the whole grid) of this grid, as a grid of its own.
    ExposureGrid window(const CellWindow& w) const;
    /// Cells needed to cover [xmin, xmax] x [ymin, ymax] plus `margin` (mm) on every side.
    static ExposureGrid covering(double xmin, double ymin, double xmax, double ymax, double margin,
                                 double pitch, int slicesPerLayer);
    /// An empty (all-zero) 2D grid on this grid's cells.
    SurfaceGrid surface() const {
        SurfaceGrid s(nx, ny, originX, originY, pitch);
        s.firstI = firstI;
        s.firstJ = firstJ;
        return s;
    }
    /// The same cells as a raster for the geometry module's rasterisers (whole grids only: a
    /// raster's origin is its own first cell's corner).
    geometry::RasterGrid raster() const {
        geometry::RasterGrid r;
        r.origin = {originX, originY};
        r.pitch = pitch;
        r.width = nx;
        r.height = ny;
        return r;
    }
};

/// One finished voxel slice: layer index, slice index within the layer (0 = top), the height of
/// the slice centre (mm) and the exposure (mJ/mm^2) on the x-y grid, row-major. In a tiled run
/// `values` covers a tile with its halo (values->firstI, firstJ) and `core` names the cells of
/// the whole grid that this tile owns: consumers count those only, so every cell is counted
/// once over the tiles. An empty core means all of `values`.
struct ExposureSlice {
    ExposureSlice() = default;
    /// `core` empty: the slice's consumer owns all of `values` (an untiled run).
    ExposureSlice(int layerIndex, int sliceIndex, double height, const SurfaceGrid* grid,
                  CellWindow owner = {})
        : layer(layerIndex), slice(sliceIndex), z(height), values(grid), core(owner) {}
    int layer = 0;
    int slice = 0;
    double z = 0;
    const SurfaceGrid* values = nullptr;
    CellWindow core;
    /// The cells this slice's consumer owns: `core`, or all of `values` when it is empty.
    CellWindow owned() const {
        if (core.width() > 0) return core;
        return {values->firstI, values->firstJ, values->firstI + values->nx,
                values->firstJ + values->ny};
    }
};
using SliceSink = std::function<void(const ExposureSlice&)>;

/// A whole 3D exposure (or adjoint source) field: slice s of layer k at index k n + s.
using ExposureField = std::vector<SurfaceGrid>;

class ExposureModel {
public:
    virtual ~ExposureModel() = default;
    /// "fitted" or "tabulated".
    virtual std::string name() const = 0;
    virtual const ExposureGrid& grid() const = 0;
    virtual double layerThickness() const = 0;
    virtual bool usesGpu() const = 0;
    /// Fraction of the kernel's energy the engine keeps after truncating it (1: none dropped).
    virtual double keptEnergyFraction() const { return 1.0; }
    /// How far (cells) a deposit reaches in x or y: a tile's halo at least this wide gives its
    /// core cells the same exposure, bit for bit, as the whole grid gives them.
    virtual int reachCells() const = 0;

    /// Forward, whole plan: deposits every layer of `plan` (layer k's top at plan.layers[k].z) and
    /// calls `sink` for each voxel slice from the top of the part down (top layer first, slice 0
    /// first). Returns the seconds spent in the engine (GPU time on the shader path).
    double run(const plan::ScanPlan& plan, const SliceSink& sink);
    /// The same on a tile: the model's grid is the tile's window of the whole grid (with a halo
    /// of at least reachCells()) and `core` the cells the tile owns, passed on in each slice.
    double run(const plan::ScanPlan& plan, const CellWindow& core, const SliceSink& sink);

    /// Forward, one layer alone (no print-through): the exposure at `depth` (mm, >= 0) below the
    /// top of the layer that received `deposit`. The fitted kernel is exact at any depth; the
    /// tabulated kernel uses the stencil of the voxel slice containing `depth` (0 beyond the
    /// kernel's depth).
    virtual SurfaceGrid layerMap(const SurfaceGrid& deposit, double depth) = 0;
    /// The adjoint (transpose) of layerMap: <layerMap(x), y> = <x, layerMapAdjoint(y)>.
    virtual SurfaceGrid layerMapAdjoint(const SurfaceGrid& map, double depth) = 0;

    /// Forward, whole stack: per-layer deposits (bottom up) -> the 3D field with print-through.
    ExposureField stack(const std::vector<SurfaceGrid>& deposits);
    /// The adjoint of stack: a 3D field -> per-layer deposits (bottom up), so that
    /// <stack(x), y> = <x, stackAdjoint(y)> over all slices and layers.
    virtual std::vector<SurfaceGrid> stackAdjoint(const ExposureField& field) = 0;

protected:
    /// The top-down layer loop shared by run() and stack(): `fill(k, deposit)` writes layer k's
    /// deposit into a zeroed grid; `top(k)` is the height of its top surface (mm).
    double forward(int layers, const std::function<void(int, SurfaceGrid&)>& fill,
                   const std::function<double(int)>& top, const SliceSink& sink);
    /// Engine hooks of forward(): start a run of `layers` layers; add layer k's deposit (layers
    /// arrive top down; the deposit may be overwritten), returning engine seconds; then hand the
    /// slices of layer k, now final, to `sink`.
    virtual void beginLayers(int layers) = 0;
    virtual double addLayer(int k, SurfaceGrid& deposit) = 0;
    virtual void emitLayer(int k, double top, const SliceSink& sink) = 0;
};

/// Layers in `field` (its slices / grid.slicesPerLayer).
/// @throw InputError when the slices are not whole layers of `grid` or differ from its cells
int fieldLayers(const ExposureField& field, const ExposureGrid& grid);

/// Sum over cells of a x b (double precision), for adjoint checks and least squares.
double dot(const SurfaceGrid& a, const SurfaceGrid& b);
/// Sum over slices of dot(a[i], b[i]). @throw InputError when the fields differ in size
double dot(const ExposureField& a, const ExposureField& b);

}  // namespace vpsim::exposure
