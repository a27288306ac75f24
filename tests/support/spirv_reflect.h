#pragma once
// Just enough SPIR-V reading for the struct-layout test: member offsets (OpMemberDecorate Offset)
// and array strides (OpDecorate ArrayStride) of named structs.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace vpsim::test {

struct SpirvStruct {
    std::vector<std::string> memberNames;
    std::map<uint32_t, uint32_t> memberOffsets;  ///< member index -> byte offset
    uint32_t arrayStride = 0;                    ///< stride of a runtime array of this struct
};

inline std::string spirvString(const uint32_t* words, size_t count) {
    std::string text;
    for (size_t i = 0; i < count; ++i)
        for (int b = 0; b < 4; ++b) {
            char c = char((words[i] >> (8 * b)) & 0xFF);
            if (c == 0) return text;
            text += c;
        }
    return text;
}

/// Parses the named structs of a SPIR-V module (by OpName).
inline std::map<std::string, SpirvStruct> reflectStructs(const uint32_t* words, size_t wordCount) {
    constexpr uint32_t OP_NAME = 5, OP_MEMBER_NAME = 6, OP_DECORATE = 71, OP_MEMBER_DECORATE = 72,
                       OP_TYPE_RUNTIME_ARRAY = 29, DECORATION_OFFSET = 35,
                       DECORATION_ARRAY_STRIDE = 6;
    std::map<uint32_t, std::string> names;
    std::map<uint32_t, SpirvStruct> byId;
    std::map<uint32_t, uint32_t> strides, arrayElement;
    for (size_t i = 5; i < wordCount;) {
        uint32_t opcode = words[i] & 0xFFFF, length = words[i] >> 16;
        if (length == 0) break;
        const uint32_t* op = words + i;
        if (opcode == OP_NAME) names[op[1]] = spirvString(op + 2, length - 2);
        if (opcode == OP_MEMBER_NAME) {
            auto& members = byId[op[1]].memberNames;
            if (members.size() <= op[2]) members.resize(op[2] + 1);
            members[op[2]] = spirvString(op + 3, length - 3);
        }
        if (opcode == OP_MEMBER_DECORATE && op[3] == DECORATION_OFFSET)
            byId[op[1]].memberOffsets[op[2]] = op[4];
        if (opcode == OP_DECORATE && op[2] == DECORATION_ARRAY_STRIDE) strides[op[1]] = op[3];
        if (opcode == OP_TYPE_RUNTIME_ARRAY) arrayElement[op[1]] = op[2];
        i += length;
    }
    for (const auto& [arrayId, elementId] : arrayElement)
        if (strides.count(arrayId)) byId[elementId].arrayStride = strides[arrayId];
    std::map<std::string, SpirvStruct> result;
    for (const auto& [id, info] : byId)
        if (names.count(id)) result[names[id]] = info;
    return result;
}

}  // namespace vpsim::test
