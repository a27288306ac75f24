#pragma once
/// @file
/// DFBTP's feature QPs (seed 000 Sec. IV, Eqs. 17 and 19), apart from the layer loop in
/// dfbtp.cpp: the rows of an edge block, the dots of a corner block, and the edge rows in scan
/// order. Internal to src/optimise/laser.

#include <vector>

#include <glm/vec2.hpp>

#include "vpsim/exposure/surface_grid.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/plan/feature_blocks.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::optimise::dfbtp {

using exposure::SurfaceGrid;

/// What one layer's feature QPs need.
struct LayerContext {
    const DfbtpParameters* p = nullptr;
    double w = 0, efficiency = 1, etar = 0, roff = 0, reff = 0;
    const geometry::PolygonSet* region = nullptr;
    std::vector<char> inside, middle;  ///< cell masks: region, middle area
    SurfaceGrid goal, planned;         ///< target after compensation; exposure planned so far
};

/// `g` at (x, y) mm, bilinear between cell centres (clamped at the borders).
double bilinear(const SurfaceGrid& g, double x, double y);
/// What the goal still lacks at (x, y): goal minus planned, at least 0.
double missingAt(const LayerContext& c, double x, double y);

/// One edge block's rows, in offset order: the row vectors (speed 0 where a row gets no energy)
/// and the pieces that continue a row through the corner block at its start (`before`, in scan
/// order) and at its end (`after`), on the same line, so that the scanner runs them with the
/// row as one power-modulated line instead of jumping to a corner dot row.
struct EdgeRows {
    std::vector<double> offsets;  ///< u_j, mm along the inward normal
    std::vector<plan::LaserVector> rows;
    std::vector<std::vector<plan::LaserVector>> before, after;
};

/// Seed Eq. 17: one linear edge as rows of constant line density lambda_j (mJ/mm) at distances
/// u_j across the edge; a row's exposure at distance u is eff sqrt(2/pi)/W exp(-2 (u-u_j)^2/W^2)
/// lambda_j (Eq. C.6). The missing exposure is averaged over five stations along the block.
EdgeRows planEdge(const plan::EdgeBlock& e, const LayerContext& c);

/// A corner's candidate dot: where it lies and, on a row line, the piece of that line it runs
/// as (its edge, row and place in the continuation).
struct CornerDot {
    glm::dvec2 at;
    int edge = -1, row = 0;  ///< edge -1: a grid dot (no edge row to continue)
    bool after = false;      ///< continues the row past the edge block's end
    glm::dvec2 from, to;     ///< the piece of the row line
};

/// The corner's candidates on the lines of the rows of the edges that meet at it, one piece a
/// dot pitch long after another from the edge block's end (incoming edge) or back from its
/// start (outgoing), to the far side of the corner block.
std::vector<CornerDot> rowLineDots(const plan::CornerBlock& corner,
                                   const std::vector<plan::EdgeBlock>& edges,
                                   const std::vector<EdgeRows>& rows, int incoming, int outgoing,
                                   double pitch);

/// The corner's candidates on a grid of the dot pitch around its vertex.
std::vector<CornerDot> gridDots(const plan::CornerBlock& corner, double pitch);

/// Seed Eq. 19: one corner as dots of energy T_k around the vertex; a dot's exposure is
/// eff 2/(pi W^2) exp(-2 r^2/W^2) T_k. Evaluated on the grid cells of the block grown by Reff.
/// Dots on a row line become pieces of that row (`rows`), grid dots layer points.
int planCorner(const plan::CornerBlock& corner, const std::vector<CornerDot>& candidates,
               LayerContext& c, std::vector<EdgeRows>& rows, plan::LayerPlan& out);

/// The edge rows in scan order: around each contour (its edge blocks in contour order), one
/// offset after the other, as ACES's border loops run, each row with the pieces that continue it
/// through its corner blocks (one line at constant speed, power modulated along it). Serpentine
/// rows along one edge reversed at every row instead.
std::vector<plan::LaserVector> edgeLoops(const std::vector<plan::EdgeBlock>& edges,
                                         std::vector<EdgeRows>& rows);

/// The edge blocks ending (`incoming`) and starting (`outgoing`) at a corner's vertex, -1 where
/// the edge there has no block.
void edgesAt(const plan::CornerBlock& corner, const std::vector<plan::EdgeBlock>& edges,
             int& incoming, int& outgoing);

}  // namespace vpsim::optimise::dfbtp
