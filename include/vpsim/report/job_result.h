#pragma once
/// @file
/// JobResult: the typed outcome of a run, from which report.json, index.html, the CLI summary,
/// the benchmarks and tests read their figures (nothing reads results back from JSON text).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/validate/feature_probe.h"
#include "vpsim/validate/slice_validator.h"
#include "vpsim/validate/surface_deviation.h"

namespace vpsim::report {

struct PartSummary {
    double volume = 0;    ///< mm^3
    double size[3] = {};  ///< bounding box, mm
    size_t triangles = 0;
};

/// The Monte Carlo kernel behind a laser run (absent for a given kernel or DLP).
struct KernelSummary {
    kernel::FittedBeam beam;  ///< We3D, De3D, zmax, efficiency of the fit
    double fitResidual = 0;
    /// Absorbed power the Eq. 12 fit carries over the table's (the fit the engine uses).
    double fitEnergyFraction = 0;
    std::string estimator;  ///< the Monte Carlo estimator of the bins
    uint64_t photons = 0;
    bool fromCache = false;
    bool tabulatedExposure = false;  ///< the exposure used the table, not the fit
};

struct PlanSummary {
    std::string strategy;
    size_t layers = 0;
    double energy = 0;  ///< mJ
    /// The planner's own figures, merged into report.json's top level (e.g. {"aces": {...}}).
    nlohmann::json planner = nlohmann::json::object();
};

struct ExposureSummary {
    std::string model;     ///< "fitted" | "tabulated"
    std::string backend;   ///< device name, or "cpu"
    int grid[3] = {};      ///< nx, ny, slices
    double voxel[3] = {};  ///< mm
    double engineSeconds = 0, sinkSeconds = 0;
    double maxDose = 0;  ///< mJ/mm^2
    uint64_t storedVoxels = 0;
    kernel::FittedBeam beam;        ///< the beam the engine used
    double keptEnergyFraction = 1;  ///< of the kernel's energy, after the engine's truncation
};

struct ValidationReport {
    validate::SliceValidationSummary slices;  ///< IoU, over-cure, XY contour errors
    validate::SurfaceDeviation deviation;     ///< signed surface deviation of the cured mesh
    /// Running statistics of every cured-surface vertex's deviation (the percentiles, the
    /// report's histogram and scale).
    validate::DeviationStatistics deviationStatistics;
    validate::FeatureMeasurements features;
};

/// A table of a report section: cells as text (already formatted).
struct ReportTable {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
};

/// A picture in the output directory with its caption.
struct ReportFigure {
    std::string file;  ///< relative to the output directory
    std::string caption;
};

/// A part of index.html that a component adds (a planner's review): a title, tables and
/// figures, rendered the same way for every component.
struct ReportSection {
    std::string title;
    std::vector<ReportTable> tables;
    std::vector<ReportFigure> figures;
};

/// The 3D view written beside index.html (viewer3d.h): what it shows and how much was cut.
struct ViewerSummary {
    size_t curedTriangles = 0, curedShown = 0;  ///< of the cured mesh, and drawn
    size_t modelTriangles = 0, modelShown = 0;
    double clusterCell = 0;     ///< mm, vertex-clustering cell of the decimation; 0: none
    uint64_t dataBytes = 0;     ///< mesh3d.js
    double limitUm = 0;         ///< the deviation colour scale's ends, ±µm
    double layerThickness = 0;  ///< mm, the clipping slider's step
    std::string missing;        ///< why no view was written (three.js not installed), else empty
};

/// The 3D view's per-layer sections and kernel map (layer_sections.h): what sections.js keeps.
struct SectionViewSummary {
    int layers = 0, layersKept = 0;  ///< of the run, and kept (every n-th and the top one)
    int width = 0, height = 0;       ///< pixels of each kept section
    double pixelMm = 0;              ///< mm per pixel
    double scaleMax = 0;             ///< mJ/cm^2 at uint8 255, linear from 0
    double aboveScale = 0;           ///< fraction of the kept pixels above scaleMax
    bool kernel = false;             ///< the kernel I(r, z) with its fit is in sections.js
    uint64_t dataBytes = 0;          ///< sections.js
};

/// A file of the output directory as written by the run (size in bytes).
struct WrittenFile {
    std::string name;
    uint64_t bytes = 0;
};

struct JobResult {
    std::string jobFile, name, backend;
    /// The inputs as given: {"job": the job file's JSON, "material": the material file's JSON}
    /// (the report's first tables; values keep the units they were written with).
    nlohmann::json inputs = nlohmann::json::object();
    nlohmann::json cure;  ///< the cure law's parameters (CureLaw::toJson)
    PartSummary part;
    std::optional<KernelSummary> kernel;
    PlanSummary plan;
    ExposureSummary exposure;
    std::vector<std::string> exports;  ///< machine files written (names in the output directory)
    double curedVolume = 0;            ///< mm^3 of the cured mesh
    ValidationReport validation;
    std::vector<std::pair<std::string, double>> stageSeconds;  ///< in run order
    /// How the work was split over MPI ranks ({"ranks": N, "split": ...}); null in one process,
    /// and then report.json has no "mpi".
    nlohmann::json mpi;
    std::vector<ReportSection> sections;            ///< components' own parts of index.html
    std::optional<ViewerSummary> viewer;            ///< the 3D view, when written
    std::optional<SectionViewSummary> sectionView;  ///< its sections, when recorded
    double deviationLimit = 0;                      ///< mm, the deviation maps' scale ends (±)
    double beyondDeviationLimit = 0;                ///< fraction of the cured surface beyond it
    /// Files of the run written before index.html (index.html and manifest.json follow), for the
    /// report's file list; the manifest lists the same files.
    std::vector<WrittenFile> files;
};

/// report.json's document.
nlohmann::json toJson(const JobResult& result);

}  // namespace vpsim::report
