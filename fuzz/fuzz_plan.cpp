// libFuzzer target: the scan-plan JSON reader (points, vectors, DLP masks) and its round trip.
#include <cstddef>
#include <cstdint>
#include <string>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/plan/scan_plan.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const vpsim::plan::ScanPlan plan =
            vpsim::plan::scanPlanFromJson(vpsim::parseJsonText(text, "fuzz.json"), "fuzz.json");
        (void)plan.totalEnergy();
        const vpsim::plan::ScanPlan back =
            vpsim::plan::scanPlanFromJson(vpsim::plan::toJson(plan), "round-trip");
        if (back.layers.size() != plan.layers.size()) __builtin_trap();
    } catch (const vpsim::Error&) {}
    return 0;
}
