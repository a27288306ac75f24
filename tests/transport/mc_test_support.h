#pragma once
// Shared by the transport tests: statistical agreement and batch statistics of (r,z) bin groups.

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "vpsim/transport/photon_mc.h"

namespace vpsim::test {

/// A Henyey-Greenstein medium (coefficients in 1/mm; thickness 0 = semi-infinite).
inline transport::McSetup hgSetup(double mua, double mus, double g, double n, double thickness,
                                  uint64_t photons, uint32_t seed) {
    transport::McSetup s;
    s.optics.mua = mua;
    s.optics.mus = mus;
    s.optics.g = g;
    s.optics.refractiveIndex = n;
    s.thickness = thickness;
    s.photons = photons;
    s.seed = seed;
    return s;
}

/// |a - b| within `sigmas` combined standard errors.
inline bool agree(const transport::Fraction& a, const transport::Fraction& b, double sigmas = 3.0) {
    return std::abs(a.value - b.value) <= sigmas * std::hypot(a.standardError, b.standardError);
}

/// Fraction of launched weight in the (r,z) bins with z index in [z0, z1) and r index in
/// [r0, r1) (all r by default), with its standard error from the per-batch bins.
inline transport::Fraction binsFraction(const transport::McResult& r, uint32_t z0, uint32_t z1,
                                        uint32_t r0 = 0,
                                        uint32_t r1 = std::numeric_limits<uint32_t>::max()) {
    using transport::MC_BATCHES;
    const auto& b = r.setup.bins;
    r1 = std::min(r1, b.rBins);
    const size_t perBatch = size_t(b.rBins) * b.zBins;
    REQUIRE(r.absorbedRZBatches.size() == perBatch * MC_BATCHES);
    double values[MC_BATCHES], sum = 0, squares = 0;
    for (int k = 0; k < MC_BATCHES; ++k) {
        uint64_t q = 0;
        for (uint32_t iz = z0; iz < z1; ++iz)
            for (uint32_t ir = r0; ir < r1; ++ir)
                q += r.absorbedRZBatches[k * perBatch + size_t(iz) * b.rBins + ir];
        values[k] = double(q) / double(r.batches[k].photons * r.launchWeight);
        sum += values[k];
    }
    transport::Fraction f;
    f.value = sum / MC_BATCHES;
    for (double v : values) squares += (v - f.value) * (v - f.value);
    f.standardError = std::sqrt(squares / (MC_BATCHES * (MC_BATCHES - 1.0)));
    return f;
}

}  // namespace vpsim::test
