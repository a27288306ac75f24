#pragma once
/// @file
/// `vpsim compare RUN_DIR... --out DIR`: runs side by side on one page (DIR/index.html): their
/// inputs, verdicts and features in columns, their exposure-error curves overlaid (XY contour
/// error per layer; the laser exposure error per layer when present), and their figures in
/// columns (copied under DIR/run-N/). A run directory whose manifest does not match its files is
/// refused before anything is written.

#include <string>
#include <vector>

namespace vpsim::report {

/// Writes the comparison into `outDir` (with its own manifest) and returns index.html's path.
/// @throw InputError naming a run directory that is not a complete run (reason from
/// verifyOutputDirectory) or a file that cannot be written
std::string writeComparePage(const std::vector<std::string>& runDirs, const std::string& outDir);

}  // namespace vpsim::report
