#include "vpsim/plan/machine/build_time.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/plan/machine/machine.h"
#include "vpsim/plan/machine/trajectory.h"
#include "vpsim/plan/machine/transition_arc.h"

namespace vpsim::plan {
namespace {

bool chained(const ScanMove& a, const ScanMove& b) {
    return std::abs(a.x1 - b.x0) <= 1e-9 && std::abs(a.y1 - b.y0) <= 1e-9;
}

void addLayer(LayerTime& sum, const LayerTime& t) {
    sum.mark += t.mark, sum.jump += t.jump, sum.delays += t.delays, sum.recoat += t.recoat;
    sum.exposure += t.exposure, sum.marks += t.marks, sum.jumps += t.jumps, sum.arcs += t.arcs;
    sum.jumpDelays += t.jumpDelays, sum.markDelays += t.markDelays;
    sum.polygonDelays += t.polygonDelays;
    sum.marksAboveProcessSpeed += t.marksAboveProcessSpeed;
}

/// Whether mark b continues mark a along the same line at the same speed: one vector whose
/// power changes on the way (a dot row modulated along a vector), with no polygon delay.
bool continues(const ScanMove& a, const ScanMove& b) {
    if (!(a.speed > 0) || a.dwell > 0 || b.dwell > 0 ||
        std::abs(a.speed - b.speed) > 1e-9 * a.speed)
        return false;
    const glm::dvec2 va = endVelocity(a), vb = startVelocity(b);
    return std::abs(va.x - vb.x) <= 1e-9 * a.speed && std::abs(va.y - vb.y) <= 1e-9 * a.speed;
}

/// Accumulates one layer's moves; jumps between marks that do not chain are implied. Every
/// change of speed happens in a jump (laser off): from the last mark's velocity to the next
/// mark's, from rest to the first mark's velocity at the start of the layer (a run-up, counted
/// as jump time), and to rest at its end (a run-out).
class LayerClock {
public:
    explicit LayerClock(const BuildTimeOptions& options) : mOptions(options) {}

    void move(const ScanMove& m, const ScanMove* next) {
        if (!m.laserOn) {
            jump({m.x0, m.y0}, {m.x1, m.y1}, next && next->laserOn ? next : nullptr);
            return;
        }
        if (mLast && mLast->laserOn) {
            if (!chained(*mLast, m))
                jump({mLast->x1, mLast->y1}, {m.x0, m.y0}, &m);
            else if (!continues(*mLast, m))
                ++mTime.polygonDelays;
        } else if (!mStarted) {  // the layer's first move: run up from rest
            mTime.jump += jumpTime({m.x0, m.y0}, {m.x0, m.y0}, {0, 0}, startVelocity(m),
                                   mOptions.scanner.machine);
        }
        ++mTime.marks;
        const double length = std::hypot(m.x1 - m.x0, m.y1 - m.y0);
        if (length > 0 && m.speed > 0) {
            mTime.mark += length / m.speed;
            const double axis =
                m.speed * std::max(std::abs(m.x1 - m.x0), std::abs(m.y1 - m.y0)) / length;
            mTime.marksAboveProcessSpeed += axis > mOptions.scanner.process.speed * (1 + 1e-9);
        }
        mTime.mark += m.dwell;
        mStarted = true;
        mLast = &m;
        mVelocity = endVelocity(m);
    }

    LayerTime finish() {
        if (mLast && mLast->laserOn) ++mTime.markDelays;         // laser off at the end
        const double a = mOptions.scanner.machine.acceleration;  // run out to rest
        mTime.jump += std::max(std::abs(mVelocity.x), std::abs(mVelocity.y)) / a;
        const ScannerDelays& d = mOptions.scanner.delays;
        mTime.delays = double(mTime.jumpDelays) * d.jump + double(mTime.markDelays) * d.mark +
                       double(mTime.polygonDelays) * d.polygon;
        return mTime;
    }

private:
    void jump(const glm::dvec2& from, const glm::dvec2& to, const ScanMove* next) {
        const bool afterMark = mLast && mLast->laserOn;
        mStarted = true;
        const glm::dvec2 v1 = next ? startVelocity(*next) : glm::dvec2{0, 0};
        const double skywriting = jumpTime(from, to, mVelocity, v1, mOptions.scanner.machine);
        if (afterMark && mOptions.transitionArcs && next) {
            if ((v1.x != 0 || v1.y != 0) && (mVelocity.x != 0 || mVelocity.y != 0)) {
                const ArcTransition arc =
                    fastestArcTransition(from, mVelocity, to, v1, mOptions.scanner.machine);
                const ScannerDelays& d = mOptions.scanner.delays;
                if (arc.feasible && arc.time < skywriting + d.jump + d.mark) {
                    mTime.jump += arc.time;
                    ++mTime.arcs;
                    mLast = nullptr;  // no mark delay, no polygon delay into the next mark
                    mVelocity = v1;
                    return;
                }
            }
        }
        mTime.jump += skywriting;
        ++mTime.jumps;
        ++mTime.jumpDelays;
        if (afterMark) ++mTime.markDelays;
        mLast = &mJumpMarker;
        mVelocity = v1;
    }

    const BuildTimeOptions& mOptions;
    LayerTime mTime;
    const ScanMove* mLast = nullptr;
    bool mStarted = false;
    ScanMove mJumpMarker;  // stands for "the last move was a jump" (laserOn = false)
    glm::dvec2 mVelocity{0, 0};
};

std::vector<ScanMove> planOrderMoves(const LayerPlan& layer, double laserPower) {
    std::vector<ScanMove> moves;
    for (const auto& v : layer.vectors) {
        ScanMove m;
        m.laserOn = true;
        m.x0 = v.x0, m.y0 = v.y0, m.x1 = v.x1, m.y1 = v.y1, m.power = v.power, m.speed = v.speed;
        moves.push_back(m);
    }
    for (const auto& p : layer.points) {
        ScanMove m;
        m.laserOn = true;
        m.x0 = m.x1 = p.x, m.y0 = m.y1 = p.y, m.power = laserPower;
        m.dwell = laserPower > 0 ? p.energy / laserPower : 0.0;
        moves.push_back(m);
    }
    return moves;
}

}  // namespace

BuildTimeOptions buildTimeOptions(const Machine& machine) {
    BuildTimeOptions options;
    options.scanner = machine.scanner;
    options.recoatTime = machine.recoatTime;
    options.projectorIrradiance = machine.projectorIrradiance;
    return options;
}

BuildTimeOptions buildTimeOptionsFromConfig(const ConfigNode& machine) {
    return buildTimeOptions(machineFromConfig(machine));
}

LayerTime layerMoveTime(const std::vector<ScanMove>& moves, const BuildTimeOptions& options) {
    LayerClock clock(options);
    for (size_t i = 0; i < moves.size(); ++i)
        clock.move(moves[i], i + 1 < moves.size() ? &moves[i + 1] : nullptr);
    return clock.finish();
}

BuildTime estimateBuildTime(const ScanPlan& plan, const BuildTimeOptions& options) {
    BuildTime out;
    for (const LayerPlan& layer : plan.layers) {
        LayerTime t = layer.trajectory.empty()
                          ? layerMoveTime(planOrderMoves(layer, plan.machine.laserPower), options)
                          : layerMoveTime(layer.trajectory, options);
        for (const MaskImage& mask : layer.masks) {
            if (!(options.projectorIrradiance > 0))
                throw InputError("a DLP build time needs a positive projector irradiance", "",
                                 "machine.projector_irradiance");
            float peak = 0;
            for (float d : mask.dose) peak = std::max(peak, d);
            t.exposure += double(peak) / options.projectorIrradiance;
        }
        t.recoat = options.recoatTime;
        addLayer(out.sum, t);
        out.layers.push_back(t);
    }
    return out;
}

nlohmann::json BuildTime::toJson() const {
    nlohmann::json perLayer = nlohmann::json::array();
    for (const LayerTime& t : layers) perLayer.push_back(t.total());
    return {{"total", sum.total()},
            {"mark", sum.mark},
            {"jump", sum.jump},
            {"delays", sum.delays},
            {"recoat", sum.recoat},
            {"exposure", sum.exposure},
            {"counts",
             {{"layers", layers.size()},
              {"marks", sum.marks},
              {"jumps", sum.jumps},
              {"transition_arcs", sum.arcs},
              {"jump_delays", sum.jumpDelays},
              {"mark_delays", sum.markDelays},
              {"polygon_delays", sum.polygonDelays},
              {"marks_above_process_speed", sum.marksAboveProcessSpeed}}},
            {"per_layer", perLayer}};
}

}  // namespace vpsim::plan
