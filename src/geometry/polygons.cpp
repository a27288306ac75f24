#include "vpsim/geometry/polygons.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <polyclipping/clipper.hpp>

namespace vpsim::geometry {

namespace cl = ClipperLib;

/// Conversions between PolygonSet (mm, double) and Clipper paths (1 nm integers).
struct PolygonSetAccess {
    static cl::Path toPath(const Contour& contour) {
        cl::Path path;
        path.reserve(contour.size());
        for (const auto& p : contour) {
            path.emplace_back(cl::cInt(std::llround(p.x * CLIPPER_UNITS_PER_MM)),
                              cl::cInt(std::llround(p.y * CLIPPER_UNITS_PER_MM)));
        }
        return path;
    }
    static Contour fromPath(const cl::Path& path) {
        Contour contour;
        contour.reserve(path.size());
        for (const auto& p : path) {
            contour.emplace_back(double(p.X) / CLIPPER_UNITS_PER_MM,
                                 double(p.Y) / CLIPPER_UNITS_PER_MM);
        }
        return contour;
    }
    static cl::Paths toPaths(const PolygonSet& set) {
        cl::Paths paths;
        for (const auto& part : set.mParts) {
            paths.push_back(toPath(part.outer));
            for (const auto& hole : part.holes) paths.push_back(toPath(hole));
        }
        return paths;
    }
    /// Flattens a PolyTree: every outer node becomes a part with its child holes; islands inside
    /// holes are visited as further outers.
    static PolygonSet fromTree(const cl::PolyTree& tree) {
        PolygonSet set;
        std::vector<const cl::PolyNode*> stack(tree.Childs.begin(), tree.Childs.end());
        while (!stack.empty()) {
            const cl::PolyNode* outer = stack.back();
            stack.pop_back();
            PolygonWithHoles part;
            part.outer = fromPath(outer->Contour);
            for (const cl::PolyNode* hole : outer->Childs) {
                part.holes.push_back(fromPath(hole->Contour));
                stack.insert(stack.end(), hole->Childs.begin(), hole->Childs.end());
            }
            set.mParts.push_back(std::move(part));
        }
        return set;
    }
    static PolygonSet execute(cl::ClipType type, const cl::Paths& subject, const cl::Paths& clip,
                              cl::PolyFillType fill) {
        cl::Clipper clipper;
        clipper.AddPaths(subject, cl::ptSubject, true);
        if (!clip.empty()) clipper.AddPaths(clip, cl::ptClip, true);
        cl::PolyTree tree;
        clipper.Execute(type, tree, fill, fill);
        return fromTree(tree);
    }
};

using A = PolygonSetAccess;

double signedArea(const Contour& c) {
    double sum = 0.0;
    for (size_t i = 0, n = c.size(); i < n; ++i) {
        const glm::dvec2& a = c[i];
        const glm::dvec2& b = c[(i + 1) % n];
        sum += a.x * b.y - a.y * b.x;
    }
    return 0.5 * sum;
}

double perimeter(const Contour& c) {
    double sum = 0.0;
    for (size_t i = 0, n = c.size(); i < n; ++i) sum += glm::length(c[(i + 1) % n] - c[i]);
    return sum;
}

double PolygonWithHoles::area() const {
    double a = signedArea(outer);
    for (const auto& h : holes) a += signedArea(h);  // holes are clockwise: negative
    return a;
}

PolygonSet PolygonSet::fromContours(const std::vector<Contour>& contours, FillRule rule) {
    cl::Paths paths;
    paths.reserve(contours.size());
    for (const auto& c : contours) {
        if (c.size() >= 3) paths.push_back(A::toPath(c));
    }
    const cl::PolyFillType fill = rule == FillRule::EvenOdd   ? cl::pftEvenOdd
                                  : rule == FillRule::NonZero ? cl::pftNonZero
                                                              : cl::pftPositive;
    return A::execute(cl::ctUnion, paths, {}, fill);
}

PolygonSet PolygonSet::rectangle(const glm::dvec2& lo, const glm::dvec2& hi) {
    return fromContours({{lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}});
}

size_t PolygonSet::holeCount() const {
    size_t n = 0;
    for (const auto& p : mParts) n += p.holes.size();
    return n;
}

std::vector<Contour> PolygonSet::contours() const {
    std::vector<Contour> all;
    for (const auto& p : mParts) {
        all.push_back(p.outer);
        all.insert(all.end(), p.holes.begin(), p.holes.end());
    }
    return all;
}

double PolygonSet::area() const {
    double a = 0.0;
    for (const auto& p : mParts) a += p.area();
    return a;
}

double PolygonSet::perimeter() const {
    double length = 0.0;
    for (const auto& p : mParts) {
        length += geometry::perimeter(p.outer);
        for (const auto& h : p.holes) length += geometry::perimeter(h);
    }
    return length;
}

std::pair<glm::dvec2, glm::dvec2> PolygonSet::bounds() const {
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& p : mParts) {
        for (const auto& v : p.outer) {
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
    }
    return {lo, hi};
}

bool PolygonSet::contains(const glm::dvec2& point) const {
    const cl::IntPoint q(cl::cInt(std::llround(point.x * CLIPPER_UNITS_PER_MM)),
                         cl::cInt(std::llround(point.y * CLIPPER_UNITS_PER_MM)));
    for (const auto& p : mParts) {
        if (cl::PointInPolygon(q, A::toPath(p.outer)) == 0) continue;
        bool inHole = false;
        for (const auto& h : p.holes) inHole = inHole || cl::PointInPolygon(q, A::toPath(h)) == 1;
        if (!inHole) return true;
    }
    return false;
}

PolygonSet PolygonSet::offset(double distance, JoinType join, double arcTolerance,
                              double miterLimit) const {
    const cl::JoinType jt = join == JoinType::Round   ? cl::jtRound
                            : join == JoinType::Miter ? cl::jtMiter
                                                      : cl::jtSquare;
    cl::ClipperOffset offsetter(miterLimit, std::max(arcTolerance, 1e-6) * CLIPPER_UNITS_PER_MM);
    offsetter.AddPaths(A::toPaths(*this), jt, cl::etClosedPolygon);
    cl::PolyTree tree;
    offsetter.Execute(tree, distance * CLIPPER_UNITS_PER_MM);
    return A::fromTree(tree);
}

PolygonSet PolygonSet::unite(const PolygonSet& other) const {
    return A::execute(cl::ctUnion, A::toPaths(*this), A::toPaths(other), cl::pftNonZero);
}

PolygonSet PolygonSet::difference(const PolygonSet& other) const {
    return A::execute(cl::ctDifference, A::toPaths(*this), A::toPaths(other), cl::pftNonZero);
}

PolygonSet PolygonSet::intersection(const PolygonSet& other) const {
    return A::execute(cl::ctIntersection, A::toPaths(*this), A::toPaths(other), cl::pftNonZero);
}

PolygonSet PolygonSet::translated(const glm::dvec2& offset) const {
    PolygonSet moved = *this;
    for (auto& p : moved.mParts) {
        for (auto& v : p.outer) v += offset;
        for (auto& h : p.holes) {
            for (auto& v : h) v += offset;
        }
    }
    // Re-round to the 1 nm grid so every PolygonSet holds Clipper-representable coordinates.
    return moved.unite(PolygonSet());
}

PolygonSet PolygonSet::rotated(double angle, const glm::dvec2& centre) const {
    const double c = std::cos(angle), s = std::sin(angle);
    auto turn = [&](glm::dvec2 p) {
        p -= centre;
        return centre + glm::dvec2(c * p.x - s * p.y, s * p.x + c * p.y);
    };
    std::vector<Contour> all = contours();
    for (auto& contour : all) {
        for (auto& p : contour) p = turn(p);
    }
    return fromContours(all, FillRule::NonZero);  // rotation keeps orientation
}

std::vector<std::pair<double, double>> PolygonSet::intervalsAt(double y) const {
    std::vector<double> xs;
    for (const auto& contour : contours()) {
        for (size_t i = 0, n = contour.size(); i < n; ++i) {
            const glm::dvec2& a = contour[i];
            const glm::dvec2& b = contour[(i + 1) % n];
            if ((a.y <= y) != (b.y <= y)) xs.push_back(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
        }
    }
    std::sort(xs.begin(), xs.end());
    std::vector<std::pair<double, double>> intervals;
    for (size_t i = 0; i + 1 < xs.size(); i += 2) {  // disjoint clean region: even-odd pairs
        if (xs[i + 1] > xs[i]) intervals.emplace_back(xs[i], xs[i + 1]);
    }
    return intervals;
}

}  // namespace vpsim::geometry
