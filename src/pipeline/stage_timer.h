#pragma once
// Private to src/pipeline: the wall-clock seconds of each stage of a run (report.json's
// stage_seconds), logged as each finishes.

#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "vpsim/core/log.h"
#include "vpsim/core/text.h"

namespace vpsim::pipeline {

class StageTimer {
public:
    explicit StageTimer(std::vector<std::pair<std::string, double>>& out) : mOut(out) {}
    /// Records the seconds since the previous stage finished (or since construction).
    void finish(const std::string& stage) {
        auto now = std::chrono::steady_clock::now();
        double seconds = std::chrono::duration<double>(now - mStart).count();
        mOut.emplace_back(stage, seconds);
        logInfo("stage " + stage + ": " + formatNumber(seconds, 3) + " s");
        mStart = now;
    }

private:
    std::vector<std::pair<std::string, double>>& mOut;
    std::chrono::steady_clock::time_point mStart = std::chrono::steady_clock::now();
};

}  // namespace vpsim::pipeline
