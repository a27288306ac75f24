#include "vpsim/pipeline/cluster_run.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "vpsim/cluster/collectives.h"
#include "vpsim/cluster/communicator.h"
#include "vpsim/core/error.h"
#include "vpsim/pipeline/picture_recorders.h"
#include "vpsim/planners/laser_exposure_review.h"
#include "vpsim/transport/mc_split.h"

namespace vpsim::pipeline {
namespace {

/// How one Monte Carlo kernel's work was shared.
nlohmann::json kernelSplit(const char* kernel, const std::optional<kernel::BeamKernel>& table,
                           bool fromCache, int ranks) {
    if (!table) return nullptr;
    if (fromCache)
        return {{"kernel", kernel}, {"what", "nothing: rank 0 read the kernel from the cache"}};
    nlohmann::json split = transport::photonSplitJson(table->photons, ranks);
    split["kernel"] = kernel;
    return split;
}

}  // namespace

void runJobOnWorkerRank(const Job& job, const RunContext& context) {
    const BeamResult beam = beamStage(job, context);  // the ranks hold the same kernel
    const nlohmann::json work = nlohmann::json::parse(context.cluster->broadcastBytes(""));
    if (!work.at("distributed").get<bool>()) return;
    if (work.at("stl").get<bool>() &&
        !checkTileScratch(*context.cluster, work.at("tile_stl_bytes").get<double>()))
        return;  // rank 0 says why
    const geometry::Mesh part = partStage(job);
    const plan::ScanPlan plan = plan::scanPlanFromJson(work.at("plan"));
    const exposure::ExposureGrid grid = exposureGrid(job, part.bounds(), beam);
    const auto model = exposureModel(job, grid, beam, context);
    const auto tiles = exposureTiles(*model, work.at("tile_side").get<double>());
    exposeTilesOnRanks(
        job, part, *model, tiles, plan, beam, context, work.at("stl").get<bool>(),
        work.at("first_tile").get<int>(), [](const std::string&) {}, [](const std::string&) {},
        [](int) {});
}

nlohmann::json TileConsumers::save() const {
    return {{"validator", validator.saveState()},
            {"cured", cured.saveState()},
            {"features", features.saveState()},
            {"exposure_error", exposureError ? exposureError->saveState() : nlohmann::json()}};
}

void TileConsumers::restore(const nlohmann::json& state, const std::string& file) const {
    try {
        validator.restoreState(state.at("validator"));
        cured.restoreState(state.at("cured"));
        features.restoreState(state.at("features").get<std::vector<double>>());
        if (exposureError) exposureError->restoreState(state.at("exposure_error"));
    } catch (const nlohmann::json::exception& e) {  // a checkpoint of an older vpsim, or edited
        throw InputError(std::string("malformed checkpoint (") + e.what() +
                             "); run without --resume to start over",
                         file);
    }
}

void TileConsumers::merge(const nlohmann::json& later) const {
    validator.mergeState(later.at("validator"));
    cured.mergeState(later.at("cured"));
    features.mergeState(later.at("features").get<std::vector<double>>());
    if (exposureError) exposureError->mergeState(later.at("exposure_error"));
}

void sendTileWork(const RunContext& context, bool distributed, double tileSide,
                  const plan::ScanPlan& plan, bool stl, int firstTile, double tileStlBytes) {
    if (!context.cluster || context.cluster->ranks() <= 1) return;
    nlohmann::json work = {{"distributed", distributed},
                           {"tile_side", tileSide},
                           {"stl", stl},
                           {"tile_stl_bytes", tileStlBytes},
                           {"first_tile", firstTile}};
    if (distributed) work["plan"] = plan::toJson(plan);
    context.cluster->broadcastBytes(work.dump());
    if (distributed && stl) checkTileScratch(*context.cluster, tileStlBytes);
}

bool checkTileScratch(cluster::Communicator& comm, double bytes) {
    // Free bytes + 1 of each rank short of room (0: room enough, or nothing to judge by).
    std::vector<uint64_t> shortOf(size_t(comm.ranks()), 0);
    std::error_code error;
    const std::filesystem::path directory = std::filesystem::temp_directory_path(error);
    const std::filesystem::space_info space = std::filesystem::space(directory, error);
    if (!error && double(space.available) < bytes)
        shortOf[size_t(comm.rank())] = uint64_t(space.available) + 1;
    comm.sumIntegers(shortOf);
    std::string ranks;
    for (size_t r = 0; r < shortOf.size(); ++r)
        if (shortOf[r] > 0)
            ranks += std::string(ranks.empty() ? "" : ", ") + "rank " + std::to_string(r) + " (" +
                     formatBytes(double(shortOf[r] - 1)) + " free)";
    if (ranks.empty()) return true;
    if (!comm.isRoot()) return false;
    throw ResourceError("each MPI rank keeps a tile's share of cured.stl (about " +
                        formatBytes(bytes) +
                        ") in its temporary directory until rank 0 takes it, and there is too "
                        "little room on " +
                        ranks +
                        ": point TMPDIR at a larger disk, use smaller tiles (simulation.tile) "
                        "or leave cured.stl out of simulation.outputs");
}

void exposeTilesOnRanks(const Job& job, const geometry::Mesh& part,
                        const exposure::ExposureModel& model,
                        const std::vector<exposure::Tile>& tiles, const plan::ScanPlan& plan,
                        const BeamResult& beam, const RunContext& context, bool stl, int firstTile,
                        const std::function<void(const std::string&)>& merge,
                        const std::function<void(const std::string&)>& appendStl,
                        const std::function<void(int)>& roundDone) {
    const exposure::ExposureGrid& grid = model.grid();
    const double voxelHeight = job.machine.layerThickness / job.simulation.slicesPerLayer;
    // The laser review's regions and the pictures' layers (rank 0's are the same).
    const geometry::LayerStack layers =
        job.machine.process == plan::Process::Laser || keepsCuredView(job) ? sliceStage(job, part)
                                                                           : geometry::LayerStack{};
    const bool figures = job.simulation.writes("figures");
    auto temporary = [&](size_t i, const char* suffix) {
        return (std::filesystem::temp_directory_path() /
                ("vpsim-tile-" + std::to_string(getpid()) + "-" + std::to_string(i) + suffix))
            .string();
    };
    auto work = [&](size_t i, uint64_t& stlBytes) {
        const exposure::Tile& tile = tiles[i];
        validate::SliceValidator validator(part, grid, *job.cure, voxelHeight);
        validate::FeatureProbes features(job.features, grid, *job.cure, voxelHeight);
        const auto exposureError =
            planners::laserExposureErrorSink(layers, job.machine, *job.cure, model, figures);
        // The tile's triangles go through a file of this rank's (the STL writer's stream).
        const std::string stlPath = stl ? temporary(i, ".stl") : "";
        auto cured = curedSurfaceSink(job, grid, voxelHeight, part, stlPath, true);
        keepCuredView(job, part, voxelHeight, *cured);
        PictureRecorders recorders(job, part, layers, grid);
        std::vector<exposure::SliceSink> sinks;
        recorders.addSinks(sinks);
        auto tileModel = exposureModel(job, grid.window(tile.window), beam, context);
        tileModel->run(plan, tile.core, [&](const exposure::ExposureSlice& slice) {
            validator.add(slice);
            cured->add(slice);
            features.add(slice);
            if (exposureError) exposureError->add(slice);
            for (const auto& sink : sinks) sink(slice);
        });
        nlohmann::json state =
            TileConsumers{validator, *cured, features, exposureError.get()}.save();
        state["tile"] = i;
        // The tile's share of the pictures, as binary records (PictureConsumers::savePartial).
        const PictureConsumers pictures =
            recorders.consumers(job, cured.get(), exposureError.get());
        std::string pictureBytes;
        if (pictures.any()) {
            BinaryStateWriter out(InMemory{"tile " + std::to_string(i) + "'s pictures"});
            pictures.savePartial(out, tile.core);
            out.commit();
            pictureBytes = out.takeBytes();
        }
        state["picture_bytes"] = pictureBytes.size();
        if (stl) {          // the triangles stay in the file until rank 0 takes them (streamToRoot)
            cured.reset();  // closes the file
            stlBytes = std::filesystem::file_size(stlPath) - 84;
            state["stl_bytes"] = stlBytes;
        }
        return state.dump() + "\n" + pictureBytes;  // the JSON has no raw line break
    };
    // A round of one tile per rank at a time (tile first + k on rank k % ranks, as runItems
    // deals), so that rank 0 holds one round's states and pictures, not the whole job's. Each
    // tile's triangles then pass from its rank's file to rank 0's STL in pieces, in the tiles'
    // order: a tile's STL can be many GB, more than a message carries or a rank holds.
    cluster::Communicator& comm = *context.cluster;
    const size_t ranks = size_t(comm.ranks());
    for (size_t first = size_t(firstTile); first < tiles.size(); first += ranks) {
        const size_t round = std::min(ranks, tiles.size() - first);
        std::vector<uint64_t> stlBytes(round, 0);  // each filled by the tile's rank
        const std::vector<std::string> partials =
            cluster::runItems(comm, round, [&](size_t i) { return work(first + i, stlBytes[i]); });
        if (stl) comm.sumIntegers(stlBytes);  // every rank learns every size
        for (size_t i = 0; i < round; ++i) {
            if (comm.isRoot()) merge(partials[i]);
            if (!stl) continue;
            const int owner = cluster::ownerOfItem(i, comm.ranks());
            const std::string path = temporary(first + i, ".stl");
            std::ifstream in;
            if (comm.rank() == owner) in.open(path, std::ios::binary);
            cluster::streamToRoot(
                comm, owner, stlBytes[i],
                [&](uint64_t offset, size_t count) {
                    std::string piece(count, '\0');
                    in.seekg(std::streamoff(84 + offset));
                    in.read(piece.data(), std::streamsize(count));
                    piece.resize(size_t(in.gcount()));
                    return piece;
                },
                appendStl);
            if (comm.rank() == owner) {
                in.close();
                std::filesystem::remove(path);
            }
        }
        if (comm.isRoot()) roundDone(int(first + round));
    }
}

void mergeTilePartial(const std::string& partial, const std::vector<exposure::Tile>& tiles,
                      const TileConsumers& consumers, const PictureConsumers& pictures) {
    const size_t end = partial.find('\n');
    if (end == std::string::npos) throw InputError("a rank's tile result is malformed");
    const nlohmann::json state = nlohmann::json::parse(partial.substr(0, end));
    const auto tile = state.at("tile").get<size_t>();
    const auto pictureBytes = state.at("picture_bytes").get<size_t>();
    if (tile >= tiles.size() || pictureBytes != partial.size() - end - 1 ||
        (pictureBytes > 0) != pictures.any())
        throw InputError("a rank's tile result is malformed");
    // The STL that follows (streamToRoot) holds the tile's triangles, 50 bytes each.
    if (state.contains("stl_bytes") && state.at("stl_bytes").get<uint64_t>() !=
                                           50 * state.at("cured").at("triangles").get<uint64_t>())
        throw InputError("a rank's tile STL does not hold its triangles");
    consumers.merge(state);
    if (pictureBytes == 0) return;
    pictures.mergePartial(
        BinaryStateReader(InMemory{"tile " + std::to_string(tile) + "'s pictures from its rank"},
                          partial.substr(end + 1)),
        tiles[tile].core);
}

nlohmann::json tileSplitJson(size_t tiles, int ranks, int firstTile) {
    const size_t first = size_t(firstTile);
    nlohmann::json perRank = nlohmann::json::array();
    for (int r = 0; r < ranks; ++r) {
        std::vector<size_t> owned = cluster::itemsOfRank(tiles - first, r, ranks);
        for (size_t& tile : owned) tile += first;
        perRank.push_back(owned);
    }
    nlohmann::json split = {{"count", tiles},
                            {"deal", "round-robin (tile i on rank i % ranks)"},
                            {"tiles_of_rank", perRank},
                            {"merge", "rank 0, in the tiles' order: the single process's figures"}};
    if (firstTile > 0) {
        split["deal"] = "round-robin from the resumed tile (tile i on rank (i - " +
                        std::to_string(firstTile) + ") % ranks)";
        split["resumed_after_tile"] = firstTile;
    }
    return split;
}

nlohmann::json clusterSummary(const BeamResult& beam, const RunContext& context) {
    if (!context.cluster || context.cluster->ranks() <= 1) return nullptr;
    const int ranks = context.cluster->ranks();
    nlohmann::json split = nlohmann::json::array();
    for (const nlohmann::json& s :
         {kernelSplit("kernel", beam.monteCarlo, beam.fromCache, ranks),
          kernelSplit("kernel.plan", beam.planMonteCarlo, beam.planFromCache, ranks)})
        if (!s.is_null()) split.push_back(s);
    return {{"ranks", ranks},
            {"split", split},
            {"rank_0",
             "the stages after the beam kernel (slice, plan, exposure, cure, validation, "
             "report) and every file written, but the tiles of \"tiles\" when there is one"}};
}

}  // namespace vpsim::pipeline
