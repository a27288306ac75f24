// A photon Monte Carlo run over MPI ranks: contiguous photon ranges, integer tallies added.
#include "vpsim/transport/mc_split.h"

#include <chrono>

#include <nlohmann/json.hpp>

#include "photon_params.h"
#include "vpsim/transport/beam_convolution.h"

namespace vpsim::transport {
namespace {

constexpr size_t BATCH_WORDS = 14;    // BatchTally's fields
constexpr size_t CONTROL_WORDS = 16;  // ControlTally's fields

size_t rzWords(const McSetup& s) {
    return size_t(s.bins.rBins) * s.bins.zBins * (s.binsPerBatch ? MC_BATCHES : 1);
}

size_t gridWords(const McSetup& s) {
    return size_t(s.grid.nxy) * s.grid.nxy * s.grid.nz;
}

/// The integer tallies of a share as one vector (zeros for a rank without photons), in the
/// order unpack reads them.
std::vector<uint64_t> pack(const McResult* r, const McSetup& traced, bool controlled) {
    std::vector<uint64_t> w;
    w.reserve(MC_BATCHES * BATCH_WORDS + rzWords(traced) + gridWords(traced) +
              (controlled ? MC_CONTROL_BATCHES * CONTROL_WORDS : 0));
    for (size_t b = 0; b < size_t(MC_BATCHES); ++b) {
        const BatchTally t = r ? r->batches[b] : BatchTally{};
        w.insert(w.end(), {t.photons, t.specular, t.diffuse, t.transmitted, t.absorbed, t.escaped,
                           t.scatterings, t.interactions, t.rouletteGain, t.rouletteLoss});
        w.insert(w.end(), t.absorbedWithin.begin(), t.absorbedWithin.end());
    }
    for (size_t j = 0; controlled && j < size_t(MC_CONTROL_BATCHES); ++j) {
        const ControlTally c =
            r && j < r->controlBatches.size() ? r->controlBatches[j] : ControlTally{};
        w.insert(w.end(), {c.diffuse, c.transmitted});
        w.insert(w.end(), c.absorbedWithin.begin(), c.absorbedWithin.end());
        for (int64_t v : c.controls) w.push_back(uint64_t(v));  // two's complement adds exactly
    }
    const auto append = [&](const std::vector<uint64_t>& v, size_t n) {
        if (r && v.size() == n)
            w.insert(w.end(), v.begin(), v.end());
        else
            w.resize(w.size() + n, 0);
    };
    append(r ? r->absorbedRZ : std::vector<uint64_t>{}, rzWords(traced));
    append(r ? r->absorbedGrid : std::vector<uint64_t>{}, gridWords(traced));
    return w;
}

/// The merged run of `traced` from the added words.
McResult unpack(const std::vector<uint64_t>& w, const McSetup& traced) {
    McResult r;
    r.setup = traced;
    const glsl::PhotonParams params = makePhotonParams(traced);
    r.launchWeight = params.launchWeight;
    size_t at = 0;
    for (BatchTally& t : r.batches) {
        for (uint64_t* field :
             {&t.photons, &t.specular, &t.diffuse, &t.transmitted, &t.absorbed, &t.escaped,
              &t.scatterings, &t.interactions, &t.rouletteGain, &t.rouletteLoss})
            *field = w[at++];
        for (uint64_t& v : t.absorbedWithin) v = w[at++];
    }
    if (r.controlled()) {
        r.controlBatches.resize(MC_CONTROL_BATCHES);
        for (ControlTally& c : r.controlBatches) {
            c.diffuse = w[at++];
            c.transmitted = w[at++];
            for (uint64_t& v : c.absorbedWithin) v = w[at++];
            for (int64_t& v : c.controls) v = int64_t(w[at++]);
        }
    }
    std::vector<uint64_t> bins(w.begin() + long(at), w.begin() + long(at + rzWords(traced)));
    at += bins.size();
    r.absorbedGrid.assign(w.begin() + long(at), w.end());
    setBins(r, std::move(bins), params);
    return r;
}

}  // namespace

PhotonShare photonShare(uint64_t photons, int rank, int ranks) {
    const uint64_t rounds = (photons + MC_CONTROL_BATCHES - 1) / MC_CONTROL_BATCHES;
    const auto start = [&](int r) {
        return std::min(photons, rounds * uint64_t(r) / uint64_t(ranks) * MC_CONTROL_BATCHES);
    };
    PhotonShare share;
    share.first = start(rank);
    share.count = (rank + 1 == ranks ? photons : start(rank + 1)) - share.first;
    return share;
}

nlohmann::json photonSplitJson(uint64_t photons, int ranks) {
    nlohmann::json ranges = nlohmann::json::array();
    for (int r = 0; r < ranks; ++r) {
        const PhotonShare s = photonShare(photons, r, ranks);
        ranges.push_back({s.first, s.first + s.count});
    }
    return {{"what", "photon batches of the beam kernel's Monte Carlo"},
            {"photons", photons},
            {"photon_ranges", ranges},
            {"merge", "integer tallies added (exact)"}};
}

McResult runPhotonMcSplit(const McSetup& setup, const std::shared_ptr<gpu::Context>& context,
                          cluster::Communicator& comm) {
    if (comm.ranks() <= 1) return runPhotonMc(setup, context);
    validateSetup(setup);
    const auto start = std::chrono::steady_clock::now();
    const bool convolves = convolvesBeam(setup);
    const McSetup traced = convolves ? pencilSetup(setup) : setup;
    const PhotonShare share = photonShare(traced.photons, comm.rank(), comm.ranks());
    McSetup mine = traced;
    mine.firstPhoton = traced.firstPhoton + share.first;
    mine.photons = share.count;
    mine.unscaledBins = true;
    McResult part;
    if (share.count > 0) part = runPhotonMc(mine, context);
    McResult probe;  // for controlled(), which depends on the setup only
    probe.setup = traced;
    std::vector<uint64_t> words =
        pack(share.count > 0 ? &part : nullptr, traced, probe.controlled());
    comm.sumIntegers(words);
    McResult merged = unpack(words, traced);
    if (convolves) merged = convolveBeam(merged, setup);
    merged.backend = (share.count > 0 ? part.backend : std::string("cpu")) + " x " +
                     std::to_string(comm.ranks()) + " ranks";
    merged.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return merged;
}

}  // namespace vpsim::transport
