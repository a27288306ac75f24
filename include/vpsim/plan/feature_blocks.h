#pragma once
/// @file
/// Feature disassembly of a layer region (seed 000 Section III-A, Fig. 17) for DFBTP: the middle
/// area (the contour offset inward by Roff, Eq. 13), one linear-edge block per straight contour
/// edge and one corner block per contour vertex, on polygons with holes (Clipper).
///
/// Edge block of edge (a, b), with tangent t and inward normal n (the region lies left of every
/// contour: outers counter-clockwise, holes clockwise): along t it spans [c, L - c] (c: the corner
/// blocks' half-size, L the edge length); across it, at distance u along n,
///   sub-block 1  u in [-Reff, 0]     outside the part: dots there may help sub-block 2;
///   sub-block 2  u in [0, Roff]      the band the middle area's edge leaves under-exposed;
///   sub-block 3  u in [Roff, Roff + Reff]  inside, already at Etar: kept from over-exposure.
/// Corner block of vertex v: the axis-aligned square of half-size c = Roff + W around v; sub-block
/// 4 is its part inside the region but outside the middle area, sub-block 5 its part outside the
/// region (grown by Reff), sub-block 6 its part in the middle area. Reff (the effective radius) is
/// where a dot's exposure falls below 1% of its centre: exp(-2 Reff^2 / W^2) = 0.01. Units: mm.

#include <vector>

#include "vpsim/geometry/polygons.h"

namespace vpsim::plan {

/// Reff: the radius where a Gaussian dot of 1/e^2 radius W falls to `fraction` of its centre.
double effectiveRadius(double beamRadius, double fraction = 0.01);

struct EdgeBlock {
    glm::dvec2 a, b;              ///< the contour edge (mm), region on the left of a -> b
    glm::dvec2 tangent;           ///< unit vector a -> b
    glm::dvec2 normal;            ///< unit inward normal
    double start = 0, end = 0;    ///< the block's extent along the tangent from a (mm)
    geometry::PolygonSet sub[3];  ///< sub-blocks 1, 2, 3
};

struct CornerBlock {
    glm::dvec2 vertex;
    bool convex = true;           ///< interior angle below 180 degrees
    double halfSize = 0;          ///< mm
    geometry::PolygonSet square;  ///< the whole block
    geometry::PolygonSet sub[3];  ///< sub-blocks 4, 5, 6
};

struct FeatureBlocks {
    geometry::PolygonSet middle;  ///< the ACES area: region offset inward by Roff
    std::vector<EdgeBlock> edges;
    std::vector<CornerBlock> corners;
};

/// Disassembles `region`. Edges shorter than two corner half-sizes get no edge block (their
/// corners cover them); vertices whose turn is below `minTurn` radians (nearly straight, e.g. on
/// a polygonised curve) get no corner block.
/// @throw InputError for non-positive Roff, Reff or beam radius
FeatureBlocks disassembleFeatures(const geometry::PolygonSet& region, double roff, double reff,
                                  double beamRadius, double minTurn = 0.2);

}  // namespace vpsim::plan
