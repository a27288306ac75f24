#include "vpsim/core/rng.h"

#include <cstring>

#include "vpsim/core/glsl_shim.h"

namespace vpsim::glsl {
namespace {
#include "rng.glsl"
}  // namespace
}  // namespace vpsim::glsl

namespace vpsim {
namespace {

glsl::RngState toState(const uint32_t s[4]) {
    glsl::RngState state;
    state.s0 = s[0];
    state.s1 = s[1];
    state.s2 = s[2];
    state.s3 = s[3];
    return state;
}

void fromState(const glsl::RngState& state, uint32_t s[4]) {
    s[0] = state.s0;
    s[1] = state.s1;
    s[2] = state.s2;
    s[3] = state.s3;
}

}  // namespace

Rng::Rng(uint32_t seed, uint32_t stream) {
    fromState(glsl::rngSeed(seed, stream), mState);
}

uint32_t Rng::next() {
    glsl::RngState state = toState(mState);
    uint32_t value = glsl::rngNext(state);
    fromState(state, mState);
    return value;
}

float Rng::uniform() {
    glsl::RngState state = toState(mState);
    float value = glsl::rngUniform(state);
    fromState(state, mState);
    return value;
}

std::vector<uint32_t> rngStreamsCpu(uint32_t seed, uint32_t firstStream, uint32_t streamCount,
                                    uint32_t valuesPerStream, uint32_t mode) {
    std::vector<uint32_t> words(size_t(streamCount) * valuesPerStream);
    for (uint32_t k = 0; k < streamCount; ++k) {
        glsl::RngState state = glsl::rngSeed(seed, firstStream + k);
        for (uint32_t i = 0; i < valuesPerStream; ++i) {
            uint32_t word;
            if (mode == 0) {
                word = glsl::rngNext(state);
            } else {
                float value = glsl::rngUniform(state);
                std::memcpy(&word, &value, sizeof word);
            }
            words[size_t(k) * valuesPerStream + i] = word;
        }
    }
    return words;
}

}  // namespace vpsim
