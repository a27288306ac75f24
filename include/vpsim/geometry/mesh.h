#pragma once
/// @file
/// Indexed triangle mesh of a part, in mm. Every planner and validation reads parts as a Mesh
/// produced by readStl() (checked and repaired) or by makeTestPart().

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace vpsim::geometry {

/// Axis-aligned bounding box (mm). Empty when lo > hi.
struct Bounds {
    glm::dvec3 lo{1e300, 1e300, 1e300};
    glm::dvec3 hi{-1e300, -1e300, -1e300};
    bool empty() const { return lo.x > hi.x; }
    glm::dvec3 size() const { return hi - lo; }
    void add(const glm::dvec3& p);
};

/// Indexed triangle mesh. Triangles list vertex indices counter-clockwise seen from outside
/// (outward normals by the right-hand rule), which readStl() guarantees for accepted files.
struct Mesh {
    std::vector<glm::dvec3> vertices;                ///< positions (mm)
    std::vector<std::array<uint32_t, 3>> triangles;  ///< vertex indices per triangle

    Bounds bounds() const;
    /// Signed enclosed volume (mm^3) by the divergence theorem; positive for a closed mesh with
    /// outward normals, meaningless for an open one.
    double volume() const;
    /// Total surface area (mm^2).
    double area() const;
    /// Unnormalised normal (b-a)x(c-a) of triangle t; its length is twice the triangle's area.
    glm::dvec3 triangleNormal(size_t t) const;
    /// Moves every vertex by `offset` (mm).
    void translate(const glm::dvec3& offset);
    /// Appends another mesh (vertices are not shared).
    void append(const Mesh& other);
};

}  // namespace vpsim::geometry
