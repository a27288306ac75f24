#pragma once
/// @file
/// Per-tile checkpoints of a long tiled run (issue 22), so that `vpsim run JOB --out DIR --resume`
/// continues after an interruption (a Slurm pre-emption) instead of starting over, in one process
/// or over MPI ranks (on any number of them). After each tile (over MPI: each merged round of
/// tiles), DIR/checkpoint/state.json holds the tiles done, the slice consumers' states (what the
/// next tiles build on) and the report's planner figures, with fingerprints of the job and the
/// contents of every file it reads (jobInputFiles), and of its part, its plan (DIR/plan.json,
/// which a resumed run exposes again instead of planning) and its tiles, so that a different job
/// is refused; the cured STL grows in place beside it (cured.stl.partial). A run with figures or
/// the 3D view also keeps their whole-part state (the sections, the picture of the cured surface,
/// the exposure-error map) in a binary file, DIR/checkpoint/pictures-N.bin after tile N, named in
/// state.json with its size and SHA-256 (PictureConsumers); over MPI ranks each tile's share of
/// them is merged on rank 0 (PictureConsumers::mergePartial). The checkpoint is no output: it is
/// not in the manifest, and a run removes it before writing the manifest.

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/optimise/laser/exposure_error_sink.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/plan/scan_plan.h"
#include "vpsim/report/figures.h"
#include "vpsim/report/layer_sections.h"
#include "vpsim/validate/streaming_surface.h"

namespace vpsim::pipeline {

struct TileCheckpoint {
    std::string inputs;       ///< of the job and its input files (jobInputsFingerprint)
    std::string fingerprint;  ///< of the inputs, part, plan and tiles (checkpointFingerprint)
    std::string planSha256;   ///< of DIR/plan.json, the plan being exposed
    /// report.json's "plan" "planner" as the run made it before the exposure
    nlohmann::json planReport = nlohmann::json::object();
    int tilesDone = 0;  ///< tiles 0 .. tilesDone - 1 are in `consumers`
    /// TileConsumers::save(), and "pictures": PictureConsumers::save()'s entry when there are
    nlohmann::json consumers = nlohmann::json::object();
};

/// The consumers whose state is the whole part's pictures, each when the run has it: the figures'
/// sections, the 3D view's layer sections, the cured surface's picture (keepView) and the
/// exposure-error figure's top map.
struct PictureConsumers {
    validate::StreamingCuredSurface* cured = nullptr;
    report::SectionRecorder* sections = nullptr;
    report::LayerSectionRecorder* layerSections = nullptr;
    optimise::ExposureErrorSink* exposureError = nullptr;

    bool any() const { return cured || sections || layerSections || exposureError; }
    /// Between two tiles, after TileConsumers::save(): writes DIR/checkpoint/pictures-N.bin (N =
    /// `tilesDone`) and returns state.json's entry for it (file, bytes, SHA-256).
    nlohmann::json save(const std::string& outDir, int tilesDone) const;
    /// Before the first slice, after TileConsumers::restore: reads the file `entry` names.
    /// @throw InputError naming the file when it is missing, changed or malformed
    void restore(const std::string& outDir, const nlohmann::json& entry) const;
    /// An MPI rank's tile (pipeline/cluster_run.h), after the consumers' save: the tile's share
    /// of each picture (its `core` cells, its part of the cured surface's picture) as records.
    void savePartial(BinaryStateWriter& out, const exposure::CellWindow& core) const;
    /// Rank 0, in the tiles' order: adds a tile's share, as one process would have made it.
    /// @throw InputError naming the state file when it is malformed
    void mergePartial(const BinaryStateReader& in, const exposure::CellWindow& core) const;
};

/// DIR/checkpoint.
std::string checkpointDirectory(const std::string& outDir);
/// A SHA-256 of the job document and the contents of the files it reads (jobInputFiles).
/// @throw InputError when one cannot be read
std::string jobInputsFingerprint(const Job& job);
/// A SHA-256 of the inputs' fingerprint, the part and plan files written in `outDir`, and the
/// tiles.
std::string checkpointFingerprint(const std::string& inputs, const std::string& outDir,
                                  const nlohmann::json& tiles);
/// Writes DIR/checkpoint/state.json atomically (not recorded in the manifest), then removes the
/// picture files it does not name.
void saveCheckpoint(const std::string& outDir, const TileCheckpoint& checkpoint);
/// The checkpoint in `outDir`, or none when there is none.
/// @throw InputError naming state.json when it is malformed or another job's (`inputs`, the
///        job's jobInputsFingerprint, differs: the job or a file it reads changed); the message
///        says to run without --resume to start over
std::optional<TileCheckpoint> loadCheckpoint(const std::string& outDir, const std::string& inputs);
/// @throw InputError as loadCheckpoint's when `fingerprint` (this run's checkpointFingerprint)
///        is not the checkpoint's: another part, plan or tiling
void checkFingerprint(const TileCheckpoint& checkpoint, const std::string& outDir,
                      const std::string& fingerprint);
/// The plan the checkpointed run was exposing: DIR/plan.json, read when its SHA-256 is the
/// checkpoint's. @throw InputError naming plan.json when it changed (or as loadScanPlan)
plan::ScanPlan checkpointPlan(const TileCheckpoint& checkpoint, const std::string& outDir);
/// Removes DIR/checkpoint (a finished run, or a run that starts over).
void removeCheckpoint(const std::string& outDir);

}  // namespace vpsim::pipeline
