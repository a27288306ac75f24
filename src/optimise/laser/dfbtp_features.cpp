#include "dfbtp_features.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "vpsim/optimise/solvers/qp_active_set.h"

namespace vpsim::optimise::dfbtp {

double bilinear(const SurfaceGrid& g, double x, double y) {
    double fx = (x - g.originX) / g.pitch - 0.5, fy = (y - g.originY) / g.pitch - 0.5;
    int i = int(std::floor(fx)), j = int(std::floor(fy));
    double tx = fx - i, ty = fy - j, sum = 0;
    for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di) {
            int ii = std::clamp(i + di, 0, g.nx - 1), jj = std::clamp(j + dj, 0, g.ny - 1);
            sum += (di ? tx : 1 - tx) * (dj ? ty : 1 - ty) * g.at(ii, jj);
        }
    return sum;
}

double missingAt(const LayerContext& c, double x, double y) {
    return std::max(bilinear(c.goal, x, y) - bilinear(c.planned, x, y), 0.0);
}

EdgeRows planEdge(const plan::EdgeBlock& e, const LayerContext& c) {
    const DfbtpParameters& p = *c.p;
    std::vector<double> us, ecs, lifts, rows;
    for (double u = -c.reff; u <= c.roff + c.reff + 1e-12; u += p.gridPitch) {
        double sum = 0;
        for (int k = 0; k < 5; ++k) {
            double s = e.start + (k + 0.5) / 5 * (e.end - e.start);
            glm::dvec2 q = e.a + s * e.tangent + u * e.normal;
            sum += missingAt(c, q.x, q.y);
        }
        us.push_back(u);
        ecs.push_back(sum / 5);
        lifts.push_back(u < 0 ? p.liftOutside : u < c.roff ? p.liftEdge : p.liftInside);
    }
    for (double u = -c.reff; u <= c.roff + 1e-12; u += p.dotPitch) rows.push_back(u);
    const int m = int(us.size()), n = int(rows.size());
    Eigen::MatrixXd K(m, n);
    Eigen::VectorXd b(m), d(m);
    const double amp = c.efficiency * std::sqrt(2.0 / M_PI) / c.w;
    for (int i = 0; i < m; ++i) {
        b(i) = ecs[i];
        d(i) = ecs[i] + lifts[i] * c.etar;
        for (int j = 0; j < n; ++j) {
            double du = (us[i] - rows[j]) / c.w;
            K(i, j) = amp * std::exp(-2 * du * du);
        }
    }
    LsqQpResult qp = solveLsqQp(K, b, K, d, 1e-12 * K.squaredNorm() / n);
    const double power = p.aces.laserPower;
    EdgeRows out;
    out.offsets = rows;
    out.before.resize(size_t(n));
    out.after.resize(size_t(n));
    for (int j = 0; j < n; ++j) {
        const double lambda = qp.x(j);
        const glm::dvec2 a = e.a + e.start * e.tangent + rows[j] * e.normal,
                         z = e.a + e.end * e.tangent + rows[j] * e.normal;
        out.rows.push_back(
            {a.x, a.y, z.x, z.y, power, lambda > 1e-9 * c.etar * c.w ? power / lambda : 0.0});
    }
    return out;
}

std::vector<CornerDot> rowLineDots(const plan::CornerBlock& corner,
                                   const std::vector<plan::EdgeBlock>& edges,
                                   const std::vector<EdgeRows>& rows, int incoming, int outgoing,
                                   double pitch) {
    std::vector<CornerDot> dots;
    for (int side = 0; side < 2; ++side) {
        const int k = side == 0 ? incoming : outgoing;
        const plan::EdgeBlock& e = edges[size_t(k)];
        const double length = glm::length(e.b - e.a);
        const int pieces = int(std::floor((2 * corner.halfSize + 1e-9) / pitch));
        for (size_t j = 0; j < rows[size_t(k)].offsets.size(); ++j)
            for (int i = 0; i < pieces; ++i) {
                const double s0 = side == 0 ? e.end + i * pitch : e.start - (i + 1) * pitch;
                const double s1 = s0 + pitch;
                if (s0 < -corner.halfSize - 1e-9 || s1 > length + corner.halfSize + 1e-9) continue;
                const glm::dvec2 n = rows[size_t(k)].offsets[j] * e.normal;
                CornerDot d;
                d.edge = k, d.row = int(j), d.after = side == 0;
                d.from = e.a + s0 * e.tangent + n, d.to = e.a + s1 * e.tangent + n;
                d.at = 0.5 * (d.from + d.to);
                dots.push_back(d);
            }
    }
    return dots;
}

std::vector<CornerDot> gridDots(const plan::CornerBlock& corner, double pitch) {
    std::vector<CornerDot> dots;
    const int reach = int(std::floor(corner.halfSize / pitch));
    for (int j = -reach; j <= reach; ++j)
        for (int i = -reach; i <= reach; ++i) {
            CornerDot d;
            d.at = corner.vertex + pitch * glm::dvec2(i, j);
            dots.push_back(d);
        }
    return dots;
}

int planCorner(const plan::CornerBlock& corner, const std::vector<CornerDot>& candidates,
               LayerContext& c, std::vector<EdgeRows>& rows, plan::LayerPlan& out) {
    const DfbtpParameters& p = *c.p;
    const SurfaceGrid& g = c.planned;
    const geometry::PolygonSet grown = c.region->offset(0.5 * c.w);
    std::vector<CornerDot> dots;
    for (const CornerDot& d : candidates) {
        const glm::dvec2 q = d.at;
        if (!grown.contains(q)) continue;
        double need = 0;  // worth a variable only where something is missing nearby
        for (glm::dvec2 o : {glm::dvec2(0), glm::dvec2(0.5 * c.w, 0), glm::dvec2(-0.5 * c.w, 0),
                             glm::dvec2(0, 0.5 * c.w), glm::dvec2(0, -0.5 * c.w)})
            need = std::max(need, missingAt(c, q.x + o.x, q.y + o.y));
        if (need > 0.01 * c.etar) dots.push_back(d);
    }
    if (dots.empty()) return 0;
    const double extent = corner.halfSize + c.reff;
    std::vector<size_t> cells;
    for (int j = 0; j < g.ny; ++j) {
        if (std::abs(g.centreY(j) - corner.vertex.y) > extent) continue;
        for (int i = 0; i < g.nx; ++i)
            if (std::abs(g.centreX(i) - corner.vertex.x) <= extent)
                cells.push_back(size_t(j) * g.nx + i);
    }
    const int m = int(cells.size()), n = int(dots.size());
    Eigen::MatrixXd K(m, n);
    Eigen::VectorXd b(m), d(m);
    const double amp = c.efficiency * 2.0 / (M_PI * c.w * c.w);
    for (int r = 0; r < m; ++r) {
        size_t cell = cells[r];
        double x = g.centreX(int(cell % g.nx)), y = g.centreY(int(cell / g.nx));
        double missing = std::max(double(c.goal.values[cell]) - c.planned.values[cell], 0.0);
        double lift = !c.inside[cell] ? p.liftOutside : c.middle[cell] ? p.liftInside : p.liftEdge;
        b(r) = missing;
        d(r) = missing + lift * c.etar;
        for (int k = 0; k < n; ++k) {
            double dx = (x - dots[k].at.x) / c.w, dy = (y - dots[k].at.y) / c.w;
            K(r, k) = amp * std::exp(-2 * (dx * dx + dy * dy));
        }
    }
    LsqQpResult qp = solveLsqQp(K, b, K, d, 1e-12 * K.squaredNorm() / n);
    Eigen::VectorXd added = K * qp.x;
    for (int r = 0; r < m; ++r) c.planned.values[cells[r]] += float(added(r));
    int placed = 0;
    const double power = p.aces.laserPower;
    for (int k = 0; k < n; ++k) {
        if (!(qp.x(k) > 0)) continue;
        ++placed;
        const CornerDot& dot = dots[k];
        if (dot.edge < 0) {
            out.points.push_back({dot.at.x, dot.at.y, qp.x(k)});
            continue;
        }
        const double lambda = qp.x(k) / glm::length(dot.to - dot.from);  // mJ/mm along the piece
        EdgeRows& r = rows[size_t(dot.edge)];
        (dot.after ? r.after : r.before)[size_t(dot.row)].push_back(
            {dot.from.x, dot.from.y, dot.to.x, dot.to.y, power, power / lambda});
    }
    return placed;
}

std::vector<plan::LaserVector> edgeLoops(const std::vector<plan::EdgeBlock>& edges,
                                         std::vector<EdgeRows>& rows) {
    std::vector<plan::LaserVector> out;
    auto add = [&](const plan::LaserVector& v) {
        if (v.speed > 0) out.push_back(v);
    };
    for (size_t first = 0; first < edges.size();) {
        size_t last = first;  // edges of one contour follow each other, end to start
        while (last + 1 < edges.size() && glm::length(edges[last].b - edges[last + 1].a) <= 1e-9)
            ++last;
        size_t offsets = 0;
        for (size_t e = first; e <= last; ++e) offsets = std::max(offsets, rows[e].rows.size());
        for (size_t j = 0; j < offsets; ++j)
            for (size_t e = first; e <= last; ++e) {
                if (j >= rows[e].rows.size()) continue;
                std::vector<plan::LaserVector>& before = rows[e].before[j];
                std::reverse(before.begin(), before.end());  // planned outwards from the row
                for (const auto& v : before) add(v);
                add(rows[e].rows[j]);
                for (const auto& v : rows[e].after[j]) add(v);
            }
        first = last + 1;
    }
    return out;
}

void edgesAt(const plan::CornerBlock& corner, const std::vector<plan::EdgeBlock>& edges,
             int& incoming, int& outgoing) {
    incoming = outgoing = -1;
    for (size_t e = 0; e < edges.size(); ++e) {
        if (glm::length(edges[e].b - corner.vertex) <= 1e-9) incoming = int(e);
        if (glm::length(edges[e].a - corner.vertex) <= 1e-9) outgoing = int(e);
    }
}

}  // namespace vpsim::optimise::dfbtp
