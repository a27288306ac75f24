#pragma once
/// @file
/// The `optimised-mask` planner's body, as plain functions so that wiring it to the pipeline's
/// Planner interface is a few lines: parse the plan section, optimise the voxelised layers,
/// quantise through the projector's grey levels and return the ScanPlan of greyscale masks
/// (whose doses are the quantised ones, so the simulation re-simulates what the printer gets).
///
/// Plan section keys (unknown keys are errors through the config's checkUnknownKeys):
///   target_conversion  Phi_obj inside the part, in (0, 1), default 0.95
///   penalty            a of Eq. 12 (>= 0), default 5.5
///   max_dose           d_max, dose (e.g. "130 mJ/cm^2"), default 130 mJ/cm^2
///   objective          "conversion-l2" (default) | "geometric"
///   bonding            "own-layer" (default: reproduces Table 2) | "run-bottom"
///   xy_coupling        bool, default false (joint optimisation through the blur, xy.h)
///   margin             geometric objective: outside nodes below (1 - margin) Ec, default 0.05
///   uniform_dose       the uniform process the report compares with, simulated in the same run
///                      (a dose, "mean": the plan's mean exposed dose, i.e. the same light spread
///                      uniformly, or 0: none), default "mean"
///   figure_x, figure_y the pixel column of the dose/conversion-along-Z figure (mm); default
///                      the column with the most solid/void changes (down-facing surfaces)
///   figure_layer       the layer whose mask the report draws; default the layer with the most
///                      distinct grey levels

#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/optimise/dlp/xy.h"
#include "vpsim/plan/grey_levels.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim {
class ConfigNode;
}

namespace vpsim::optimise {

struct DlpMaskPlannerSettings {
    double targetConversion = 0.95;
    double penalty = 5.5;
    double maxDose = 1.3;  ///< mJ/mm^2
    DlpObjective objective = DlpObjective::ConversionL2;
    Bonding bonding = Bonding::OwnLayer;
    bool xyCoupling = false;
    double margin = 0.05;
    double uniformDose = -1.0;  ///< mJ/mm^2; -1: the plan's mean exposed dose; 0: no comparison
    bool figureColumnGiven = false;
    double figureX = 0.0, figureY = 0.0;  ///< mm
    long figureLayer = -1;                ///< -1: the layer with the most distinct grey levels
};

/// The resin and process a planner gets from the job.
struct DlpProcess {
    double rateConstant = 0.0;            ///< K, mm^2/mJ
    double gelPoint = 0.0;                ///< Phi_c
    double penetrationDepth = 0.0;        ///< Dp, mm
    double layerThickness = 0.05;         ///< mm
    double pixelPitch = 0.0625;           ///< mm
    double blurRadius = 0.04;             ///< mm (xy coupling)
    double originX = 0.0, originY = 0.0;  ///< mm, corner of pixel (0, 0)
};

struct DlpMaskPlan {
    plan::ScanPlan plan;                     ///< one greyscale mask per layer (quantised doses)
    DlpPartResult optimised;                 ///< the optimiser's doses before quantisation
    std::vector<std::vector<uint8_t>> grey;  ///< per layer, per pixel grey level
    nlohmann::json summary;  ///< figures for the report (columns, gaps, grey histogram)
    /// Data of the report's DLP figures (dlpReportFigureData), kept out of report.json.
    nlohmann::json figures;
    /// With xy_coupling: the column optimum's plan (quantised the same way), which the report
    /// simulates beside the joint one to compare their XY contour errors; else empty.
    plan::ScanPlan columnPlan;
};

/// Optimises, quantises and builds the plan. @throw InputError on bad inputs, or when d_max
/// exceeds the brightest grey level's dose
DlpMaskPlan planOptimisedMasks(const DlpLayerStack& part, const DlpProcess& process,
                               const DlpMaskPlannerSettings& settings,
                               const plan::GreyLevels& levels);

/// Data of the paper's Fig. 13-16 for pixel column (x, y): per layer the height of its top node
/// (mm), solid or not, the optimised and the quantised dose (mJ/cm^2) and the conversion Phi at
/// the node after quantisation (print-through included):
/// {"z_mm", "solid", "dose_mJ_per_cm2", "quantised_dose_mJ_per_cm2", "conversion"}.
/// @throw InputError when (x, y) is outside the part's masks
/// The data of the report's DLP figures: {"column": dlpColumnFigureData of the figure column
/// with "x_mm", "y_mm", "gel_point", "target_conversion"; "layer": the mask layer to draw;
/// "grey_dose_mJ_per_cm2": dose of each grey level 0..255; "mean_exposed_dose": mJ/mm^2}.
/// @throw InputError when figure_x/y or figure_layer lie outside the part
nlohmann::json dlpReportFigureData(const DlpMaskPlan& plan, const DlpLayerStack& part,
                                   const DlpProcess& process,
                                   const DlpMaskPlannerSettings& settings,
                                   const plan::GreyLevels& levels);

/// The pixel column with the most solid/void changes along Z (ties: nearest the centre).
void busiestColumn(const DlpLayerStack& part, int& x, int& y);

/// The layer with the most distinct grey levels among its exposed pixels (ties: the lowest).
long busiestGreyLayer(const std::vector<std::vector<uint8_t>>& grey);

nlohmann::json dlpColumnFigureData(const DlpMaskPlan& plan, const DlpLayerStack& part,
                                   const DlpProcess& process, int x, int y);

}  // namespace vpsim::optimise
