#include <algorithm>
#include <sstream>

#include "vpsim/core/io.h"
#include "vpsim/geometry/polygons.h"

namespace vpsim::geometry {

void writePolygonSvg(const std::string& path, const PolygonSet& region, const std::string& title) {
    auto [lo, hi] = region.bounds();
    if (region.empty()) {
        lo = glm::dvec2(0.0);
        hi = glm::dvec2(1.0);
    }
    const double span = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6});
    const double margin = 0.08 * span;
    const double pixelsPerMm = 600.0 / (span + 2 * margin);
    const double width = (hi.x - lo.x + 2 * margin) * pixelsPerMm;
    const double height = (hi.y - lo.y + 2 * margin) * pixelsPerMm + 30;
    // Map mm to SVG pixels with y pointing up (SVG's y points down).
    auto px = [&](const glm::dvec2& p) {
        std::ostringstream s;
        s << (p.x - lo.x + margin) * pixelsPerMm << "," << 30 + (hi.y + margin - p.y) * pixelsPerMm;
        return s.str();
    };
    std::ostringstream svg;
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
        << "\" font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << "<text x=\"8\" y=\"20\" font-size=\"14\">" << title << " (area " << region.area()
        << " mm^2, " << region.outerCount() << " outer, " << region.holeCount() << " holes; x from "
        << lo.x << " mm, y from " << lo.y << " mm)</text>\n";
    for (const auto& contour : region.contours()) {
        if (contour.empty()) continue;
        svg << "<path fill-rule=\"evenodd\" d=\"M";
        for (const auto& p : contour) svg << px(p) << " ";
        svg << "Z\" fill=\"" << (signedArea(contour) > 0 ? "#6a9fd4" : "white")
            << "\" stroke=\"#1b3b6f\" stroke-width=\"1\"/>\n";
    }
    // Scale bar: 1 mm, or 0.1 mm for tiny regions.
    const double bar = span > 2.0 ? 1.0 : 0.1;
    svg << "<line x1=\"10\" y1=\"" << height - 10 << "\" x2=\"" << 10 + bar * pixelsPerMm
        << "\" y2=\"" << height - 10 << "\" stroke=\"black\" stroke-width=\"3\"/><text x=\""
        << 14 + bar * pixelsPerMm << "\" y=\"" << height - 6 << "\" font-size=\"12\">" << bar
        << " mm</text>\n</svg>\n";
    writeFileAtomic(path, svg.str());
}

}  // namespace vpsim::geometry
