// Reading working-curve measurements (dose, cured thickness) from CSV, units from the header.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"
#include "vpsim/cure/calibration.h"

namespace vpsim::cure {
namespace {

constexpr uint64_t MAX_CSV_BYTES = uint64_t(64) << 20;  // a working curve has tens of rows

std::string trim(const std::string& text) {
    size_t begin = text.find_first_not_of(" \t\r\"'");
    size_t end = text.find_last_not_of(" \t\r\"'");
    return begin == std::string::npos ? "" : text.substr(begin, end - begin + 1);
}

std::string lower(std::string text) {
    for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

std::vector<std::string> splitCells(const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream stream(line);
    std::string cell;
    while (std::getline(stream, cell, ',')) cells.push_back(trim(cell));
    if (!line.empty() && line.back() == ',') cells.push_back("");
    return cells;
}

/// Factor from the column's unit to base units, or 0 when the name carries no unit of `dimension`.
/// Units are in brackets ("dose [mJ/cm^2]", "Cd (mm)") or after an '_' ("dose_mJ_per_cm2").
double unitFactor(const std::string& name, Dimension dimension) {
    auto tryUnit = [&](std::string unit) {
        for (size_t at; (at = unit.find("_per_")) != std::string::npos;) unit.replace(at, 5, "/");
        if (unit.empty()) return 0.0;
        try {
            return parseQuantity("1 " + unit, dimension);
        } catch (const InputError&) {
            return 0.0;
        }
    };
    size_t open = name.find_first_of("[(");
    if (open != std::string::npos) {
        size_t close = name.find_first_of("])", open);
        return close == std::string::npos ? 0.0
                                          : tryUnit(trim(name.substr(open + 1, close - open - 1)));
    }
    for (size_t at = name.find('_'); at != std::string::npos; at = name.find('_', at + 1)) {
        double factor = tryUnit(name.substr(at + 1));
        if (factor > 0.0) return factor;
    }
    return 0.0;
}

bool isDoseName(const std::string& name) {
    std::string n = lower(name);
    return n.find("dose") != std::string::npos || n.find("exposure") != std::string::npos;
}

bool isDepthName(const std::string& name) {
    std::string n = lower(name);
    std::string head = n.substr(0, n.find_first_of("_ [("));
    return n.find("depth") != std::string::npos || n.find("thickness") != std::string::npos ||
           head == "cd" || head == "zf";
}

struct Column {
    size_t index = 0;
    double factor = 0.0;
    std::string name;
};

Column findColumn(const std::vector<std::string>& header, bool (*matches)(const std::string&),
                  Dimension dimension, const char* what, const char* example,
                  const std::string& file, int line) {
    std::vector<size_t> found;
    for (size_t i = 0; i < header.size(); ++i)
        if (matches(header[i])) found.push_back(i);
    if (found.empty())
        throw InputError(std::string("no ") + what +
                             " column in the header (expected a name like '" + example + "')",
                         file, "", line);
    if (found.size() > 1)
        throw InputError(std::string("more than one ") + what + " column: " +
                             quoteUser(header[found[0]]) + " and " + quoteUser(header[found[1]]),
                         file, "", line);
    Column column{found[0], unitFactor(header[found[0]], dimension), header[found[0]]};
    if (column.factor <= 0.0)
        throw InputError("column " + quoteUser(column.name) + " carries no " +
                             dimension.describe() + " unit (name it like '" + example + "')",
                         file, "", line);
    return column;
}

double parseCell(const std::string& cell, const Column& column, const std::string& file, int line) {
    if (cell.empty())
        throw InputError("empty cell in column " + quoteUser(column.name), file, "", line);
    // Decimal only (strtod would read "0x10", "inf", "nan"); 1e400 overflows to inf.
    const std::optional<double> value = parseDecimal(cell);
    if (!value)
        throw InputError(
            "non-numeric cell " + quoteUser(cell) + " in column " + quoteUser(column.name), file,
            "", line);
    const double scaled = *value * column.factor;
    if (!(std::fabs(scaled) <= MAX_QUANTITY_MAGNITUDE))
        throw InputError(
            "cell " + quoteUser(cell) + " in column " + quoteUser(column.name) + " is out of range",
            file, "", line);
    return scaled;
}

}  // namespace

WorkingCurveData parseWorkingCurveCsv(const std::string& text, const std::string& file) {
    WorkingCurveData data;
    data.file = file;
    std::vector<std::string> header;
    Column dose, depth;
    std::stringstream stream(text);
    std::string rawLine;
    int lineNumber = 0, lastLine = 0;
    while (std::getline(stream, rawLine)) {
        ++lineNumber;
        std::string line = trim(rawLine);
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> cells = splitCells(line);
        if (header.empty()) {
            header = cells;
            dose = findColumn(header, isDoseName, dim::DOSE, "dose", "dose_mJ_per_cm2", file,
                              lineNumber);
            depth = findColumn(header, isDepthName, dim::LENGTH, "cure depth", "thickness_mm", file,
                               lineNumber);
            data.doseColumn = dose.name;
            data.depthColumn = depth.name;
            continue;
        }
        if (cells.size() != header.size())
            throw InputError("expected " + std::to_string(header.size()) +
                                 " cells as in the header, got " + std::to_string(cells.size()),
                             file, "", lineNumber);
        double e0 = parseCell(cells[dose.index], dose, file, lineNumber);
        double cd = parseCell(cells[depth.index], depth, file, lineNumber);
        if (!(e0 > 0.0))
            throw InputError(
                "dose must be positive (the working curve is fitted against ln E0), got " +
                    quoteUser(cells[dose.index]),
                file, "", lineNumber);
        if (!(cd > 0.0))
            throw InputError(
                "cure depth must be positive (uncured samples do not lie on the working curve), "
                "got " +
                    quoteUser(cells[depth.index]),
                file, "", lineNumber);
        data.dose.push_back(e0);
        data.cureDepth.push_back(cd);
        data.line.push_back(lineNumber);
        lastLine = lineNumber;
    }
    if (header.empty())
        throw InputError("no header line (expected e.g. 'dose_mJ_per_cm2,thickness_mm')", file);
    if (data.dose.size() < 3)
        throw InputError(
            "only " + std::to_string(data.dose.size()) +
                " data row(s); at least 3 are needed to fit a line with standard errors",
            file, "", lastLine > 0 ? lastLine : lineNumber);
    return data;
}

WorkingCurveData loadWorkingCurveCsv(const std::string& path) {
    return parseWorkingCurveCsv(readFile(path, MAX_CSV_BYTES), path);
}

}  // namespace vpsim::cure
