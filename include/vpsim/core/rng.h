#pragma once
/// @file
/// CPU access to the Monte Carlo random number generator of shaders/include/rng.glsl (the same
/// source the shaders compile), so CPU and GPU streams are bit-identical for a seed and stream.

#include <cstdint>
#include <vector>

namespace vpsim {

/// One xoshiro128** stream, seeded per stream index (e.g. per photon).
class Rng {
public:
    Rng(uint32_t seed, uint32_t stream);
    /// Next 32 random bits.
    uint32_t next();
    /// Uniform float in (0, 1] (never 0).
    float uniform();

private:
    uint32_t mState[4];
};

/// Outputs of streams [firstStream, firstStream + streamCount), `valuesPerStream` each,
/// stream-major: mode 0 raw words, mode 1 the bits of uniform(). The CPU reference for
/// shaders/rng_stream.comp.
std::vector<uint32_t> rngStreamsCpu(uint32_t seed, uint32_t firstStream, uint32_t streamCount,
                                    uint32_t valuesPerStream, uint32_t mode);

}  // namespace vpsim
