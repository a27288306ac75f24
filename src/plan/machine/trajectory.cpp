#include "vpsim/plan/machine/trajectory.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

#include "vpsim/core/error.h"
#include "vpsim/plan/machine/part_grouping.h"

namespace vpsim::plan {
namespace {

constexpr double SAME_POINT = 1e-9;  // mm: chained vectors share their end points

bool samePoint(double x0, double y0, double x1, double y1) {
    return std::abs(x0 - x1) <= SAME_POINT && std::abs(y0 - y1) <= SAME_POINT;
}

ScanMove markOf(const LaserVector& v, int part) {
    ScanMove m;
    m.laserOn = true;
    m.x0 = v.x0, m.y0 = v.y0, m.x1 = v.x1, m.y1 = v.y1;
    m.power = v.power, m.speed = v.speed, m.part = part;
    return m;
}

/// Closest point to p on segment ab and its parameter t in [0, 1].
glm::dvec2 closestOnSegment(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p,
                            double& t) {
    const glm::dvec2 ab = b - a;
    const double len2 = ab.x * ab.x + ab.y * ab.y;
    t = len2 > 0 ? std::clamp(((p.x - a.x) * ab.x + (p.y - a.y) * ab.y) / len2, 0.0, 1.0) : 0.0;
    return a + t * ab;
}

/// Starts a closed chain at its point closest to `target`, splitting the vector there (seed 002's
/// dummy mark vector) when that point is not a vertex.
std::vector<ScanMove> rotateLoop(std::vector<ScanMove> loop, const glm::dvec2& target) {
    size_t best = 0;
    double bestDistance = INFINITY, bestT = 0;
    for (size_t i = 0; i < loop.size(); ++i) {
        double t;
        glm::dvec2 q =
            closestOnSegment({loop[i].x0, loop[i].y0}, {loop[i].x1, loop[i].y1}, target, t);
        double d = std::hypot(q.x - target.x, q.y - target.y);
        if (d < bestDistance) best = i, bestDistance = d, bestT = t;
    }
    std::vector<ScanMove> out;
    ScanMove first = loop[best], second = loop[best];
    const double sx = first.x0 + bestT * (first.x1 - first.x0);
    const double sy = first.y0 + bestT * (first.y1 - first.y0);
    first.x1 = sx, first.y1 = sy;    // the piece before the split point, scanned last
    second.x0 = sx, second.y0 = sy;  // the piece after it, scanned first
    if (!samePoint(second.x0, second.y0, second.x1, second.y1)) out.push_back(second);
    for (size_t k = 1; k < loop.size(); ++k) out.push_back(loop[(best + k) % loop.size()]);
    if (!samePoint(first.x0, first.y0, first.x1, first.y1)) out.push_back(first);
    return out;
}

/// A part's marks: borders (closed chains) first, each starting nearest the first hatch start,
/// then everything else in the planner's order.
std::vector<ScanMove> partMarks(const std::vector<LaserVector>& vectors,
                                const std::vector<int>& members, int part) {
    std::vector<std::vector<ScanMove>> chains;
    for (int index : members) {
        ScanMove m = markOf(vectors[size_t(index)], part);
        if (!chains.empty() &&
            samePoint(chains.back().back().x1, chains.back().back().y1, m.x0, m.y0))
            chains.back().push_back(m);
        else
            chains.push_back({m});
    }
    std::vector<std::vector<ScanMove>> loops, open;
    for (auto& chain : chains) {
        bool closed = chain.size() >= 3 && samePoint(chain.front().x0, chain.front().y0,
                                                     chain.back().x1, chain.back().y1);
        (closed ? loops : open).push_back(std::move(chain));
    }
    std::vector<ScanMove> marks;
    glm::dvec2 hatchStart = open.empty() ? glm::dvec2{loops[0][0].x0, loops[0][0].y0}
                                         : glm::dvec2{open[0][0].x0, open[0][0].y0};
    for (auto& loop : loops) {
        std::vector<ScanMove> rotated = rotateLoop(std::move(loop), hatchStart);
        marks.insert(marks.end(), rotated.begin(), rotated.end());
    }
    for (auto& chain : open) marks.insert(marks.end(), chain.begin(), chain.end());
    return marks;
}

/// Points of one part as rows along x (one row per y, serpentine).
std::vector<std::vector<const LaserPoint*>> pointRows(const std::vector<LaserPoint>& points,
                                                      const std::vector<int>& members) {
    std::vector<const LaserPoint*> sorted;
    for (int i : members)
        if (points[size_t(i)].energy > 0) sorted.push_back(&points[size_t(i)]);
    std::sort(sorted.begin(), sorted.end(), [](const LaserPoint* a, const LaserPoint* b) {
        return a->y < b->y || (a->y == b->y && a->x < b->x);
    });
    std::vector<std::vector<const LaserPoint*>> rows;
    for (const LaserPoint* p : sorted) {
        if (rows.empty() || std::abs(p->y - rows.back().back()->y) > 1e-6) rows.emplace_back();
        rows.back().push_back(p);
    }
    for (size_t r = 1; r < rows.size(); r += 2) std::reverse(rows[r].begin(), rows[r].end());
    return rows;
}

/// Modulated row scan: point k owns the cell between the midpoints to its neighbours; the row
/// runs at one constant speed (the process speed, or slower where the laser's power cannot give
/// the hottest point its energy at it), and each cell's power gives its point the energy.
std::vector<ScanMove> modulatedRow(const std::vector<const LaserPoint*>& row, double power,
                                   double maxSpeed, int part) {
    std::vector<ScanMove> marks;
    const size_t m = row.size();
    if (m == 1) {
        ScanMove dwell;
        dwell.laserOn = true, dwell.part = part, dwell.power = power;
        dwell.x0 = dwell.x1 = row[0]->x, dwell.y0 = dwell.y1 = row[0]->y;
        dwell.dwell = row[0]->energy / power;
        return {dwell};
    }
    auto x = [&](size_t k) { return row[k]->x; };
    auto cell = [&](size_t k) {
        double lo = k > 0 ? 0.5 * (x(k - 1) + x(k)) : x(0) - 0.5 * (x(1) - x(0));
        double hi = k + 1 < m ? 0.5 * (x(k) + x(k + 1)) : x(k) + 0.5 * (x(k) - x(k - 1));
        return std::pair<double, double>{lo, hi};
    };
    double speed = maxSpeed;
    for (size_t k = 0; k < m; ++k) {
        auto [lo, hi] = cell(k);
        speed = std::min(speed, std::abs(hi - lo) * power / row[k]->energy);
    }
    const double y = row[0]->y;
    for (size_t k = 0; k < m; ++k) {
        auto [lo, hi] = cell(k);
        ScanMove mark;
        mark.laserOn = true, mark.part = part, mark.speed = speed;
        mark.power = row[k]->energy * speed / std::abs(hi - lo);
        mark.x0 = lo, mark.y0 = y, mark.x1 = hi, mark.y1 = y;
        marks.push_back(mark);
    }
    return marks;
}

std::vector<ScanMove> pointMarks(const std::vector<LaserPoint>& points,
                                 const std::vector<int>& members, double power,
                                 const TrajectoryOptions& options, int part) {
    std::vector<ScanMove> marks;
    for (const auto& row : pointRows(points, members)) {
        if (options.points == PointStrategy::Modulated) {
            auto rowMarks = modulatedRow(row, power, options.scanner.process.speed, part);
            marks.insert(marks.end(), rowMarks.begin(), rowMarks.end());
            continue;
        }
        for (const LaserPoint* p : row) {
            ScanMove dwell;
            dwell.laserOn = true, dwell.part = part, dwell.power = power;
            dwell.x0 = dwell.x1 = p->x, dwell.y0 = dwell.y1 = p->y;
            dwell.dwell = p->energy / power;
            marks.push_back(dwell);
        }
    }
    return marks;
}

std::vector<ScanMove> reversed(const std::vector<ScanMove>& marks) {
    std::vector<ScanMove> out(marks.rbegin(), marks.rend());
    for (ScanMove& m : out) std::swap(m.x0, m.x1), std::swap(m.y0, m.y1);
    return out;
}

/// Jump time from the end of `from` to the start of `to`.
double jumpBetween(const std::vector<ScanMove>& from, const std::vector<ScanMove>& to,
                   const AxisLimits& machine) {
    const ScanMove &exit = from.back(), &entry = to.front();
    return jumpTime({exit.x1, exit.y1}, {entry.x0, entry.y0}, endVelocity(exit),
                    startVelocity(entry), machine);
}

/// Jump time inside one part (between its marks that do not chain).
double internalJumps(const std::vector<ScanMove>& marks, const AxisLimits& machine) {
    double t = 0;
    for (size_t k = 1; k < marks.size(); ++k)
        if (!samePoint(marks[k - 1].x1, marks[k - 1].y1, marks[k].x0, marks[k].y0))
            t += jumpTime({marks[k - 1].x1, marks[k - 1].y1}, {marks[k].x0, marks[k].y0},
                          endVelocity(marks[k - 1]), startVelocity(marks[k]), machine);
    return t;
}

/// Picks each part's direction along a fixed order (two states per part, exact, counting the
/// jumps between and inside parts), reverses the parts that run backwards and returns how many
/// do; `cost` becomes the new time of the jumps between parts, `gain` the saving in all jumps.
int chooseDirections(std::vector<std::vector<ScanMove>>& parts, const std::vector<int>& order,
                     const AxisLimits& machine, double& cost, double& gain) {
    const size_t n = order.size();
    if (n < 2) return 0;
    std::vector<std::array<std::vector<ScanMove>, 2>> variants(n);
    for (size_t k = 0; k < n; ++k)
        variants[k] = {parts[size_t(order[k])], reversed(parts[size_t(order[k])])};
    std::vector<std::array<double, 2>> inside(n), best(n);
    std::vector<std::array<int, 2>> from(n, {0, 0});
    double original = 0;
    for (size_t k = 0; k < n; ++k) {
        for (int d = 0; d < 2; ++d)
            inside[k][size_t(d)] = internalJumps(variants[k][size_t(d)], machine);
        original +=
            inside[k][0] + (k > 0 ? jumpBetween(variants[k - 1][0], variants[k][0], machine) : 0.0);
    }
    best[0] = inside[0];
    for (size_t k = 1; k < n; ++k)
        for (int d = 0; d < 2; ++d) {
            best[k][size_t(d)] = INFINITY;
            for (int e = 0; e < 2; ++e) {
                double c = best[k - 1][size_t(e)] + inside[k][size_t(d)] +
                           jumpBetween(variants[k - 1][size_t(e)], variants[k][size_t(d)], machine);
                if (c < best[k][size_t(d)]) best[k][size_t(d)] = c, from[k][size_t(d)] = e;
            }
        }
    int d = best[n - 1][1] < best[n - 1][0] ? 1 : 0;
    gain = original - best[n - 1][size_t(d)];
    int count = 0;
    std::vector<int> chosen(n);
    for (size_t k = n; k-- > 0;) {
        chosen[k] = d;
        d = from[k][size_t(d)];
    }
    cost = 0;
    for (size_t k = 0; k < n; ++k) {
        if (k > 0)
            cost += jumpBetween(variants[k - 1][size_t(chosen[k - 1])],
                                variants[k][size_t(chosen[k])], machine);
        if (chosen[k] == 1) parts[size_t(order[k])] = variants[k][1], ++count;
    }
    return count;
}

}  // namespace

glm::dvec2 endVelocity(const ScanMove& move) {
    if (!move.laserOn || !(move.speed > 0) || move.dwell > 0) return {0.0, 0.0};
    const double dx = move.x1 - move.x0, dy = move.y1 - move.y0, length = std::hypot(dx, dy);
    if (!(length > 0)) return {0.0, 0.0};
    return {dx / length * move.speed, dy / length * move.speed};
}

glm::dvec2 startVelocity(const ScanMove& move) {
    return endVelocity(move);
}

LayerTrajectory buildLayerTrajectory(const LayerPlan& layer, double laserPower,
                                     const TrajectoryOptions& options,
                                     const geometry::PolygonSet* region) {
    PartGroups groups = groupLayerParts(layer, options.partGap, region);
    LayerTrajectory out;
    std::vector<std::vector<ScanMove>> parts;
    for (size_t p = 0; p < groups.vectors.size(); ++p) {
        std::vector<ScanMove> marks;
        if (!groups.vectors[p].empty()) marks = partMarks(layer.vectors, groups.vectors[p], int(p));
        if (!groups.points[p].empty()) {
            if (!(laserPower > 0)) throw InputError("laser points need a positive laser power");
            auto pm = pointMarks(layer.points, groups.points[p], laserPower, options, int(p));
            marks.insert(marks.end(), pm.begin(), pm.end());
        }
        if (!marks.empty()) parts.push_back(std::move(marks));
    }
    out.parts = int(parts.size());
    CostMatrix cost(out.parts);
    for (int i = 0; i < out.parts; ++i)
        for (int j = 0; j < out.parts; ++j) {
            if (i == j) continue;
            const ScanMove &exit = parts[size_t(i)].back(), &entry = parts[size_t(j)].front();
            cost(i, j) = jumpTime({exit.x1, exit.y1}, {entry.x0, entry.y0}, endVelocity(exit),
                                  startVelocity(entry), options.scanner.machine);
        }
    out.order = orderParts(cost, options.order);
    if (options.chooseEntry) {
        double chosen = out.order.cost, gain = 0;
        std::vector<std::vector<ScanMove>> trial = parts;
        int count = chooseDirections(trial, out.order.order, options.scanner.machine, chosen, gain);
        if (gain > 1e-12) {
            parts = std::move(trial);
            out.order.cost = chosen;
            out.order.provenOptimal = false;  // optimal for fixed entries only
            out.reversedParts = count;
        }
    }
    for (int p : out.order.order)
        for (ScanMove mark : parts[size_t(p)]) {
            mark.part = p;
            if (!out.moves.empty()) {
                const ScanMove& last = out.moves.back();
                if (!samePoint(last.x1, last.y1, mark.x0, mark.y0)) {
                    ScanMove jump;
                    jump.x0 = last.x1, jump.y0 = last.y1, jump.x1 = mark.x0, jump.y1 = mark.y0;
                    jump.part = p;
                    out.moves.push_back(jump);
                }
            }
            out.moves.push_back(mark);
        }
    return out;
}

std::vector<LayerTrajectory> buildTrajectories(const ScanPlan& plan,
                                               const TrajectoryOptions& options,
                                               const std::vector<geometry::PolygonSet>* regions) {
    if (regions && regions->size() != plan.layers.size())
        throw InputError("trajectories: " + std::to_string(regions->size()) +
                         " sliced layers for a plan of " + std::to_string(plan.layers.size()));
    std::vector<LayerTrajectory> out;
    for (size_t i = 0; i < plan.layers.size(); ++i)
        out.push_back(buildLayerTrajectory(plan.layers[i], plan.machine.laserPower, options,
                                           regions ? &(*regions)[i] : nullptr));
    return out;
}

void attachTrajectories(ScanPlan& plan, const std::vector<LayerTrajectory>& trajectories) {
    if (trajectories.size() != plan.layers.size())
        throw std::logic_error("attachTrajectories: layer counts differ");
    for (size_t i = 0; i < trajectories.size(); ++i)
        plan.layers[i].trajectory = trajectories[i].moves;
}

}  // namespace vpsim::plan
