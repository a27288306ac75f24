#include <catch2/catch.hpp>

#include <cstddef>

#include "support/spirv_reflect.h"
#include "vpsim/core/glsl_shim.h"
#include "vpsim/shaders/layout_probe_spv.h"

namespace vpsim::glsl {
#include "photon_types.glsl"
#include "shared_structs.glsl"
}  // namespace vpsim::glsl

using namespace vpsim;

namespace {

struct MemberLayout {
    const char* name;
    size_t offset;
};

/// Compares C++ offsetof/sizeof with the std430 offsets and array stride glslang assigned.
void checkStruct(const char* name, size_t size, std::initializer_list<MemberLayout> members) {
    auto structs = test::reflectStructs(layout_probe_spv, sizeof layout_probe_spv / 4);
    INFO("struct " << name);
    REQUIRE(structs.count(name) == 1);
    const auto& reflected = structs.at(name);
    REQUIRE(reflected.memberOffsets.size() == members.size());
    uint32_t index = 0;
    for (const auto& member : members) {
        INFO("member " << member.name);
        CHECK(reflected.memberNames.at(index) == member.name);
        CHECK(reflected.memberOffsets.at(index) == member.offset);
        ++index;
    }
    CHECK(reflected.arrayStride == size);
}

}  // namespace

#define VPSIM_MEMBER(type, member)      \
    MemberLayout {                      \
#member, offsetof(type, member) \
    }

TEST_CASE("shared structs have the same layout in C++ and std430 GLSL", "[gpu][layout]") {
    using glsl::RngStreamParams;
    checkStruct(
        "RngStreamParams", sizeof(RngStreamParams),
        {VPSIM_MEMBER(RngStreamParams, seed), VPSIM_MEMBER(RngStreamParams, firstStream),
         VPSIM_MEMBER(RngStreamParams, streamCount), VPSIM_MEMBER(RngStreamParams, valuesPerStream),
         VPSIM_MEMBER(RngStreamParams, mode), VPSIM_MEMBER(RngStreamParams, pad0),
         VPSIM_MEMBER(RngStreamParams, pad1), VPSIM_MEMBER(RngStreamParams, pad2)});
    using glsl::ExposureBlurParams;
    checkStruct(
        "ExposureBlurParams", sizeof(ExposureBlurParams),
        {VPSIM_MEMBER(ExposureBlurParams, nx), VPSIM_MEMBER(ExposureBlurParams, ny),
         VPSIM_MEMBER(ExposureBlurParams, sourceWidth),
         VPSIM_MEMBER(ExposureBlurParams, targetWidth), VPSIM_MEMBER(ExposureBlurParams, scale),
         VPSIM_MEMBER(ExposureBlurParams, stripRows), VPSIM_MEMBER(ExposureBlurParams, pad1),
         VPSIM_MEMBER(ExposureBlurParams, pad2)});
    using glsl::ExposureStencilParams;
    checkStruct("ExposureStencilParams", sizeof(ExposureStencilParams),
                {VPSIM_MEMBER(ExposureStencilParams, nx), VPSIM_MEMBER(ExposureStencilParams, ny),
                 VPSIM_MEMBER(ExposureStencilParams, groupX),
                 VPSIM_MEMBER(ExposureStencilParams, paddedWidth),
                 VPSIM_MEMBER(ExposureStencilParams, padding),
                 VPSIM_MEMBER(ExposureStencilParams, columnPadding),
                 VPSIM_MEMBER(ExposureStencilParams, groupY),
                 VPSIM_MEMBER(ExposureStencilParams, sliceWidth),
                 VPSIM_MEMBER(ExposureStencilParams, storeMask)});
    using glsl::PhotonParams;
    checkStruct("PhotonParams", sizeof(PhotonParams),
                {VPSIM_MEMBER(PhotonParams, seed),
                 VPSIM_MEMBER(PhotonParams, photonStart),
                 VPSIM_MEMBER(PhotonParams, photonCount),
                 VPSIM_MEMBER(PhotonParams, invocationStride),
                 VPSIM_MEMBER(PhotonParams, beamShape),
                 VPSIM_MEMBER(PhotonParams, beamW0),
                 VPSIM_MEMBER(PhotonParams, mua),
                 VPSIM_MEMBER(PhotonParams, mus),
                 VPSIM_MEMBER(PhotonParams, g),
                 VPSIM_MEMBER(PhotonParams, phaseModel),
                 VPSIM_MEMBER(PhotonParams, phaseTableSize),
                 VPSIM_MEMBER(PhotonParams, nMedium),
                 VPSIM_MEMBER(PhotonParams, nAbove),
                 VPSIM_MEMBER(PhotonParams, nBelow),
                 VPSIM_MEMBER(PhotonParams, thickness),
                 VPSIM_MEMBER(PhotonParams, lateralRadius),
                 VPSIM_MEMBER(PhotonParams, launchWeight),
                 VPSIM_MEMBER(PhotonParams, enteringWeight),
                 VPSIM_MEMBER(PhotonParams, rBinWidth),
                 VPSIM_MEMBER(PhotonParams, zBinWidth),
                 VPSIM_MEMBER(PhotonParams, rBins),
                 VPSIM_MEMBER(PhotonParams, zBins),
                 VPSIM_MEMBER(PhotonParams, gridVoxel),
                 VPSIM_MEMBER(PhotonParams, gridNxy),
                 VPSIM_MEMBER(PhotonParams, gridNz),
                 VPSIM_MEMBER(PhotonParams, depth0),
                 VPSIM_MEMBER(PhotonParams, depth1),
                 VPSIM_MEMBER(PhotonParams, depth2),
                 VPSIM_MEMBER(PhotonParams, depth3),
                 VPSIM_MEMBER(PhotonParams, rouletteWeight),
                 VPSIM_MEMBER(PhotonParams, photonStartHi),
                 VPSIM_MEMBER(PhotonParams, estimator)});
}
