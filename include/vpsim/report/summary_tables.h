#pragma once
/// @file
/// The summary of a run as tables, from its report.json document (toJson), so index.html and
/// `vpsim compare` show the same rows: the inputs (job, material, cure law, part, machine,
/// kernel, simulation, plan summary), the verdict and the features. Numbers are formatted for
/// people (4 significant digits), keys from report.json's names ("hatch_spacing_um" becomes
/// "hatch spacing (µm)").

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/core/base64.h"  // base64, used with the tables by the report writers
#include "vpsim/report/job_result.h"

namespace vpsim::report {

/// A titled table of a summary.
struct SummaryTable {
    std::string title;
    ReportTable table;
};

/// The inputs, first what was asked (job sections as written) then the plan's summary.
std::vector<SummaryTable> inputTables(const nlohmann::json& report);
/// IoU, surface deviation with the shares beyond the band and the colour scale, over-cure, XY
/// error, volumes.
SummaryTable verdictTable(const nlohmann::json& report);
/// Predicted, objective, measured and their differences per feature; empty rows when none.
SummaryTable featuresTable(const nlohmann::json& report);

/// Several runs' tables of one kind as one table with a column per run (rows by first cell).
ReportTable sideBySide(const std::vector<ReportTable>& tables,
                       const std::vector<std::string>& runNames);

/// A table as HTML (the first column as row headers); every cell escaped.
std::string tableHtml(const ReportTable& table);
/// "hatch_spacing_um" -> "hatch spacing (µm)".
std::string humanKey(const std::string& key);
/// A JSON value as text for a table cell: numbers with 4 significant digits, arrays joined.
std::string humanValue(const nlohmann::json& value);

}  // namespace vpsim::report
