// The plotting layer: what a figure shows is in its SVG as text (title, axis labels, tick labels,
// colour bar label, legend, note), maps keep the data's aspect ratio, large grids are averaged
// down to MAX_MAP_CELLS (checked against a brute-force mean), and both files are written.
#include <png.h>
#include <zlib.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>

#include "support/svg_text.h"
#include "vpsim/core/error.h"
#include "vpsim/core/image.h"
#include "vpsim/plot/plot.h"

using namespace vpsim;
using vpsim::test::hasText;
using vpsim::test::readWhole;
using vpsim::test::svgTexts;

namespace {

std::filesystem::path scratch(const char* name) {
    const auto dir = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

/// Numbers among the SVG's texts (the tick labels).
size_t numericTexts(const std::string& svg) {
    size_t count = 0;
    for (const std::string& t : svgTexts(svg))
        count += std::regex_match(t, std::regex(R"(\s*[-−]?[0-9]+(\.[0-9]+)?\s*)"));
    return count;
}

/// width / height of the SVG's embedded raster (the map's plot area).
double rasterAspect(const std::string& svg) {
    std::smatch m;
    REQUIRE(std::regex_search(svg, m,
                              std::regex(R"(<image x='[^']*' y='[^']*' width='([0-9.]+)' )"
                                         R"(height='([0-9.]+)')")));
    return std::stod(m[1]) / std::stod(m[2]);
}

/// (x, y, width, height) of the SVG's embedded raster in the page's pixels.
std::array<double, 4> rasterRectangle(const std::string& svg) {
    std::smatch m;
    REQUIRE(std::regex_search(svg, m,
                              std::regex(R"(<image x='([0-9.]+)' y='([0-9.]+)' width='([0-9.]+)' )"
                                         R"(height='([0-9.]+)')")));
    return {std::stod(m[1]), std::stod(m[2]), std::stod(m[3]), std::stod(m[4])};
}

struct PngPixels {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
    std::array<int, 3> at(int x, int y) const {
        const uint8_t* p = &rgb[(size_t(y) * width + x) * 3];
        return {p[0], p[1], p[2]};
    }
};

PngPixels readPng(const std::string& path) {
    const std::string data = readWhole(path);
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_memory(&image, data.data(), data.size()));
    image.format = PNG_FORMAT_RGB;
    PngPixels pixels{int(image.width), int(image.height), {}};
    pixels.rgb.resize(PNG_IMAGE_SIZE(image));
    REQUIRE(png_image_finish_read(&image, nullptr, pixels.rgb.data(), 0, nullptr));
    return pixels;
}

}  // namespace

TEST_CASE("line figure: labels, ticks and legend as SVG text, and a PNG", "[plot]") {
    const auto dir = scratch("vpsim_test_plot_line");
    plot::LineFigure f;
    f.title = "A title";
    f.xLabel = "depth z (µm)";
    f.yLabel = "We (µm)";
    f.note = "a note under the plot";
    f.curves.push_back({"first curve", {0, 1, 2}, {1, 3, 2}});
    f.curves.push_back({"second curve", {0, 2}, {2, 2}, plot::paletteColour(1), true});
    const std::string stem = (dir / "line").string();
    plot::writeLineFigure(stem, f);
    const std::string svg = readWhole(stem + ".svg");
    for (const char* text : {"A title", "depth z (µm)", "We (µm)", "first curve", "second curve",
                             "a note under the plot"}) {
        INFO(text);
        CHECK(hasText(svg, text));
    }
    CHECK(numericTexts(svg) >= 6);  // tick labels on both axes
    CHECK(std::filesystem::file_size(stem + ".png") > 1000);
    std::filesystem::remove_all(dir);
}

TEST_CASE("bars on categories and a log axis", "[plot]") {
    const auto dir = scratch("vpsim_test_plot_bars");
    plot::LineFigure f{"Bars", "", "count", {}};
    plot::Curve bars{"counts"};
    bars.style = plot::CurveStyle::Bars;
    bars.x = {0, 1}, bars.y = {3, 3000};
    bars.errorLow = {2, 2000}, bars.errorHigh = {4, 4000};
    f.curves = {bars};
    f.xCategories = {{0, "hole"}, {1, "pillar"}};
    f.logY = true;
    const std::string stem = (dir / "bars").string();
    plot::writeLineFigure(stem, f);
    const std::string svg = readWhole(stem + ".svg");
    CHECK(hasText(svg, "hole"));
    CHECK(hasText(svg, "pillar"));
    CHECK(hasText(svg, "counts"));
    std::filesystem::remove_all(dir);
}

TEST_CASE("map figure: colour bar, outlines in the legend, true aspect ratio", "[plot]") {
    const auto dir = scratch("vpsim_test_plot_map");
    plot::MapFigure f;
    f.title = "Exposure map";
    f.nx = 40, f.ny = 10;
    f.x0 = 0, f.x1 = 4, f.y0 = 1, f.y1 = 2;  // 4 mm x 1 mm
    for (int j = 0; j < f.ny; ++j)
        for (int i = 0; i < f.nx; ++i) f.values.push_back(float(i));
    f.scale = {plot::ColourMap::Sequential, 0, 39, "exposure (mJ/cm#u2#d)", false, false};
    f.outlines.push_back({"cured edge", {}, 20.0, {230, 30, 30}, false});
    f.lines.push_back({"model outline", {1, 3, 3, 1, 1}, {1.2, 1.2, 1.8, 1.8, 1.2}});
    f.note = "1.5% of the cells above the scale";
    const std::string stem = (dir / "map").string();
    plot::writeMapFigure(stem, f);
    const std::string svg = readWhole(stem + ".svg");
    for (const char* text : {"Exposure map", "x (mm)", "y (mm)", "exposure (mJ/cm", "cured edge",
                             "model outline", "1.5% of the cells"}) {
        INFO(text);
        CHECK(hasText(svg, text));
    }
    CHECK(hasText(svg, " mm"));  // the scale bar's length
    CHECK(rasterAspect(svg) == Approx(4.0).epsilon(0.01));
    CHECK(std::filesystem::file_size(stem + ".png") > 1000);
    const plot::MapFigure empty;
    CHECK_THROWS_AS(plot::writeMapFigure(stem, empty), InputError);
    std::filesystem::remove_all(dir);
}

TEST_CASE("map figure's PNG: the cells under the SVG's raster, edge pixels by area", "[plot]") {
    const auto dir = scratch("vpsim_test_plot_map_png");
    plot::MapFigure f;  // three columns: the scale's bottom, no data, the scale's top
    f.nx = 3, f.ny = 2;
    f.x0 = 0, f.x1 = 3, f.y0 = 0, f.y1 = 1;
    f.values = {0, NAN, 1, 0, NAN, 1};
    f.scale = {plot::ColourMap::Sequential, 0, 1, "exposure", false, false};
    f.scaleBar = false;
    const std::string stem = (dir / "cells").string();
    plot::writeMapFigure(stem, f);
    const auto [left, top, width, height] = rasterRectangle(readWhole(stem + ".svg"));
    const PngPixels png = readPng(stem + ".png");
    const int y = int(top + height / 4);  // the middle of the top row of cells
    using Colour = std::array<int, 3>;
    auto near = [](Colour a, Colour b) {
        for (int k = 0; k < 3; ++k)
            if (std::abs(a[k] - b[k]) > 1) return false;
        return true;
    };
    // Viridis's ends (matplotlib's table) and the no-data grey, at the columns' centres.
    CHECK(near(png.at(int(left + width / 6), y), {68, 1, 84}));
    CHECK(near(png.at(int(left + width / 2), y), {150, 150, 150}));
    CHECK(near(png.at(int(left + 5 * width / 6), y), {253, 231, 37}));
    // The pixel across the first columns' edge: each colour by the length of it that it covers.
    const double edge = left + width / 3;
    const int x = int(std::floor(edge));
    const double first = edge - x;
    INFO("edge at " << edge);
    CHECK(near(png.at(x, y), {int(std::lround(first * 68 + (1 - first) * 150)),
                              int(std::lround(first * 1 + (1 - first) * 150)),
                              int(std::lround(first * 84 + (1 - first) * 150))}));
    std::filesystem::remove_all(dir);
}

TEST_CASE("large maps are averaged down to MAX_MAP_CELLS, their edges kept", "[plot]") {
    plot::MapFigure f;
    f.nx = 2500, f.ny = 7;
    f.x0 = -1, f.x1 = 1.5, f.y0 = 0, f.y1 = 0.007;
    for (int j = 0; j < f.ny; ++j)
        for (int i = 0; i < f.nx; ++i)
            f.values.push_back(i == 5 && j == 3 ? NAN : float(std::sin(0.01 * i) + j));
    std::vector<float> mask(f.values.size(), 1.0f);
    f.outlines.push_back({"mask", mask, 0.5, {0, 0, 0}, false});
    const plot::MapFigure d = plot::downsampled(f);
    REQUIRE(d.nx == 834);  // ceil(2500 / 3): blocks of 2 or 3 cells
    REQUIRE(d.ny == 3);
    CHECK(d.x0 == f.x0);
    CHECK(d.x1 == f.x1);
    REQUIRE(d.outlines[0].field.size() == d.values.size());
    // Brute force: cell i of the original is in the last block starting at or before it (block b
    // starts at floor(b n / n')), and a block's value is the mean of its finite cells.
    auto block = [](int i, int n, int blocks) { return ((i + 1) * blocks + n - 1) / n - 1; };
    for (int jd = 0; jd < d.ny; ++jd)
        for (int id = 0; id < d.nx; id += 97) {
            double sum = 0;
            int count = 0;
            for (int j = 0; j < f.ny; ++j)
                for (int i = 0; i < f.nx; ++i) {
                    const float v = f.values[size_t(j) * f.nx + i];
                    if (block(i, f.nx, d.nx) != id || block(j, f.ny, d.ny) != jd || std::isnan(v))
                        continue;
                    sum += v, ++count;
                }
            INFO(id << ", " << jd);
            CHECK(d.values[size_t(jd) * d.nx + id] == Approx(sum / count).epsilon(1e-5));
            CHECK(d.outlines[0].field[size_t(jd) * d.nx + id] == 1.0f);
        }
    plot::MapFigure small = f;
    small.nx = 10, small.ny = 7;
    small.values.resize(70);
    CHECK(plot::downsampled(small).values == small.values);
}

TEST_CASE("contour lines: joined polylines at the interpolated crossings", "[plot]") {
    const int n = 41;
    auto field = [&](auto value) {
        std::vector<float> f;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) f.push_back(float(value(i, j)));
        return f;
    };
    // A cone: one closed line, on the circle of the level's radius, enclosing its area.
    const double cx = 20.3, cy = 19.6, r = 12;
    auto distance = [&](double i, double j) { return std::hypot(i - cx, j - cy); };
    std::vector<plot::ContourLine> lines = plot::contourLines(field(distance), n, n, r);
    REQUIRE(lines.size() == 1);
    const plot::ContourLine& circle = lines[0];
    REQUIRE(circle.x.size() > 50);
    CHECK(circle.x.front() == circle.x.back());
    CHECK(circle.y.front() == circle.y.back());
    double area = 0;
    for (size_t k = 0; k < circle.x.size(); ++k) {
        CHECK(distance(circle.x[k], circle.y[k]) == Approx(r).margin(0.03));
        if (k > 0) area += circle.x[k - 1] * circle.y[k] - circle.x[k] * circle.y[k - 1];
    }
    CHECK(std::abs(area) / 2 == Approx(M_PI * r * r).epsilon(0.01));
    // Two separate bumps: two lines.
    auto bumps = [&](double i, double j) {
        return std::max(5 - std::hypot(i - 10, j - 10), 5 - std::hypot(i - 30, j - 30));
    };
    CHECK(plot::contourLines(field(bumps), n, n, 1.0).size() == 2);
    // A ramp across the grid: one open line from edge to edge at the interpolated x.
    lines = plot::contourLines(field([](int i, int) { return i; }), n, n, 10.25);
    REQUIRE(lines.size() == 1);
    CHECK(lines[0].x.size() == size_t(n));
    for (double x : lines[0].x) CHECK(x == Approx(10.25));
    CHECK(std::min(lines[0].y.front(), lines[0].y.back()) == 0);
    CHECK(std::max(lines[0].y.front(), lines[0].y.back()) == n - 1);
    // A cell without data inside a field above the level: the line goes round it through its
    // neighbours' centres.
    std::vector<float> hole = field([](int, int) { return 1.0; });
    hole[size_t(5) * n + 5] = NAN;
    lines = plot::contourLines(hole, n, n, 0.5);
    REQUIRE(lines.size() == 1);
    CHECK(lines[0].x.size() == 5);
    for (size_t k = 0; k < lines[0].x.size(); ++k)
        CHECK(std::abs(lines[0].x[k] - 5) + std::abs(lines[0].y[k] - 5) == 1.0);
    CHECK(plot::contourLines(hole, n, n, 2.0).empty());
}

/// The filter byte of each row of an 8-bit RGB PNG (its IDAT chunks inflated).
std::vector<int> rowFilters(const std::string& png, int width, int height) {
    std::string deflated;
    for (size_t at = 8; at + 8 <= png.size();) {
        const size_t length = size_t(uint8_t(png[at])) << 24 | size_t(uint8_t(png[at + 1])) << 16 |
                              size_t(uint8_t(png[at + 2])) << 8 | size_t(uint8_t(png[at + 3]));
        if (png.compare(at + 4, 4, "IDAT") == 0) deflated += png.substr(at + 8, length);
        at += 12 + length;
    }
    std::vector<unsigned char> rows(size_t(height) * (1 + 3 * size_t(width)));
    uLongf size = uLongf(rows.size());
    REQUIRE(uncompress(rows.data(), &size, reinterpret_cast<const Bytef*>(deflated.data()),
                       uLong(deflated.size())) == Z_OK);
    std::vector<int> filters;
    for (int y = 0; y < height; ++y) filters.push_back(rows[size_t(y) * (1 + 3 * size_t(width))]);
    return filters;
}

TEST_CASE("PNG effort: Quick writes unfiltered rows of the same pixels", "[plot]") {
    const auto dir = scratch("vpsim_test_png_effort");
    RgbImage image(120, 40);  // a figure's kind of picture: a ramp beside flat colour
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < 60; ++x) image.set(x, y, uint8_t(4 * x), uint8_t(6 * y), 90);
    const std::string quick = (dir / "quick.png").string(), small = (dir / "small.png").string();
    writePng(quick, image, PngEffort::Quick);
    writePng(small, image);
    for (const std::string& path : {quick, small}) {
        const PngPixels read = readPng(path);
        CHECK(read.width == image.width);
        CHECK(read.rgb == image.pixels);
    }
    const std::vector<int> unfiltered = rowFilters(readWhole(quick), image.width, image.height);
    CHECK(std::all_of(unfiltered.begin(), unfiltered.end(), [](int f) { return f == 0; }));
    const std::vector<int> chosen = rowFilters(readWhole(small), image.width, image.height);
    CHECK(std::any_of(chosen.begin(), chosen.end(), [](int f) { return f != 0; }));
    std::filesystem::remove_all(dir);
}

TEST_CASE("figure stems from a user's FILE.svg", "[plot]") {
    CHECK(plot::figureStem("out/wc.svg") == "out/wc");
    CHECK(plot::figureStem("out/wc") == "out/wc");
    CHECK(plot::figureStem(".svg") == ".svg");
    CHECK_THROWS_AS(plot::figureStem(std::filesystem::temp_directory_path().string()), InputError);
}

TEST_CASE("missing PLplot drivers: one clear error, no file, no prompt", "[plot]") {
    const auto dir = scratch("vpsim_test_plot_no_drivers");
    const std::string drivers = (dir / "drivers").string();
    std::filesystem::create_directories(drivers);
    ::setenv("PLPLOT_DRV_DIR", drivers.c_str(), 1);
    plot::LineFigure f{"t", "x", "y", {{"c", {0, 1}, {0, 1}}}};
    const std::string stem = (dir / "line").string();
    CHECK_THROWS_AS(plot::writeLineFigure(stem, f), ResourceError);
    CHECK_THROWS_WITH(
        plot::writeLineFigure(stem, f),
        Catch::Contains("svg driver is not in " + drivers) && Catch::Contains("PLPLOT_DRV_DIR"));
    CHECK_FALSE(std::filesystem::exists(stem + ".svg"));
    CHECK_FALSE(std::filesystem::exists(stem + ".png"));
    ::unsetenv("PLPLOT_DRV_DIR");
    CHECK_NOTHROW(plot::requirePlotting());  // the installed drivers
    std::filesystem::remove_all(dir);
}
