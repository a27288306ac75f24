#pragma once
/// @file
/// Planar regions (layer cross-sections) as polygons with holes, in mm, and their booleans and
/// offsets through Clipper (libpolyclipping). Clipper works on integers: coordinates are rounded
/// to CLIPPER_UNITS_PER_MM = 1e6 units per mm (1 nm), far below any printable feature, while a
/// 64-bit coordinate still spans +-4.6e12 mm. Areas of results are therefore exact to within
/// about (perimeter x 1 nm).
///
/// Orientation, seen from +z (x right, y up): outer contours counter-clockwise (positive
/// signed area), holes clockwise. An island inside a hole is another outer contour.

#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

namespace vpsim::geometry {

/// Clipper integer units per mm (1 nm resolution).
constexpr double CLIPPER_UNITS_PER_MM = 1e6;

/// A closed polygon (last vertex connects to the first), mm.
using Contour = std::vector<glm::dvec2>;

/// Signed area (mm^2): positive when counter-clockwise.
double signedArea(const Contour& contour);
/// Length of the closed polygon (mm).
double perimeter(const Contour& contour);

/// One connected region: an outer contour (CCW) and its holes (CW).
struct PolygonWithHoles {
    Contour outer;
    std::vector<Contour> holes;
    double area() const;  ///< outer area minus hole areas (mm^2)
};

/// How offset() joins edges at convex corners. Round matches a round beam spot.
enum class JoinType { Round, Miter, Square };
/// How overlapping input contours combine in PolygonSet::fromContours.
enum class FillRule { EvenOdd, NonZero, Positive };

/// A set of disjoint polygons with holes (a Clipper PolyTree flattened to {outer, holes}).
class PolygonSet {
public:
    PolygonSet() = default;
    /// Builds a clean set from arbitrary closed contours (any orientation, overlaps resolved by
    /// `rule`). Positive keeps regions wound counter-clockwise at least once: the union of
    /// consistently oriented solids, which is what slicing produces.
    static PolygonSet fromContours(const std::vector<Contour>& contours,
                                   FillRule rule = FillRule::NonZero);
    /// Axis-aligned rectangle [lo, hi] (mm).
    static PolygonSet rectangle(const glm::dvec2& lo, const glm::dvec2& hi);

    const std::vector<PolygonWithHoles>& parts() const { return mParts; }
    bool empty() const { return mParts.empty(); }
    size_t outerCount() const { return mParts.size(); }
    size_t holeCount() const;
    /// Every contour, outers CCW and holes CW.
    std::vector<Contour> contours() const;

    double area() const;       ///< mm^2
    double perimeter() const;  ///< total length of outer and hole contours (mm)
    /// Bounding box (lo, hi) in mm; lo > hi when empty.
    std::pair<glm::dvec2, glm::dvec2> bounds() const;
    /// Point-in-region test (points on the boundary count as inside).
    bool contains(const glm::dvec2& point) const;

    /// Grows (distance > 0) or shrinks (distance < 0) the region by `distance` mm.
    /// @param arcTolerance largest distance between a round join's arc and its chords (mm)
    /// @param miterLimit   for JoinType::Miter, in multiples of |distance|
    PolygonSet offset(double distance, JoinType join = JoinType::Round, double arcTolerance = 1e-3,
                      double miterLimit = 2.0) const;
    PolygonSet unite(const PolygonSet& other) const;
    PolygonSet difference(const PolygonSet& other) const;
    PolygonSet intersection(const PolygonSet& other) const;
    PolygonSet translated(const glm::dvec2& offset) const;
    /// Rotated counter-clockwise by `angle` (radians) about `centre` (mm); e.g. to hatch at an
    /// angle, rotate by -angle, take intervalsAt() rows, rotate the lines back.
    PolygonSet rotated(double angle, const glm::dvec2& centre = {0.0, 0.0}) const;
    /// Exact x-intervals [x0, x1] of the region on the horizontal line y (mm), sorted. A vertex on
    /// the line is counted by the half-open rule min(y) <= line < max(y) of its edges, the same
    /// rule as rasterizeBinary(), so touching the line at a single point gives nothing.
    std::vector<std::pair<double, double>> intervalsAt(double y) const;

private:
    std::vector<PolygonWithHoles> mParts;
    friend struct PolygonSetAccess;
};

/// Writes an SVG picture of a region (outers filled, holes white, mm axes) atomically.
/// @throw InputError when the file cannot be written
void writePolygonSvg(const std::string& path, const PolygonSet& region, const std::string& title);

}  // namespace vpsim::geometry
