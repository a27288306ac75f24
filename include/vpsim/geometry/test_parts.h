#pragma once
/// @file
/// Parametric, exact, watertight test parts (mm) for planners, validation and tests. Every part
/// stands on z = 0 with its footprint centred on x = y = 0, and is built from shared vertices
/// with outward-facing triangles (checkMesh() accepts it without repairs).
///
/// | name          | shape                                                                    |
/// options (defaults)                         |
/// |---------------|--------------------------------------------------------------------------|--------------------------------------------|
/// | box           | rectangular block                                                        |
/// size 10, height 10                         | | tapered       | square frustum, wider at the
/// bottom                                      | size 10 (bottom side), top-size 5, height 10 | |
/// bottom-narrow | inverted square frustum                                                  | size
/// 10 (top side), top-size = bottom side 5, height 10 | | l-shape       | L footprint:
/// [0,s]x[0,s/2] + [0,s/2]x[s/2,s], centred (sharp convex and concave corners) | size 10, height 10
/// | | holes         | seed 001 case 1: block size x depth x 11 with two square through-holes along
/// y: bottom 3 x 3 (z 2..5), top 1.5 x 1.5 (z 7..8.5) | size 10, depth 5 | | overhangs     | seed
/// 001 case 2: 4 mm column, height 10, with two unsupported ledges: top one 3 mm thick (z 7..10, on
/// -x), bottom one 1 mm thick (z 3..4, on +x) | size 16 (total x), depth 5 | | pillars       |
/// `count` separate square pillars on a grid (ceil(sqrt(count)) columns)    | count 4, size 1
/// (side), height 2, spacing 3 (centre to centre) | | cylinder      | regular `segments`-gon prism
/// (a vertex at angle 0)                       | size 10 (diameter), height 10, segments 64 |
///
/// Seed 001 gives only the holes' and overhangs' Z dimensions (Table 2: holes 1.5 and 3 mm high,
/// overhangs 3 and 1 mm thick); its figures with the other dimensions were lost, so the block
/// sizes above are our choice.

#include <optional>
#include <string>
#include <vector>

#include "vpsim/geometry/mesh.h"

namespace vpsim::geometry {

/// Options of makeTestPart(); unset values take the part's default (see table above).
struct TestPartOptions {
    std::optional<double> size;     ///< main horizontal size (mm)
    std::optional<double> height;   ///< mm
    std::optional<double> topSize;  ///< frustums: side of the smaller face (mm)
    std::optional<double> depth;    ///< holes, overhangs: extent along y (mm)
    std::optional<double> spacing;  ///< pillars: centre-to-centre distance (mm)
    std::optional<int> count;       ///< pillars: number of pillars
    std::optional<int> segments;    ///< cylinder: number of sides (>= 3)
};

/// Names accepted by makeTestPart(), in table order.
std::vector<std::string> testPartNames();

/// Builds a named test part. @throw InputError for an unknown name or impossible options
/// (non-positive sizes, holes or ledges that do not fit, fewer than 3 segments)
Mesh makeTestPart(const std::string& name, const TestPartOptions& options = {});

/// Square frustum centred on the z axis from z = 0 (side `bottom`) to z = height (side `top`).
Mesh makeFrustum(double bottom, double top, double height);
/// Regular polygonal prism of circumradius `radius`, z in [0, height].
Mesh makeCylinder(double radius, double height, int segments);

/// Union of filled cells of a rectilinear grid (cell (i,j,k) spans xs[i]..xs[i+1] etc.), meshed
/// watertight with shared grid vertices. filled has (xs.size()-1)(ys.size()-1)(zs.size()-1)
/// entries, index i + nx (j + ny k). Cells touching only along an edge give non-manifold
/// edges: avoid such layouts.
Mesh makeCellMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                  const std::vector<double>& zs, const std::vector<char>& filled);

}  // namespace vpsim::geometry
