#include "vpsim/geometry/test_parts.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vpsim/core/error.h"

namespace vpsim::geometry {
namespace {

constexpr double PI = 3.14159265358979323846;

double positive(const std::optional<double>& value, double fallback, const char* what) {
    const double v = value.value_or(fallback);
    if (!(v > 0.0) || !std::isfinite(v)) {
        std::ostringstream s;
        s << "test part option " << what << " must be positive, got " << v;
        throw InputError(s.str(), "", what);
    }
    return v;
}

void addQuad(Mesh& mesh, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    mesh.triangles.push_back({a, b, c});
    mesh.triangles.push_back({a, c, d});
}

Mesh makeBox(const glm::dvec3& lo, const glm::dvec3& hi) {
    return makeCellMesh({lo.x, hi.x}, {lo.y, hi.y}, {lo.z, hi.z}, {1});
}

Mesh makeHoles(double size, double depth) {
    if (size <= 4.0)
        throw InputError("the holes part needs size > 4 mm (its bottom hole is 3 mm wide)", "",
                         "size");
    const std::vector<double> xs{-size / 2, -1.5, -0.75, 0.75, 1.5, size / 2};
    const std::vector<double> zs{0.0, 2.0, 5.0, 7.0, 8.5, 11.0};
    std::vector<char> filled(5 * 5, 1);
    for (int i = 1; i <= 3; ++i)
        filled[i + 5 * 1] = 0;  // bottom hole: x -1.5..1.5, z 2..5 (3 mm high)
    filled[2 + 5 * 3] = 0;      // top hole: x -0.75..0.75, z 7..8.5 (1.5 mm high)
    return makeCellMesh(xs, {-depth / 2, depth / 2}, zs, filled);
}

Mesh makeOverhangs(double size, double depth) {
    if (size <= 4.0)
        throw InputError("the overhangs part needs size > 4 mm (its column is 4 mm wide)", "",
                         "size");
    const std::vector<double> xs{-size / 2, -2.0, 2.0, size / 2};
    const std::vector<double> zs{0.0, 3.0, 4.0, 7.0, 10.0};
    std::vector<char> filled(3 * 4, 0);
    for (int k = 0; k < 4; ++k) filled[1 + 3 * k] = 1;  // the column
    filled[0 + 3 * 3] = 1;                              // top ledge on -x: z 7..10, 3 mm thick
    filled[2 + 3 * 1] = 1;                              // bottom ledge on +x: z 3..4, 1 mm thick
    return makeCellMesh(xs, {-depth / 2, depth / 2}, zs, filled);
}

Mesh makePillars(int count, double side, double height, double spacing) {
    if (count < 1) throw InputError("pillars: count must be at least 1", "", "count");
    if (spacing <= side)
        throw InputError("pillars: spacing must exceed the pillar size (they would touch)", "",
                         "spacing");
    const int columns = int(std::ceil(std::sqrt(double(count))));
    const int rows = (count + columns - 1) / columns;
    Mesh mesh;
    for (int n = 0; n < count; ++n) {
        const double cx = (n % columns - 0.5 * (columns - 1)) * spacing;
        const double cy = (n / columns - 0.5 * (rows - 1)) * spacing;
        mesh.append(
            makeBox({cx - side / 2, cy - side / 2, 0.0}, {cx + side / 2, cy + side / 2, height}));
    }
    return mesh;
}

}  // namespace

std::vector<std::string> testPartNames() {
    return {"box",   "tapered",   "bottom-narrow", "l-shape",
            "holes", "overhangs", "pillars",       "cylinder"};
}

namespace {

/// Rejects options that the part does not use, so a typo never goes unnoticed.
void checkApplicable(const std::string& name, const TestPartOptions& o) {
    const bool frustum = name == "tapered" || name == "bottom-narrow";
    const bool seedPart = name == "holes" || name == "overhangs";
    auto reject = [&](bool given, bool applies, const char* option) {
        if (given && !applies)
            throw InputError(std::string("option ") + option + " does not apply to the " + name +
                             " part");
    };
    reject(o.height.has_value(), !seedPart, "height (fixed by seed 001 for this part)");
    reject(o.topSize.has_value(), frustum, "top-size");
    reject(o.depth.has_value(), seedPart, "depth");
    reject(o.spacing.has_value(), name == "pillars", "spacing");
    reject(o.count.has_value(), name == "pillars", "count");
    reject(o.segments.has_value(), name == "cylinder", "segments");
}

}  // namespace

Mesh makeTestPart(const std::string& name, const TestPartOptions& o) {
    const auto known = testPartNames();
    if (std::find(known.begin(), known.end(), name) != known.end()) checkApplicable(name, o);
    if (name == "box") {
        const double s = positive(o.size, 10.0, "size");
        return makeBox({-s / 2, -s / 2, 0.0}, {s / 2, s / 2, positive(o.height, 10.0, "height")});
    }
    if (name == "tapered" || name == "bottom-narrow") {
        const double wide = positive(o.size, 10.0, "size");
        const double narrow = positive(o.topSize, wide / 2, "top-size");
        const double h = positive(o.height, 10.0, "height");
        return name == "tapered" ? makeFrustum(wide, narrow, h) : makeFrustum(narrow, wide, h);
    }
    if (name == "l-shape") {
        const double s = positive(o.size, 10.0, "size");
        std::vector<char> filled{1, 1, 1, 0};  // cells (0,0) (1,0) (0,1); (1,1) is the notch
        return makeCellMesh({-s / 2, 0.0, s / 2}, {-s / 2, 0.0, s / 2},
                            {0.0, positive(o.height, 10.0, "height")}, filled);
    }
    if (name == "holes")
        return makeHoles(positive(o.size, 10.0, "size"), positive(o.depth, 5.0, "depth"));
    if (name == "overhangs")
        return makeOverhangs(positive(o.size, 16.0, "size"), positive(o.depth, 5.0, "depth"));
    if (name == "pillars") {
        return makePillars(o.count.value_or(4), positive(o.size, 1.0, "size"),
                           positive(o.height, 2.0, "height"), positive(o.spacing, 3.0, "spacing"));
    }
    if (name == "cylinder") {
        const int segments = o.segments.value_or(64);
        if (segments < 3) throw InputError("cylinder: segments must be at least 3", "", "segments");
        return makeCylinder(positive(o.size, 10.0, "size") / 2, positive(o.height, 10.0, "height"),
                            segments);
    }
    std::string names;
    for (const auto& n : testPartNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("unknown test part '" + name + "' (known: " + names + ")");
}

Mesh makeFrustum(double bottom, double top, double height) {
    Mesh mesh;
    const double corner[4][2] = {
        {-1, -1}, {1, -1}, {1, 1}, {-1, 1}};  // counter-clockwise from above
    for (int level = 0; level < 2; ++level) {
        const double half = 0.5 * (level == 0 ? bottom : top);
        for (const auto& c : corner)
            mesh.vertices.emplace_back(c[0] * half, c[1] * half, level * height);
    }
    addQuad(mesh, 0, 3, 2, 1);  // bottom, facing -z
    addQuad(mesh, 4, 5, 6, 7);  // top, facing +z
    for (uint32_t k = 0; k < 4; ++k) addQuad(mesh, k, (k + 1) % 4, 4 + (k + 1) % 4, 4 + k);
    return mesh;
}

Mesh makeCylinder(double radius, double height, int segments) {
    Mesh mesh;
    const auto n = uint32_t(segments);
    for (int level = 0; level < 2; ++level) {
        for (uint32_t k = 0; k < n; ++k) {
            const double angle = 2.0 * PI * k / n;
            mesh.vertices.emplace_back(radius * std::cos(angle), radius * std::sin(angle),
                                       level * height);
        }
    }
    const uint32_t bottomCentre = 2 * n, topCentre = 2 * n + 1;
    mesh.vertices.emplace_back(0.0, 0.0, 0.0);
    mesh.vertices.emplace_back(0.0, 0.0, height);
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t next = (k + 1) % n;
        mesh.triangles.push_back({bottomCentre, next, k});
        mesh.triangles.push_back({topCentre, n + k, n + next});
        addQuad(mesh, k, next, n + next, n + k);
    }
    return mesh;
}

Mesh makeCellMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                  const std::vector<double>& zs, const std::vector<char>& filled) {
    const int n[3] = {int(xs.size()) - 1, int(ys.size()) - 1, int(zs.size()) - 1};
    if (n[0] < 1 || n[1] < 1 || n[2] < 1 || filled.size() != size_t(n[0]) * n[1] * n[2]) {
        throw InputError("cell mesh: grid and filled-cell list do not match");
    }
    const std::vector<double>* coords[3] = {&xs, &ys, &zs};
    auto isFilled = [&](int i, int j, int k) {
        if (i < 0 || j < 0 || k < 0 || i >= n[0] || j >= n[1] || k >= n[2]) return false;
        return filled[size_t(i) + size_t(n[0]) * (j + size_t(n[1]) * k)] != 0;
    };
    Mesh mesh;
    std::vector<int64_t> nodeIndex(size_t(n[0] + 1) * (n[1] + 1) * (n[2] + 1), -1);
    auto node = [&](const int c[3]) {
        int64_t& index =
            nodeIndex[size_t(c[0]) + size_t(n[0] + 1) * (c[1] + size_t(n[1] + 1) * c[2])];
        if (index < 0) {
            index = int64_t(mesh.vertices.size());
            mesh.vertices.emplace_back((*coords[0])[c[0]], (*coords[1])[c[1]], (*coords[2])[c[2]]);
        }
        return uint32_t(index);
    };
    for (int k = 0; k < n[2]; ++k) {
        for (int j = 0; j < n[1]; ++j) {
            for (int i = 0; i < n[0]; ++i) {
                if (!isFilled(i, j, k)) continue;
                const int cell[3] = {i, j, k};
                for (int axis = 0; axis < 3; ++axis) {
                    for (int side = 0; side < 2; ++side) {
                        int nb[3] = {i, j, k};
                        nb[axis] += side ? 1 : -1;
                        if (isFilled(nb[0], nb[1], nb[2])) continue;
                        // Corners in the face's (b, c) axes; b x c = axis, so this order faces
                        // +axis.
                        const int b = (axis + 1) % 3, c = (axis + 2) % 3;
                        const int offsets[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                        uint32_t corner[4];
                        for (int q = 0; q < 4; ++q) {
                            int at[3] = {cell[0], cell[1], cell[2]};
                            at[axis] += side;
                            at[b] += offsets[q][0];
                            at[c] += offsets[q][1];
                            corner[q] = node(at);
                        }
                        if (side == 1) {
                            addQuad(mesh, corner[0], corner[1], corner[2], corner[3]);
                        } else {
                            addQuad(mesh, corner[0], corner[3], corner[2], corner[1]);
                        }
                    }
                }
            }
        }
    }
    return mesh;
}

}  // namespace vpsim::geometry
