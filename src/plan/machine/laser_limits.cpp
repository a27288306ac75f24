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

/// A dot's column along the row and its scan line across it; `merge` grid rows share one line.
struct Dot {
    double along = 0, line = 0, energy = 0;
};

Rows rowsAlong(const std::vector<const LaserPoint*>& dots, double pitch, bool alongX, int merge,
               std::vector<LaserPoint>& merged) {
    auto along = [&](const LaserPoint* p) { return alongX ? p->x : p->y; };
    auto across = [&](const LaserPoint* p) { return alongX ? p->y : p->x; };
    double origin = INFINITY, start = INFINITY;  // the grid's first line and first column
    for (const LaserPoint* p : dots)
        origin = std::min(origin, across(p)), start = std::min(start, along(p));
    // Merge the grid rows k at a time: each dot goes to its group's middle line, and dots of one
    // group in the same column add up.
    std::map<std::pair<long, long>, double> cells;  // (line, column) -> energy
    for (const LaserPoint* p : dots) {
        const long row = std::lround((across(p) - origin) / pitch);
        const long column = std::lround((along(p) - start) / pitch);
        cells[{row / merge, column}] += p->energy;
    }
    merged.clear();
    merged.reserve(cells.size());
    for (const auto& [key, energy] : cells) {
        const double line = origin + (double(key.first * merge) + 0.5 * (merge - 1)) * pitch;
        const double position = start + double(key.second) * pitch;
        merged.push_back(alongX ? LaserPoint{position, line, energy}
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
        const LaserPoint* p = &merged[k++];
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
void dotsToChains(LayerPlan& layer, double pitch, int merge, LimitFit& fit) {
    std::vector<const LaserPoint*> dots;
    for (const LaserPoint& p : layer.points) dots.push_back(&p);
    std::vector<LaserPoint> mergedX, mergedY;  // the dots the chains point to
    Rows x = rowsAlong(dots, pitch, true, merge, mergedX);
    Rows y = rowsAlong(dots, pitch, false, merge, mergedY);
    const Rows& rows = y.chains.size() < x.chains.size() ? y : x;
    std::vector<LaserPoint> kept;
    for (const auto& chain : rows.chains) {
        if (chain.size() < 2) {
            kept.push_back(*chain[0]);
            ++fit.dwellPoints;
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

/// Sets one run's speed and powers (see the file comment) and appends what is kept.
void fitRun(const std::vector<LaserVector>& chain, const LaserLimits& limits,
            std::vector<LaserVector>& out, LimitFit& fit) {
    const LaserVector& first = chain.front();
    double fastest = markSpeedLimit(first.x0, first.y0, first.x1, first.y1, limits.processSpeed);
    for (const LaserVector& v : chain) {
        const double lineEnergy = v.power / v.speed;
        fastest = std::min(fastest, limits.powerMax / lineEnergy);  // full power on the densest
    }
    // At the process limit, or as fast as full power allows. (Slowing short chains to sqrt(a L /
    // 2), which trades mark time against the reversals, was measured: ACES 30% faster, but the dot
    // rows of the inverse planner, cut by dropped dots into runs, 20% slower.)
    const double speed = fastest;
    const double peakPerLineEnergy = std::sqrt(2.0 / M_PI) / limits.beamRadius;
    for (const LaserVector& v : chain) {
        const double lineEnergy = v.power / v.speed;  // mJ/mm
        if (lineEnergy * peakPerLineEnergy < limits.negligibleDose) {
            ++fit.droppedNegligible;
            continue;
        }
        LaserVector fitted = v;
        fitted.speed = speed;
        fitted.power = std::min(lineEnergy * speed, limits.powerMax);
        if (fitted.power < limits.powerMin) {
            if (fitted.power < 0.5 * limits.powerMin) {
                ++fit.droppedBelowMinPower;
                continue;
            }
            fitted.power = limits.powerMin;
            ++fit.raisedToMinPower;
        }
        out.push_back(fitted);
    }
}

/// A chain whose pieces span more than the laser's power range (densest over weakest above
/// powerMax / powerMin) cannot run at one speed with every piece's power in range: it is cut
/// into runs that can, each at its own speed (the scanner changes speed in the short jump
/// between them).
void fitChain(const std::vector<LaserVector>& chain, const LaserLimits& limits,
              std::vector<LaserVector>& out, LimitFit& fit) {
    const double range = limits.powerMin > 0 ? limits.powerMax / limits.powerMin : INFINITY;
    std::vector<LaserVector> run;
    double lo = INFINITY, hi = 0;
    const double peakPerLineEnergy = std::sqrt(2.0 / M_PI) / limits.beamRadius;
    for (const LaserVector& v : chain) {
        const double e = v.power / v.speed;
        if (e * peakPerLineEnergy < limits.negligibleDose) {  // dropped: no say in the speed
            ++fit.droppedNegligible;
            continue;
        }
        if (!run.empty() && std::max(hi, e) > range * std::min(lo, e)) {
            fitRun(run, limits, out, fit);
            run.clear(), lo = INFINITY, hi = 0;
        }
        run.push_back(v), lo = std::min(lo, e), hi = std::max(hi, e);
    }
    if (!run.empty()) fitRun(run, limits, out, fit);
}

void fitVectors(std::vector<LaserVector>& vectors, const LaserLimits& limits, LimitFit& fit) {
    std::vector<LaserVector> out, chain;
    for (const LaserVector& v : vectors) {
        if (!(v.power > 0) || !(v.speed > 0) || !(lengthOf(v) > 0)) {
            ++fit.droppedNegligible;  // no energy, or nothing to scan
            continue;
        }
        if (!chain.empty() && !continues(chain.back(), v)) {
            fitChain(chain, limits, out, fit);
            chain.clear();
        }
        chain.push_back(v);
    }
    if (!chain.empty()) fitChain(chain, limits, out, fit);
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
            {"dwell_points", dwellPoints},
            {"dot_rows_per_line", rowsMerged}};
}

LimitFit fitPlanToLimits(ScanPlan& plan, const LaserLimits& limits, double dotPitch) {
    if (!(limits.powerMax > 0) || !(limits.processSpeed > 0) || !(limits.beamRadius > 0))
        throw InputError("laser limits need a positive power, process speed and beam radius");
    LimitFit fit;
    // One grid row per scan line: merging rows on a fixed lattice aliases the line patterns the
    // optimisers produce (measured on laser-l-shape's inverse plan: 60 um lines on a 40 um
    // lattice beat into 120 um stripes and the IoU fell from 0.972 to 0.923).
    const int merge = 1;
    fit.rowsMerged = merge;
    for (LayerPlan& layer : plan.layers) {
        dropNegligibleDots(layer.points, limits, fit);
        if (dotPitch > 0 && !layer.points.empty())
            dotsToChains(layer, dotPitch, merge, fit);
        else
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
