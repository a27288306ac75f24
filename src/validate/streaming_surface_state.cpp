#include <filesystem>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

#include "streaming_surface_state.h"

namespace vpsim::validate {

nlohmann::json StreamingCuredSurface::saveState() {
    State& s = *mState;
    if (s.stl || s.finished)
        throw InputError(
            "the cured surface's state is saved only for an in-place STL or none, before "
            "finish()");
    if (s.started) s.closeTile();
    uint64_t stlBytes = 0;
    if (s.stlOut) {
        s.stlOut->flush();
        if (!*s.stlOut) throw InputError("cannot write the cured surface", s.inPlacePath);
        stlBytes = uint64_t(s.stlOut->tellp());
    }
    return {{"triangles", s.triangleCount},
            {"volume", s.volume},
            {"reference", {s.reference.x, s.reference.y, s.reference.z}},
            {"reference_set", s.referenceSet},
            {"statistics", s.statistics.toJson()},
            {"stl_bytes", stlBytes}};
}

void StreamingCuredSurface::restoreState(const nlohmann::json& state) {
    State& s = *mState;
    if (s.started || s.triangleCount || s.stl)
        throw InputError("the cured surface's state is restored only before its first slice");
    try {
        s.triangleCount = state.at("triangles").get<uint64_t>();
        s.volume = state.at("volume").get<double>();
        const auto& r = state.at("reference");
        s.reference = {r.at(0).get<double>(), r.at(1).get<double>(), r.at(2).get<double>()};
        s.referenceSet = state.at("reference_set").get<bool>();
        s.statistics = DeviationStatistics::fromJson(state.at("statistics"));
        s.tileStatistics = DeviationStatistics(s.statistics.band());
        const uint64_t stlBytes = state.at("stl_bytes").get<uint64_t>();
        if (s.inPlacePath.empty() != (stlBytes == 0))
            throw InputError("the saved cured surface's STL does not match this one's");
        if (stlBytes == 0) return;
        // The tiles after the state's are written again: the STL is cut back to its length.
        std::error_code error;
        const auto size = std::filesystem::file_size(s.inPlacePath, error);
        if (error || size < stlBytes)
            throw InputError(
                "shorter than its saved state (" + std::to_string(stlBytes) + " bytes)",
                s.inPlacePath);
        std::filesystem::resize_file(s.inPlacePath, stlBytes);
        s.inPlace = std::make_unique<std::fstream>(s.inPlacePath,
                                                   std::ios::in | std::ios::out | std::ios::binary);
        s.inPlace->seekp(0, std::ios::end);
        if (!*s.inPlace) throw InputError("cannot write the cured surface", s.inPlacePath);
        s.stlOut = s.inPlace.get();
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed cured-surface state: ") + e.what());
    }
}

void StreamingCuredSurface::savePicture(BinaryStateWriter& out) const {
    const State& s = *mState;
    if (s.started) throw InputError("the cured surface's picture is saved between tiles only");
    if (s.clusters) s.clusters->save(out, "cured.clusters");
    if (!s.keep) return;
    // Every vertex and triangle kept so far; a kept triangle's halo corner is resolved through
    // haloKeys and seamVertices when the mesh is made.
    out.add("cured.vertices", s.vertices);
    out.add("cured.deviations", s.deviations);
    out.add("cured.kept", s.kept);
    out.add("cured.halo_vertices", s.haloVertices);
    out.add("cured.halo_keys", s.haloKeys);
    std::vector<uint64_t> seamKeys;
    std::vector<uint32_t> seamIndices;
    for (const auto& [key, index] : s.seamVertices) {
        seamKeys.push_back(key);
        seamIndices.push_back(index);
    }
    out.add("cured.seam_keys", seamKeys);
    out.add("cured.seam_indices", seamIndices);
}

void StreamingCuredSurface::restorePicture(const BinaryStateReader& in) {
    State& s = *mState;
    if (s.started) throw InputError("the cured surface's picture is restored before its slices");
    if (s.clusters) s.clusters->restore(in, "cured.clusters");
    if (!s.keep) return;
    s.vertices = in.take<glm::vec3>("cured.vertices");
    s.deviations = in.take<float>("cured.deviations");
    s.kept = in.take<std::array<uint32_t, 3>>("cured.kept");
    s.haloVertices = in.take<glm::vec3>("cured.halo_vertices");
    s.haloKeys = in.take<uint64_t>("cured.halo_keys");
    const auto seamKeys = in.take<uint64_t>("cured.seam_keys");
    const auto seamIndices = in.take<uint32_t>("cured.seam_indices");
    bool good = s.deviations.size() == s.vertices.size() &&
                s.haloKeys.size() == s.haloVertices.size() && seamKeys.size() == seamIndices.size();
    s.seamVertices.clear();
    for (size_t i = 0; good && i < seamKeys.size(); ++i) {
        good = seamIndices[i] < s.vertices.size();
        s.seamVertices[seamKeys[i]] = seamIndices[i];
    }
    for (const auto& tri : s.kept)
        for (uint32_t v : tri)
            good =
                good && (v & surface_detail::HALO ? (v & ~surface_detail::HALO) < s.haloKeys.size()
                                                  : v < s.vertices.size());
    if (!good)
        throw InputError("malformed checkpoint state (the kept surface's records disagree)",
                         in.path());
    s.base = 0;
    s.layerStart = s.vertices.size();
}

void StreamingCuredSurface::mergeState(const nlohmann::json& later, const std::string& stlBody) {
    State& s = *mState;
    if (s.started || s.keep || s.clusters || s.finished)
        throw InputError("the cured surface merges other tiles only between its own");
    try {
        s.triangleCount += later.at("triangles").get<uint64_t>();
        s.volume += later.at("volume").get<double>();
        s.statistics.merge(DeviationStatistics::fromJson(later.at("statistics")));
        if (!s.referenceSet) {
            const auto& r = later.at("reference");
            s.reference = {r.at(0).get<double>(), r.at(1).get<double>(), r.at(2).get<double>()};
            s.referenceSet = later.at("reference_set").get<bool>();
        }
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed cured-surface state: ") + e.what());
    }
    s.openInPlace();
    if (s.stlOut) s.stlOut->write(stlBody.data(), std::streamsize(stlBody.size()));
}

}  // namespace vpsim::validate
