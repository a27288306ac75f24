#include "vpsim/geometry/mesh.h"

#include <glm/geometric.hpp>

namespace vpsim::geometry {

void Bounds::add(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
}

Bounds Mesh::bounds() const {
    Bounds b;
    for (const auto& v : vertices) b.add(v);
    return b;
}

double Mesh::volume() const {
    // Sum of signed tetrahedra against the bounding-box centre (less cancellation than the origin).
    const Bounds b = bounds();
    const glm::dvec3 c = b.empty() ? glm::dvec3(0.0) : 0.5 * (b.lo + b.hi);
    double sum = 0.0;
    for (const auto& t : triangles) {
        sum += glm::dot(vertices[t[0]] - c, glm::cross(vertices[t[1]] - c, vertices[t[2]] - c));
    }
    return sum / 6.0;
}

double Mesh::area() const {
    double sum = 0.0;
    for (size_t t = 0; t < triangles.size(); ++t) sum += glm::length(triangleNormal(t));
    return 0.5 * sum;
}

glm::dvec3 Mesh::triangleNormal(size_t t) const {
    const auto& tri = triangles[t];
    const glm::dvec3& a = vertices[tri[0]];
    return glm::cross(vertices[tri[1]] - a, vertices[tri[2]] - a);
}

void Mesh::translate(const glm::dvec3& offset) {
    for (auto& v : vertices) v += offset;
}

void Mesh::append(const Mesh& other) {
    const auto base = static_cast<uint32_t>(vertices.size());
    vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
    for (const auto& t : other.triangles)
        triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

}  // namespace vpsim::geometry
