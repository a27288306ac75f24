#include <filesystem>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

#include "streaming_surface_state.h"

namespace vpsim::validate {

using surface_detail::HALO;

nlohmann::json StreamingCuredSurface::saveState() {
    State& s = *mState;
    s.settle();
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
    s.settle();
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
    s.settle();
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

namespace {

/// The kept picture's records (keepView(0)), checked against each other.
struct KeptPicture {
    std::vector<glm::vec3> vertices, haloVertices;
    std::vector<float> deviations;
    std::vector<std::array<uint32_t, 3>> kept;
    std::vector<uint64_t> haloKeys, seamKeys;
    std::vector<uint32_t> seamIndices;

    explicit KeptPicture(const BinaryStateReader& in)
        : vertices(in.take<glm::vec3>("cured.vertices")),
          haloVertices(in.take<glm::vec3>("cured.halo_vertices")),
          deviations(in.take<float>("cured.deviations")),
          kept(in.take<std::array<uint32_t, 3>>("cured.kept")),
          haloKeys(in.take<uint64_t>("cured.halo_keys")),
          seamKeys(in.take<uint64_t>("cured.seam_keys")),
          seamIndices(in.take<uint32_t>("cured.seam_indices")) {
        bool good = deviations.size() == vertices.size() &&
                    haloKeys.size() == haloVertices.size() && seamKeys.size() == seamIndices.size();
        for (size_t i = 0; good && i < seamIndices.size(); ++i)
            good = seamIndices[i] < vertices.size();
        for (const auto& tri : kept)
            for (uint32_t v : tri)
                good = good && (v & HALO ? (v & ~HALO) < haloKeys.size() : v < vertices.size());
        if (!good)
            throw InputError("malformed checkpoint state (the kept surface's records disagree)",
                             in.path());
    }
};

template <class T>
void append(std::vector<T>& to, const std::vector<T>& more) {
    to.insert(to.end(), more.begin(), more.end());
}

}  // namespace

void StreamingCuredSurface::restorePicture(const BinaryStateReader& in) {
    State& s = *mState;
    s.settle();
    if (s.started) throw InputError("the cured surface's picture is restored before its slices");
    if (s.clusters) s.clusters->restore(in, "cured.clusters");
    if (!s.keep) return;
    KeptPicture picture(in);
    s.vertices = std::move(picture.vertices);
    s.deviations = std::move(picture.deviations);
    s.kept = std::move(picture.kept);
    s.haloVertices = std::move(picture.haloVertices);
    s.haloKeys = std::move(picture.haloKeys);
    s.seamVertices.clear();
    for (size_t i = 0; i < picture.seamKeys.size(); ++i)
        s.seamVertices[picture.seamKeys[i]] = picture.seamIndices[i];
    s.base = 0;
    s.layerStart = s.vertices.size();
}

void StreamingCuredSurface::mergePicture(const BinaryStateReader& later) {
    State& s = *mState;
    s.settle();
    if (s.started || s.finished)
        throw InputError("the cured surface merges other tiles only between its own");
    if (s.clusters) s.clusters->merge(later, "cured.clusters");
    if (!s.keep) return;
    // Its vertices and halo vertices follow this surface's, as the one process numbers them.
    KeptPicture picture(later);
    const auto vertexOffset = uint32_t(s.vertices.size()),
               haloOffset = uint32_t(s.haloVertices.size());
    for (std::array<uint32_t, 3> tri : picture.kept) {
        for (uint32_t& v : tri) v = v & HALO ? HALO | ((v & ~HALO) + haloOffset) : v + vertexOffset;
        s.kept.push_back(tri);
    }
    for (size_t i = 0; i < picture.seamKeys.size(); ++i)
        s.seamVertices[picture.seamKeys[i]] = picture.seamIndices[i] + vertexOffset;
    append(s.vertices, picture.vertices);
    append(s.deviations, picture.deviations);
    append(s.haloVertices, picture.haloVertices);
    append(s.haloKeys, picture.haloKeys);
    s.base = 0;
    s.layerStart = s.vertices.size();
}

void StreamingCuredSurface::mergeState(const nlohmann::json& later) {
    State& s = *mState;
    s.settle();
    if (s.started || s.finished)
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
}

void StreamingCuredSurface::appendStl(const std::string& triangles) {
    State& s = *mState;
    s.settle();
    if (s.stlOut) s.stlOut->write(triangles.data(), std::streamsize(triangles.size()));
}

}  // namespace vpsim::validate
