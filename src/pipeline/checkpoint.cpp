#include "vpsim/pipeline/checkpoint.h"

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/output_directory.h"

namespace vpsim::pipeline {

std::string checkpointDirectory(const std::string& outDir) {
    return outDir + "/checkpoint";
}

std::string checkpointFingerprint(const nlohmann::json& jobDocument, const std::string& outDir,
                                  const nlohmann::json& tiles) {
    const nlohmann::json what = {{"job", jobDocument},
                                 {"part", sha256OfFile(outDir + "/part.stl")},
                                 {"plan", sha256OfFile(outDir + "/plan.json")},
                                 {"tiles", tiles}};
    return sha256Hex(what.dump());
}

void saveCheckpoint(const std::string& outDir, const TileCheckpoint& checkpoint) {
    // Written beside the run's files but not through io.h's writers: the manifest must not list it.
    const std::string dir = checkpointDirectory(outDir), path = dir + "/state.json";
    const std::string temporary = path + ".tmp." + std::to_string(getpid());
    std::filesystem::create_directories(dir);
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out << nlohmann::json{{"fingerprint", checkpoint.fingerprint},
                              {"tiles_done", checkpoint.tilesDone},
                              {"consumers", checkpoint.consumers}}
                   .dump();
        out.flush();
        if (!out) throw InputError("cannot write the checkpoint (disk full?)", temporary);
    }
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) throw InputError("cannot write the checkpoint: " + error.message(), path);
}

std::optional<TileCheckpoint> loadCheckpoint(const std::string& outDir,
                                             const std::string& fingerprint) {
    const std::string path = checkpointDirectory(outDir) + "/state.json";
    if (!std::filesystem::exists(path)) return std::nullopt;
    const std::string restart = "; run without --resume to start over";
    TileCheckpoint checkpoint;
    try {
        const nlohmann::json state = nlohmann::json::parse(readFile(path));
        checkpoint.fingerprint = state.at("fingerprint").get<std::string>();
        checkpoint.tilesDone = state.at("tiles_done").get<int>();
        checkpoint.consumers = state.at("consumers");
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed checkpoint (") + e.what() + ")" + restart, path);
    }
    if (checkpoint.fingerprint != fingerprint)
        throw InputError("the checkpoint is of another job, part, plan or tiling" + restart, path);
    return checkpoint;
}

void removeCheckpoint(const std::string& outDir) {
    std::error_code error;
    std::filesystem::remove_all(checkpointDirectory(outDir), error);
    if (error)
        throw InputError("cannot remove the checkpoint: " + error.message(),
                         checkpointDirectory(outDir));
}

}  // namespace vpsim::pipeline
