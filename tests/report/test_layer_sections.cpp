// The 3D view's per-layer sections: the sampling stays under its pixel budget with the finest
// pixels that fit, and sections.js holds, for each kept layer, the box average of its middle
// voxel slice on the stated scale, the cured pixels by the majority rule, the model's outline,
// and the kernel's fit at the bin centres; all checked against direct computations.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpsim/cure/threshold_law.h"
#include "vpsim/report/layer_sections.h"

using namespace vpsim;

namespace {

std::string decodeBase64(const std::string& text) {
    std::string out;
    int bits = 0;
    unsigned buffer = 0;  // holds at most 13 unread bits: masked after each byte
    for (char c : text) {
        int v = c >= 'A' && c <= 'Z'   ? c - 'A'
                : c >= 'a' && c <= 'z' ? c - 'a' + 26
                : c >= '0' && c <= '9' ? c - '0' + 52
                : c == '+'             ? 62
                : c == '/'             ? 63
                                       : -1;
        if (v < 0) continue;  // padding
        buffer = (buffer << 6) | unsigned(v), bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(char((buffer >> bits) & 0xffu));
            buffer &= (1u << bits) - 1;
        }
    }
    return out;
}

template <typename T>
std::vector<T> decodeArray(const nlohmann::json& field) {
    const std::string bytes = decodeBase64(field.get<std::string>());
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
    return out;
}

/// The JSON object assigned to `name` in sections.js.
nlohmann::json assigned(const std::string& js, const std::string& name) {
    const size_t start = js.find(name + "=") + name.size() + 1;
    const size_t end = js.find(";\n", start);
    return nlohmann::json::parse(js.substr(start, end - start));
}

}  // namespace

TEST_CASE("Section sampling: finest pixels under the budget, then every n-th layer", "[report]") {
    for (int nx : {10, 255, 257, 700, 3000})
        for (int ny : {1, 90, 400, 2500})
            for (int layers : {1, 7, 64, 300, 5000}) {
                const report::SectionSampling s = report::sectionSampling(nx, ny, layers);
                INFO(nx << " x " << ny << " cells, " << layers << " layers");
                CHECK(std::max(s.width, s.height) <= report::SECTION_MAX_SIDE);
                CHECK(s.width == (nx + s.factor - 1) / s.factor);
                CHECK(s.height == (ny + s.factor - 1) / s.factor);
                const uint64_t kept = uint64_t((layers + s.stride - 1) / s.stride);
                CHECK(kept * uint64_t(s.width) * s.height <= report::SECTION_PIXEL_BUDGET);
                // A finer pixel would not have fitted all layers, unless it is above the cap.
                const int finer = s.factor - 1;
                if (finer >= 1 && std::max(nx, ny) <= finer * report::SECTION_MAX_SIDE)
                    CHECK(uint64_t((nx + finer - 1) / finer) * ((ny + finer - 1) / finer) *
                              uint64_t(layers) >
                          report::SECTION_PIXEL_BUDGET);
                // Layers are skipped only at the coarsest pixels.
                if (s.stride > 1) CHECK(std::max(s.width, s.height) <= report::SECTION_MIN_SIDE);
            }
}

TEST_CASE("Layer sections: box averages of the middle slice, majority cure, outlines, kernel fit",
          "[report]") {
    const auto dir = std::filesystem::temp_directory_path() / "vpsim_test_layer_sections";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    exposure::ExposureGrid grid;
    grid.nx = 300, grid.ny = 121;  // more than 256 cells: 2 x 2 cells per pixel, a partial row
    grid.originX = -1.5, grid.originY = -0.6, grid.pitch = 0.01, grid.slicesPerLayer = 3;
    geometry::LayerStack stack;
    stack.layerThickness = 0.05;
    const int layers = 4;
    for (int k = 0; k < layers; ++k) {
        geometry::Layer layer;
        layer.index = k;
        layer.z = 0.05 * k + 0.025;
        layer.region = geometry::PolygonSet::rectangle({-1.0 + 0.1 * k, -0.5}, {1.0, 0.5});
        stack.layers.push_back(layer);
    }
    const cure::ThresholdLaw law(0.1);  // 10 mJ/cm^2
    report::LayerSectionRecorder recorder(stack, grid, law);
    // Slice s of layer k: a ramp in x and y that differs per layer; the other slices far above,
    // so recording the wrong slice shows.
    const auto value = [](int i, int j, int k) { return float(0.001 * i + 0.0003 * j + 0.02 * k); };
    for (int k = layers - 1; k >= 0; --k)
        for (int s = 0; s < grid.slicesPerLayer; ++s) {
            exposure::SurfaceGrid g = grid.surface();
            for (int j = 0; j < grid.ny; ++j)
                for (int i = 0; i < grid.nx; ++i) g.at(i, j) = s == 1 ? value(i, j, k) : 100.0f;
            recorder.add({k, s, 0.05 * (k + 1) - (s + 0.5) * 0.05 / 3, &g});
        }
    kernel::BeamKernel beam;
    beam.rBins = 6, beam.zBins = 5, beam.rBin = 0.01, beam.zBin = 0.02;
    beam.intensity.assign(30, 1.0f);
    beam.fit.amplitude = 3.0, beam.fit.we3d = 0.03, beam.fit.de3d = 0.05;
    const report::SectionViewSummary summary = recorder.write(dir.string(), &beam);

    std::ifstream in(dir / "sections.js");
    std::stringstream text;
    text << in.rdbuf();
    const nlohmann::json d = assigned(text.str(), "window.VPSIM_SECTIONS");
    REQUIRE(d["width"] == 150);
    REQUIRE(d["height"] == 61);
    CHECK(summary.layersKept == layers);
    CHECK(d["kept"] == nlohmann::json({0, 1, 2, 3}));
    const double top = d["scale_max"].get<double>();
    CHECK(top >= 2 * 10.0);
    const std::vector<uint8_t> exposure = decodeArray<uint8_t>(d["exposure"]);
    const std::vector<uint8_t> cured = decodeArray<uint8_t>(d["cured"]);
    REQUIRE(exposure.size() == size_t(layers) * 150 * 61);
    const size_t perLayer = 150 * 61, bytesPerLayer = (perLayer + 7) / 8;
    size_t above = 0;
    for (int k = 0; k < layers; ++k)
        for (int pj = 0; pj < 61; ++pj)
            for (int pi = 0; pi < 150; ++pi) {
                double sum = 0;
                int n = 0, curedCells = 0;
                for (int j = 2 * pj; j < std::min(grid.ny, 2 * pj + 2); ++j)
                    for (int i = 2 * pi; i < 2 * pi + 2; ++i, ++n) {
                        sum += value(i, j, k);
                        curedCells += value(i, j, k) >= 0.1f;
                    }
                const double mJcm2 = sum / n * 100;
                above += mJcm2 > top;
                const size_t p = size_t(pj) * 150 + pi;
                const double shown = exposure[k * perLayer + p] / 255.0 * top;
                if (mJcm2 <= top) CHECK(std::abs(shown - mJcm2) <= top / 255.0 * 0.5 + 1e-6);
                const bool bit = (cured[k * bytesPerLayer + p / 8] >> (p % 8)) & 1;
                CHECK(bit == (2 * curedCells >= n));
            }
    // The scale is the 99th percentile: about 1% above it, no more.
    CHECK(double(above) / exposure.size() <= 0.011);
    CHECK(d["above_fraction"].get<double>() ==
          Approx(double(above) / exposure.size()).margin(1e-4));
    // Each layer's outline is its rectangle.
    const std::vector<uint32_t> counts = decodeArray<uint32_t>(d["outline_counts"]);
    const std::vector<float> xy = decodeArray<float>(d["outline_xy"]);
    size_t c = 0, p = 0;
    for (int k = 0; k < layers; ++k) {
        REQUIRE(counts[c++] == 1);
        REQUIRE(counts[c++] == 4);
        double xmin = 1e9;
        for (int v = 0; v < 4; ++v, p += 2) xmin = std::min(xmin, double(xy[p]));
        CHECK(xmin == Approx(-1.0 + 0.1 * k));
    }
    CHECK(p == xy.size());
    // The kernel's fit at the bin centres.
    const nlohmann::json kern = assigned(text.str(), "window.VPSIM_KERNEL");
    const std::vector<float> fit = decodeArray<float>(kern["fit"]);
    REQUIRE(fit.size() == 30);
    for (int iz = 0; iz < 5; ++iz)
        for (int ir = 0; ir < 6; ++ir) {
            const double r = (ir + 0.5) * 0.01, z = (iz + 0.5) * 0.02;
            CHECK(fit[iz * 6 + ir] ==
                  Approx(3.0 * std::exp(-2 * r * r / (0.03 * 0.03)) * std::exp(-z / 0.05)));
        }
    CHECK(std::filesystem::exists(dir / "section_view.js"));
    std::filesystem::remove_all(dir);
}
