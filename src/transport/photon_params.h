#pragma once
// Internal: the shared photon Monte Carlo types (shaders/include/photon_types.glsl) seen from
// C++, and the host-side preparation common to the CPU and GPU paths.

#include <vector>

#include "vpsim/core/glsl_shim.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim::glsl {
#include "photon_types.glsl"
}

namespace vpsim::transport {

// The push-constant block is 32 four-byte scalars: the 128 bytes every Vulkan device accepts.
static_assert(sizeof(glsl::PhotonParams) == 128, "PhotonParams must stay 32 x 4 bytes");
static_assert(MC_BATCHES == int(glsl::PHOTON_BATCHES), "one batch count on both sides");
static_assert(MC_CONTROL_TERMS == int(glsl::PHOTON_CONTROL_TERMS) &&
                  MC_CONTROL_BATCHES == int(glsl::PHOTON_CONTROL_BATCHES),
              "one control layout on both sides");
static_assert(glsl::PHOTON_CONTROL_OFFSET == glsl::PHOTON_BATCHES * glsl::PHOTON_TALLY_STRIDE &&
                  glsl::PHOTON_CONTROL_STRIDE == 6 + glsl::PHOTON_CONTROL_TERMS &&
                  glsl::PHOTON_BIN_OFFSET ==
                      glsl::PHOTON_CONTROL_OFFSET +
                          glsl::PHOTON_CONTROL_BATCHES * glsl::PHOTON_CONTROL_STRIDE,
              "tally layout");

/// Weight quanta of one launched photon (2^24: specular split resolved to 6e-8).
constexpr uint32_t LAUNCH_WEIGHT = 1u << 24;
/// Most inverse-CDF entries (the GPU keeps the table in 32 KiB of shared memory).
constexpr size_t MAX_PHASE_TABLE = 7936;
/// Most cylindrical bins and Cartesian voxels (tally memory stays bounded whatever the photons).
constexpr uint64_t MAX_RZ_BINS = 1u << 22;
constexpr uint64_t MAX_GRID_VOXELS = 1u << 24;

/// Push-constant block for photons [0, photons) of a validated setup (photon range and stride
/// are filled in by the caller).
glsl::PhotonParams makePhotonParams(const McSetup& setup);
/// The inverse CDF as the shaders read it (resampled to MAX_PHASE_TABLE entries when longer);
/// empty for Henyey-Greenstein.
std::vector<float> makePhaseTable(const McSetup& setup);
/// Photons of batch b (index % batches == b) among photon indices [first, first + photons).
uint64_t photonsInBatch(uint64_t first, uint64_t photons, int batch, int batches = MC_BATCHES);
/// Stores the (r,z) tally words of a run of `params`: one copy, or MC_BATCHES copies when
/// result.setup.binsPerBatch (then absorbedRZ is their sum). The collision estimator's words are
/// interaction counts, turned into quanta here (photon_types.glsl); kept as they are when
/// result.setup.unscaledBins (a rank's share, scaled after the ranks are added).
void setBins(McResult& result, std::vector<uint64_t> words, const glsl::PhotonParams& params);
/// Photon-weighted mean of per-batch fractions, with the standard error of their spread.
Fraction fractionOfBatches(const McResult& result, const std::array<double, MC_BATCHES>& values);

}  // namespace vpsim::transport
