#include "vpsim/plan/machine/laser_limits.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

namespace vpsim::plan {
namespace {

constexpr double SAME = 1e-9;  // mm: chained vectors share their end points

double lengthOf(const LaserVector& v) {
    return std::hypot(v.x1 - v.x0, v.y1 - v.y0);
}

/// Whether b continues a: starts where a ends, in the same direction.
bool continues(const LaserVector& a, const LaserVector& b) {
    if (std::abs(a.x1 - b.x0) > SAME || std::abs(a.y1 - b.y0) > SAME) return false;
    const double la = lengthOf(a), lb = lengthOf(b);
    if (!(la > 0) || !(lb > 0)) return false;
    const double cross = (a.x1 - a.x0) * (b.y1 - b.y0) - (a.y1 - a.y0) * (b.x1 - b.x0);
    const double dot = (a.x1 - a.x0) * (b.x1 - b.x0) + (a.y1 - a.y0) * (b.y1 - b.y0);
    return dot > 0 && std::abs(cross) <= 1e-9 * la * lb;
}

/// A dot grid's rows along one axis: runs of dots one pitch apart, in serpentine order.
struct Rows {
    std::vector<std::vector<const LaserPoint*>> chains;
    bool alongX = true;
};

/// The rows of `dots` along x (or y): `onGrid` gets the dots on their grid cells (dots sharing
/// a cell add up) and the chains point to them.
Rows rowsAlong(const std::vector<const LaserPoint*>& dots, double pitch, bool alongX,
               std::vector<LaserPoint>& onGrid) {
    auto along = [&](const LaserPoint* p) { return alongX ? p->x : p->y; };
    auto across = [&](const LaserPoint* p) { return alongX ? p->y : p->x; };
    double origin = INFINITY, start = INFINITY;  // the grid's first line and first column
    for (const LaserPoint* p : dots)
        origin = std::min(origin, across(p)), start = std::min(start, along(p));
    // One grid row per scan line: merging rows on a fixed lattice aliases the line patterns the
    // optimisers produce (measured on laser-l-shape's inverse plan: 60 um lines on a 40 um
    // lattice beat into 120 um stripes and the IoU fell from 0.972 to 0.923).
    std::map<std::pair<long, long>, double> cells;  // (line, column) -> energy
    for (const LaserPoint* p : dots) {
        const long row = std::lround((across(p) - origin) / pitch);
        const long column = std::lround((along(p) - start) / pitch);
        cells[{row, column}] += p->energy;
    }
    onGrid.clear();
    onGrid.reserve(cells.size());
    for (const auto& [key, energy] : cells) {
        const double line = origin + double(key.first) * pitch;
        const double position = start + double(key.second) * pitch;
        onGrid.push_back(alongX ? LaserPoint{position, line, energy}
                                : LaserPoint{line, position, energy});
    }
    // `cells` is ordered by line, then column: runs of neighbouring columns are the chains.
    Rows rows;
    rows.alongX = alongX;
    std::vector<size_t> lineStart;  // first chain of each line
    long lastLine = -1, lastColumn = 0;
    size_t k = 0;
    for (const auto& [key, energy] : cells) {
        (void)energy;
        const LaserPoint* p = &onGrid[k++];
        if (key.first != lastLine) lineStart.push_back(rows.chains.size());
        if (key.first == lastLine && key.second == lastColumn + 1)
            rows.chains.back().push_back(p);
        else
            rows.chains.push_back({p});
        lastLine = key.first, lastColumn = key.second;
    }
    // Serpentine: every other scan line runs backwards (its chains reversed, in reverse order).
    lineStart.push_back(rows.chains.size());
    std::vector<std::vector<const LaserPoint*>> ordered;
    for (size_t l = 0; l + 1 < lineStart.size(); ++l) {
        const size_t first = lineStart[l], end = lineStart[l + 1];
        for (size_t c = 0; c < end - first; ++c) {
            auto chain = rows.chains[l % 2 ? end - 1 - c : first + c];
            if (l % 2) std::reverse(chain.begin(), chain.end());
            ordered.push_back(std::move(chain));
        }
    }
    rows.chains = std::move(ordered);
    return rows;
}

/// A layer's dots: chains of two or more become vectors of one pitch per dot (energy per length
/// E / pitch); the others stay points.
void dotsToChains(LayerPlan& layer, double pitch, LimitFit& fit) {
    std::vector<const LaserPoint*> dots;
    for (const LaserPoint& p : layer.points) dots.push_back(&p);
    std::vector<LaserPoint> onGridX, onGridY;  // the dots the chains point to
    Rows x = rowsAlong(dots, pitch, true, onGridX);
    Rows y = rowsAlong(dots, pitch, false, onGridY);
    const Rows& rows = y.chains.size() < x.chains.size() ? y : x;
    std::vector<LaserPoint> kept;
    for (const auto& chain : rows.chains) {
        if (chain.size() < 2) {
            kept.push_back(*chain[0]);
            continue;
        }
        const double step = (rows.alongX ? chain[1]->x - chain[0]->x : chain[1]->y - chain[0]->y);
        const double half = 0.5 * step;  // signed: the chain's direction
        for (const LaserPoint* p : chain) {
            LaserVector v;
            v.x0 = rows.alongX ? p->x - half : p->x, v.y0 = rows.alongX ? p->y : p->y - half;
            v.x1 = rows.alongX ? p->x + half : p->x, v.y1 = rows.alongX ? p->y : p->y + half;
            v.power = p->energy / pitch;  // energy per length at 1 mm/s; refitted below
            v.speed = 1.0;
            layer.vectors.push_back(v);
        }
    }
    fit.pointsAsVectors += (long long)(layer.points.size()) - (long long)(kept.size());
    layer.points = std::move(kept);
}

/// A vector's own peak dose is below the negligible dose.
bool negligible(const LaserVector& v, const LaserLimits& limits) {
    return v.power / v.speed * std::sqrt(2.0 / M_PI) / limits.beamRadius < limits.negligibleDose;
}

/// Sets one run's speed and powers (see the file comment) and appends what is kept. `pathSpeed`
/// caps the speed (the time-optimal speed of the scan path the run belongs to).
void fitRun(const std::vector<LaserVector>& chain, const LaserLimits& limits, double pathSpeed,
            std::vector<LaserVector>& out, LimitFit& fit) {
    const LaserVector& first = chain.front();
    double fastest = markSpeedLimit(first.x0, first.y0, first.x1, first.y1, limits.processSpeed);
    double slowest = 0;  // the weakest piece at the minimum power
    const double range = limits.powerMin > 0 ? limits.powerMax / limits.powerMin : INFINITY;
    double densest = 0;
    for (const LaserVector& v : chain) densest = std::max(densest, v.power / v.speed);
    for (const LaserVector& v : chain) {
        const double lineEnergy = v.power / v.speed;
        // Negligible pieces, and those below the power range (fitChain), have no say.
        if (negligible(v, limits) || lineEnergy * range < densest) continue;
        fastest = std::min(fastest, limits.powerMax / lineEnergy);  // full power on the densest
        slowest = std::max(slowest, limits.powerMin / lineEnergy);
    }
    const double speed = std::min(fastest, std::max(pathSpeed, slowest));
    std::vector<LaserVector> fitted(chain);
    std::vector<char> weak(chain.size(), 0);  // needs less than half the minimum power
    for (size_t k = 0; k < chain.size(); ++k) {
        const LaserVector& v = chain[k];
        fitted[k].speed = speed;
        fitted[k].power = std::min(v.power / v.speed * speed, limits.powerMax);
        weak[k] = fitted[k].power < 0.5 * limits.powerMin;
    }
    // A stretch of weak pieces between two kept ones is dropped when a jump over it is faster
    // than marking it at the minimum power (the jump costs its delays, gapDelay); else it is
    // marked at the minimum power, a little more dose, and the line goes on without a jump.
    for (size_t k = 0; k < chain.size();) {
        if (!weak[k]) {
            ++k;
            continue;
        }
        size_t end = k;
        double length = 0;
        while (end < chain.size() && weak[end]) length += lengthOf(chain[end++]);
        const bool inside = k > 0 && end < chain.size();
        if (inside && length < speed * limits.gapDelay)
            std::fill(weak.begin() + k, weak.begin() + end, 0);
        k = end;
    }
    for (size_t k = 0; k < chain.size(); ++k) {
        if (weak[k]) {
            ++fit.droppedBelowMinPower;
            continue;
        }
        if (fitted[k].power < limits.powerMin) {
            fitted[k].power = limits.powerMin;
            ++fit.raisedToMinPower;
        }
        out.push_back(fitted[k]);
    }
}

/// A chain whose pieces span more than the laser's power range (densest over weakest above
/// powerMax / powerMin) cannot run at one speed with every piece's power in range: it is cut
/// into runs that can, each at its own speed (the scanner changes speed in the short jump
/// between them). Negligible pieces at the chain's ends are dropped, those inside kept.
void fitChain(const std::vector<LaserVector>& chain, const LaserLimits& limits, double pathSpeed,
              std::vector<LaserVector>& out, LimitFit& fit) {
    size_t begin = 0, end = chain.size();
    while (begin < end && negligible(chain[begin], limits)) ++begin;
    while (end > begin && negligible(chain[end - 1], limits)) --end;
    fit.droppedNegligible += (long long)(chain.size() - (end - begin));
    const double range = limits.powerMin > 0 ? limits.powerMax / limits.powerMin : INFINITY;
    // Pieces weaker than the chain's densest over the power range have no say in the cuts:
    // fitRun marks them at the minimum power (at most 1/range of the densest's dose) or drops
    // them, rather than cutting the line into runs joined by jumps for them.
    double densest = 0;
    for (size_t k = begin; k < end; ++k)
        densest = std::max(densest, chain[k].power / chain[k].speed);
    std::vector<LaserVector> run;
    double lo = INFINITY, hi = 0;
    for (size_t k = begin; k < end; ++k) {
        const LaserVector& v = chain[k];
        const double e = v.power / v.speed;
        if (!negligible(v, limits) && e * range >= densest) {
            if (!run.empty() && std::max(hi, e) > range * std::min(lo, e)) {
                fitRun(run, limits, pathSpeed, out, fit);
                run.clear(), lo = INFINITY, hi = 0;
            }
            lo = std::min(lo, e), hi = std::max(hi, e);
        }
        run.push_back(v);
    }
    if (!run.empty()) fitRun(run, limits, pathSpeed, out, fit);
}

/// Whether b lies on a's line ahead of a's end and runs the same way: the next piece of one
/// scan line after a gap.
bool aheadOnLine(const LaserVector& a, const LaserVector& b) {
    const double dx = a.x1 - a.x0, dy = a.y1 - a.y0, length = std::hypot(dx, dy);
    const double ux = dx / length, uy = dy / length;
    const double off = std::abs((b.x0 - a.x1) * uy - (b.y0 - a.y1) * ux);
    const double ahead = (b.x0 - a.x1) * ux + (b.y0 - a.y1) * uy;
    const double bx = b.x1 - b.x0, by = b.y1 - b.y0;
    const double turn = std::abs(bx * uy - by * ux), same = bx * ux + by * uy;
    return off <= SAME && ahead >= -SAME && same > 0 && turn <= 1e-9 * std::hypot(bx, by);
}

/// Per vector, the time-optimal speed sqrt(a L / 2) of its scan path: vectors in plan order that
/// chain or continue one scan line, L their length with the gaps (INFINITY without an
/// acceleration).
std::vector<double> pathSpeeds(const std::vector<LaserVector>& vectors, double acceleration) {
    std::vector<double> speeds(vectors.size(), INFINITY);
    if (!(acceleration > 0)) return speeds;
    size_t first = 0;
    double length = 0;
    for (size_t k = 0; k <= vectors.size(); ++k) {
        const bool goesOn = k > 0 && k < vectors.size() &&
                            ((std::abs(vectors[k - 1].x1 - vectors[k].x0) <= SAME &&
                              std::abs(vectors[k - 1].y1 - vectors[k].y0) <= SAME) ||
                             aheadOnLine(vectors[k - 1], vectors[k]));
        if (k > 0 && !goesOn) {
            std::fill(speeds.begin() + long(first), speeds.begin() + long(k),
                      std::sqrt(0.5 * acceleration * length));
            first = k, length = 0;
        }
        if (k == vectors.size()) break;
        length += lengthOf(vectors[k]);
        if (goesOn)
            length +=
                std::hypot(vectors[k].x0 - vectors[k - 1].x1, vectors[k].y0 - vectors[k - 1].y1);
    }
    return speeds;
}

void fitVectors(std::vector<LaserVector>& vectors, const LaserLimits& limits, LimitFit& fit) {
    std::vector<LaserVector> kept, out, chain;
    for (const LaserVector& v : vectors) {
        if (!(v.power > 0) || !(v.speed > 0) || !(lengthOf(v) > 0))
            ++fit.droppedNegligible;  // no energy, or nothing to scan
        else
            kept.push_back(v);
    }
    const std::vector<double> pathSpeed = pathSpeeds(kept, limits.jumpAcceleration);
    for (size_t k = 0; k < kept.size(); ++k) {
        if (!chain.empty() && !continues(chain.back(), kept[k])) {
            fitChain(chain, limits, pathSpeed[k - 1], out, fit);
            chain.clear();
        }
        chain.push_back(kept[k]);
    }
    if (!chain.empty()) fitChain(chain, limits, pathSpeed.back(), out, fit);
    vectors = std::move(out);
}

void dropNegligibleDots(std::vector<LaserPoint>& points, const LaserLimits& limits, LimitFit& fit) {
    const double peakPerEnergy = 2.0 / (M_PI * limits.beamRadius * limits.beamRadius);
    const size_t before = points.size();
    points.erase(std::remove_if(points.begin(), points.end(),
                                [&](const LaserPoint& p) {
                                    return !(p.energy * peakPerEnergy >= limits.negligibleDose) ||
                                           !(p.energy > 0);
                                }),
                 points.end());
    fit.droppedNegligible += (long long)(before - points.size());
}

std::string number(double value) {
    std::ostringstream out;
    out.precision(3);
    out << value;
    return out.str();
}

}  // namespace

LaserLimits laserLimits(const Machine& machine, double beamRadius, double negligibleDose) {
    LaserLimits limits;
    limits.powerMin = machine.laserPowerMin;
    limits.powerMax = machine.laserPower;
    limits.processSpeed = machine.scanner.process.speed;
    limits.beamRadius = beamRadius;
    limits.negligibleDose = negligibleDose;
    limits.jumpAcceleration = machine.scanner.machine.acceleration;
    limits.gapDelay = machine.scanner.delays.jump + machine.scanner.delays.mark;
    return limits;
}

double markSpeedLimit(double x0, double y0, double x1, double y1, double processSpeed) {
    const double dx = std::abs(x1 - x0), dy = std::abs(y1 - y0), axis = std::max(dx, dy);
    return axis > 0 ? processSpeed * std::hypot(dx, dy) / axis : processSpeed;
}

nlohmann::json LimitFit::toJson() const {
    return {{"dropped_negligible", droppedNegligible},
            {"dropped_below_min_power", droppedBelowMinPower},
            {"raised_to_min_power", raisedToMinPower},
            {"points_as_vectors", pointsAsVectors},
            {"dwell_points", dwellPoints}};
}

LimitFit fitPlanToLimits(ScanPlan& plan, const LaserLimits& limits, double dotPitch) {
    if (!(limits.powerMax > 0) || !(limits.processSpeed > 0) || !(limits.beamRadius > 0))
        throw InputError("laser limits need a positive power, process speed and beam radius");
    LimitFit fit;
    for (LayerPlan& layer : plan.layers) {
        // Dots first become chains, so that negligible dots inside a row keep it going.
        if (dotPitch > 0 && !layer.points.empty()) dotsToChains(layer, dotPitch, fit);
        dropNegligibleDots(layer.points, limits, fit);
        fit.dwellPoints += (long long)layer.points.size();
        fitVectors(layer.vectors, limits, fit);
    }
    plan.machine.laserPowerMin = limits.powerMin;
    return fit;
}

nlohmann::json laserUseJson(const ScanPlan& plan, double powerMin, double processSpeed) {
    double pLo = INFINITY, pHi = 0, vLo = INFINITY, vHi = 0;
    long long above = 0, belowMin = 0, aboveMax = 0, marks = 0;
    const double pMax = plan.machine.laserPower;
    auto power = [&](double p) {
        pLo = std::min(pLo, p), pHi = std::max(pHi, p);
        belowMin += p < powerMin * (1 - 1e-9);
        aboveMax += p > pMax * (1 + 1e-9);
    };
    for (const LayerPlan& layer : plan.layers) {
        for (const LaserVector& v : layer.vectors) {
            ++marks;
            power(v.power);
            vLo = std::min(vLo, v.speed), vHi = std::max(vHi, v.speed);
            above += v.speed > markSpeedLimit(v.x0, v.y0, v.x1, v.y1, processSpeed) * (1 + 1e-9);
        }
        for (const LaserPoint& p : layer.points) {
            (void)p;
            ++marks;
            power(pMax);  // a dwell at the laser's power
        }
    }
    if (marks == 0) return nullptr;
    nlohmann::json speeds = vHi > 0 ? nlohmann::json{vLo, vHi} : nlohmann::json(nullptr);
    return {{"power_mW", {pLo, pHi}},
            {"speed_mm_per_s", speeds},
            {"power_limits_mW", {powerMin, pMax}},
            {"process_speed_mm_per_s", processSpeed},
            {"marks", marks},
            {"marks_above_process_speed", above},
            {"marks_below_min_power", belowMin},
            {"marks_above_max_power", aboveMax}};
}

void checkDoseReachable(const Machine& machine, double targetDose, double lineSpacing) {
    const double speed = machine.scanner.process.speed;
    const double least = machine.laserPowerMin / (speed * lineSpacing);  // mJ/mm^2
    if (!(least > targetDose)) return;
    const double power = targetDose * speed * lineSpacing;
    throw InputError("the target dose " + number(targetDose * 100) + " mJ/cm^2 needs " +
                         number(power) + " mW at the process speed " + number(speed / 1000) +
                         " m/s, below the laser's minimum " + number(machine.laserPowerMin) +
                         " mW: lower machine.laser_power_min to at most " + number(power) +
                         " mW or raise machine.scanner.process_speed to at least " +
                         number(machine.laserPowerMin / (targetDose * lineSpacing) / 1000) + " m/s",
                     "", "machine.laser_power_min");
}

}  // namespace vpsim::plan
