#pragma once
/// @file
/// Per-tile checkpoints of a long tiled run (issue 22), so that `vpsim run JOB --out DIR --resume`
/// continues after an interruption (a Slurm pre-emption) instead of starting over. After each
/// tile, DIR/checkpoint/state.json holds the tiles done and the slice consumers' states (what
/// the next tiles build on), with a fingerprint of the job, its part, its plan and its tiles so
/// that a different job is refused; the cured STL grows in place beside it (cured.stl.partial).
/// The checkpoint is no output: it is not in the manifest, and a run removes it before writing
/// the manifest.

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace vpsim::pipeline {

struct TileCheckpoint {
    std::string fingerprint;  ///< of the job, part, plan and tiles (checkpointFingerprint)
    int tilesDone = 0;        ///< tiles 0 .. tilesDone - 1 are in `consumers`
    nlohmann::json consumers = nlohmann::json::object();  ///< each consumer's saveState()
};

/// DIR/checkpoint.
std::string checkpointDirectory(const std::string& outDir);
/// A SHA-256 of the job document, the part and plan files written in `outDir`, and the tiles.
std::string checkpointFingerprint(const nlohmann::json& jobDocument, const std::string& outDir,
                                  const nlohmann::json& tiles);
/// Writes DIR/checkpoint/state.json atomically (not recorded in the manifest).
void saveCheckpoint(const std::string& outDir, const TileCheckpoint& checkpoint);
/// The checkpoint in `outDir`, or none when there is none.
/// @throw InputError when it is malformed or another job's (its fingerprint differs): the message
///        says to run without --resume to start over
std::optional<TileCheckpoint> loadCheckpoint(const std::string& outDir,
                                             const std::string& fingerprint);
/// Removes DIR/checkpoint (a finished run, or a run that starts over).
void removeCheckpoint(const std::string& outDir);

}  // namespace vpsim::pipeline
