#include "vpsim/pipeline/checkpoint.h"

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "vpsim/core/binary_state.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/output_directory.h"

namespace vpsim::pipeline {
namespace {

const std::string RESTART = "; run without --resume to start over";

std::string statePath(const std::string& outDir) {
    return checkpointDirectory(outDir) + "/state.json";
}

}  // namespace

std::string checkpointDirectory(const std::string& outDir) {
    return outDir + "/checkpoint";
}

std::string jobInputsFingerprint(const Job& job) {
    nlohmann::json files = nlohmann::json::object();  // contents, so that an edit is seen
    for (const std::string& file : jobInputFiles(job)) files[file] = sha256OfFile(file);
    return sha256Hex(nlohmann::json{{"job", job.document}, {"files", files}}.dump());
}

std::string checkpointFingerprint(const std::string& inputs, const std::string& outDir,
                                  const nlohmann::json& tiles) {
    const nlohmann::json what = {{"inputs", inputs},
                                 {"part", sha256OfFile(outDir + "/part.stl")},
                                 {"plan", sha256OfFile(outDir + "/plan.json")},
                                 {"tiles", tiles}};
    return sha256Hex(what.dump());
}

void saveCheckpoint(const std::string& outDir, const TileCheckpoint& checkpoint) {
    // Written beside the run's files but not through io.h's writers: the manifest must not list it.
    const std::string dir = checkpointDirectory(outDir), path = statePath(outDir);
    const std::string temporary = path + ".tmp." + std::to_string(getpid());
    std::filesystem::create_directories(dir);
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out << nlohmann::json{{"inputs", checkpoint.inputs},
                              {"fingerprint", checkpoint.fingerprint},
                              {"plan_sha256", checkpoint.planSha256},
                              {"plan_report", checkpoint.planReport},
                              {"tiles_done", checkpoint.tilesDone},
                              {"consumers", checkpoint.consumers}}
                   .dump();
        out.flush();
        if (!out) throw InputError("cannot write the checkpoint (disk full?)", temporary);
    }
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) throw InputError("cannot write the checkpoint: " + error.message(), path);
    // The earlier tiles' pictures: state.json no longer names them.
    const auto pictures = checkpoint.consumers.find("pictures");
    const std::string kept = pictures != checkpoint.consumers.end()
                                 ? pictures->at("file").get<std::string>()
                                 : std::string();
    for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("pictures-", 0) == 0 && name != kept)
            std::filesystem::remove(entry.path(), error);
    }
}

nlohmann::json PictureConsumers::save(const std::string& outDir, int tilesDone) const {
    const std::string name = "pictures-" + std::to_string(tilesDone) + ".bin";
    const std::string path = checkpointDirectory(outDir) + "/" + name;
    BinaryStateWriter out(path);
    if (cured) cured->savePicture(out);
    if (sections) sections->saveState(out);
    if (layerSections) layerSections->saveState(out);
    if (exposureError) exposureError->savePicture(out);
    out.commit();
    return {{"file", name}, {"bytes", out.bytes()}, {"sha256", out.sha256()}};
}

void PictureConsumers::restore(const std::string& outDir, const nlohmann::json& entry) const {
    std::string file, sha256;
    uint64_t bytes = 0;
    try {
        file = entry.at("file").get<std::string>();
        bytes = entry.at("bytes").get<uint64_t>();
        sha256 = entry.at("sha256").get<std::string>();
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed checkpoint (pictures: ") + e.what() + ")" + RESTART,
                         statePath(outDir));
    }
    if (file.rfind("pictures-", 0) != 0 || file.find('/') != std::string::npos)
        throw InputError("malformed checkpoint (pictures: not a pictures file)" + RESTART,
                         statePath(outDir));
    const std::string path = checkpointDirectory(outDir) + "/" + file;
    std::error_code error;
    if (std::filesystem::file_size(path, error) != bytes || error || sha256OfFile(path) != sha256)
        throw InputError("missing or changed since the checkpoint was written" + RESTART, path);
    const BinaryStateReader in(path);
    if (cured) cured->restorePicture(in);
    if (sections) sections->restoreState(in);
    if (layerSections) layerSections->restoreState(in);
    if (exposureError) exposureError->restorePicture(in);
}

void PictureConsumers::savePartial(BinaryStateWriter& out, const exposure::CellWindow& core) const {
    if (cured) cured->savePicture(out);
    if (sections) sections->savePartial(out, core);
    if (layerSections) layerSections->savePartial(out, core);
    if (exposureError) exposureError->savePartialPicture(out, core);
}

void PictureConsumers::mergePartial(const BinaryStateReader& in,
                                    const exposure::CellWindow& core) const {
    if (cured) cured->mergePicture(in);
    if (sections) sections->mergePartial(in, core);
    if (layerSections) layerSections->mergePartial(in, core);
    if (exposureError) exposureError->mergePicture(in, core);
}

std::optional<TileCheckpoint> loadCheckpoint(const std::string& outDir, const std::string& inputs) {
    const std::string path = statePath(outDir);
    if (!std::filesystem::exists(path)) return std::nullopt;
    TileCheckpoint checkpoint;
    try {
        const nlohmann::json state = nlohmann::json::parse(readFile(path));
        checkpoint.inputs = state.at("inputs").get<std::string>();
        checkpoint.fingerprint = state.at("fingerprint").get<std::string>();
        checkpoint.planSha256 = state.at("plan_sha256").get<std::string>();
        checkpoint.planReport = state.at("plan_report");
        checkpoint.tilesDone = state.at("tiles_done").get<int>();
        checkpoint.consumers = state.at("consumers");
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed checkpoint (") + e.what() + ")" + RESTART, path);
    }
    if (checkpoint.inputs != inputs)
        throw InputError(
            "the checkpoint is of another job (the job or the contents of a file it reads, "
            "its material or part STL, differ)" +
                RESTART,
            path);
    return checkpoint;
}

void checkFingerprint(const TileCheckpoint& checkpoint, const std::string& outDir,
                      const std::string& fingerprint) {
    if (checkpoint.fingerprint != fingerprint)
        throw InputError("the checkpoint is of another job, part, plan or tiling" + RESTART,
                         statePath(outDir));
}

plan::ScanPlan checkpointPlan(const TileCheckpoint& checkpoint, const std::string& outDir) {
    const std::string path = outDir + "/plan.json";
    if (!std::filesystem::exists(path) || sha256OfFile(path) != checkpoint.planSha256)
        throw InputError(
            "missing or changed since the checkpoint was written (its SHA-256 is "
            "not the checkpoint's)" +
                RESTART,
            path);
    return plan::loadScanPlan(path);
}

void removeCheckpoint(const std::string& outDir) {
    std::error_code error;
    std::filesystem::remove_all(checkpointDirectory(outDir), error);
    if (error)
        throw InputError("cannot remove the checkpoint: " + error.message(),
                         checkpointDirectory(outDir));
}

}  // namespace vpsim::pipeline
