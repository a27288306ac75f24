// Benchmark: applying the cure model to a 1e8-voxel dose array (cured mask and FPP conversion),
// compared with a plain memcpy of the dose bytes measured in the same run (the memory-bandwidth
// floor; docs/PLATFORM.md quotes ~30 GB/s for 2 threads on the reference machine). Prints JSON.
//
// Usage: bench_cure [voxels] [repetitions]   (defaults 1e8 and 5; best time of the repetitions)

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <random>
#include <thread>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "vpsim/cure/cure_field.h"
#include "vpsim/cure/fpp_law.h"

namespace {

template <class Work>
double bestSeconds(int repetitions, const Work& work) {
    double best = 1e300;
    for (int r = 0; r < repetitions; ++r) {
        auto start = std::chrono::steady_clock::now();
        work();
        best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
}

}  // namespace

int main(int argc, char** argv) {
    const size_t voxels = argc > 1 ? size_t(std::atof(argv[1])) : size_t(100000000);
    const int repetitions = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
    const size_t chunk = size_t(1) << 20;

    // Doses spread around the iso-level (fixed seed), touched once so page faults are not timed.
    std::vector<float> dose(voxels), copy(voxels), conversion(voxels);
    std::vector<uint8_t> mask(voxels);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uniform(0.0f, 2.0f);
    for (size_t i = 0; i < std::min(voxels, size_t(1) << 16); ++i) dose[i] = uniform(rng);
    for (size_t i = size_t(1) << 16; i < voxels; ++i) dose[i] = dose[i & 0xFFFF];
    std::memcpy(copy.data(), dose.data(), voxels * sizeof(float));
    std::memset(mask.data(), 0, voxels);
    std::memset(conversion.data(), 0, voxels * sizeof(float));

    vpsim::cure::FppLaw model(0.528, 0.276);
    const double floatBytes = double(voxels) * sizeof(float);

    double memcpySerial = bestSeconds(
        repetitions, [&] { std::memcpy(copy.data(), dose.data(), voxels * sizeof(float)); });
    double memcpyParallel = bestSeconds(repetitions, [&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, voxels, chunk),
                          [&](const tbb::blocked_range<size_t>& r) {
                              std::memcpy(copy.data() + r.begin(), dose.data() + r.begin(),
                                          r.size() * sizeof(float));
                          });
    });
    double maskTime = bestSeconds(
        repetitions, [&] { vpsim::cure::cureMask(model, dose.data(), voxels, mask.data()); });
    double conversionTime = bestSeconds(repetitions, [&] {
        vpsim::cure::conversionField(model, dose.data(), voxels, conversion.data());
    });

    // Keep the results observable so nothing is optimised away.
    size_t cured = 0;
    for (size_t i = 0; i < voxels; i += 4099) cured += mask[i];

    const double memcpyBest = std::min(memcpySerial, memcpyParallel);
    const double maskBytes = floatBytes + double(voxels);  // read floats, write bytes
    const double conversionBytes = 2.0 * floatBytes;       // read floats, write floats
    nlohmann::json out;
    out["benchmark"] = "cure";
    out["voxels"] = voxels;
    out["repetitions"] = repetitions;
    out["threads"] = std::thread::hardware_concurrency();
    out["memcpy_dose_bytes_s"] = {{"serial", memcpySerial}, {"parallel", memcpyParallel}};
    out["memcpy_GB_per_s"] = 2.0 * floatBytes / memcpyBest / 1e9;  // read + write
    out["cure_mask_s"] = maskTime;
    out["cure_mask_voxels_per_s"] = double(voxels) / maskTime;
    out["cure_mask_GB_per_s"] = maskBytes / maskTime / 1e9;
    // The figure of merit: bandwidth the mask reaches as a fraction of memcpy's (1 = memory-bound).
    out["cure_mask_fraction_of_memcpy_bandwidth"] =
        (maskBytes / maskTime) / (2.0 * floatBytes / memcpyBest);
    // < 1 is possible: the mask writes 1 byte per voxel where memcpy writes 4.
    out["cure_mask_time_over_memcpy"] = maskTime / memcpyBest;
    out["fpp_conversion_s"] = conversionTime;
    out["fpp_conversion_voxels_per_s"] = double(voxels) / conversionTime;
    out["fpp_conversion_GB_per_s"] = conversionBytes / conversionTime / 1e9;
    out["fpp_conversion_time_over_memcpy"] = conversionTime / memcpyBest;
    out["fpp_conversion_fraction_of_memcpy_bandwidth"] =
        (conversionBytes / conversionTime) / (2.0 * floatBytes / memcpyBest);
    out["design_floor_GB_per_s"] = 30.0;
    out["cure_mask_fraction_of_design_floor"] = maskBytes / maskTime / 1e9 / 30.0;
    out["sampled_cured_voxels"] = cured;
    std::cout << out.dump(2) << std::endl;
    return 0;
}
