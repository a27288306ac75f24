#include <filesystem>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

#include "streaming_surface_state.h"

namespace vpsim::validate {

nlohmann::json StreamingCuredSurface::saveState() {
    State& s = *mState;
    if (s.keep || s.clusters || s.stl || s.finished)
        throw InputError(
            "the cured surface's state is saved only for an in-place STL, without "
            "kept triangles or view, before finish()");
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
