#include <cmath>

#include "vpsim/core/config.h"
#include "vpsim/core/units.h"
#include "vpsim/plan/aces.h"

namespace vpsim::plan {

void readAcesKeys(const ConfigNode& plan, AcesParameters& p) {
    p.homogeneity = plan.numberInRange("homogeneity", 1e-6, 0.5, p.homogeneity);
    std::string edge =
        plan.choice("edge", {"seed-5-percent", "cure-at-contour"},
                    p.edge == AcesEdge::SeedFivePercent ? "seed-5-percent" : "cure-at-contour");
    p.edge = edge == "seed-5-percent" ? AcesEdge::SeedFivePercent : AcesEdge::CureAtContour;
    long long loops = plan.integer("border_count", p.borderCount);
    if (loops < 0 || loops > 100) throw plan.error("border_count", "must be between 0 and 100");
    p.borderCount = int(loops);
    if (plan.has("border_offset")) {
        double offset = plan.quantity("border_offset", dim::LENGTH);
        if (!(offset >= 0)) throw plan.error("border_offset", "must be >= 0");
        p.borderOffset = offset;
    }
}

}  // namespace vpsim::plan
