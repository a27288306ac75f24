// libFuzzer target: the JSON config reader (limits, duplicate keys), --set overrides, the
// unit-aware getters and the unknown-key check. Any exception other than vpsim::Error is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/units.h"

namespace {

using namespace vpsim;

const Dimension DIMENSIONS[] = {dim::LENGTH,         dim::DOSE,  dim::POWER,         dim::TIME,
                                dim::INVERSE_LENGTH, dim::ANGLE, dim::DIMENSIONLESS, dim::SPEED};

/// Reads every key of an object with a getter of its type, as components would.
void visit(const ConfigNode& node, const nlohmann::json& object, int depth) {
    if (depth > 8) return;
    size_t k = 0;
    for (auto it = object.begin(); it != object.end(); ++it, ++k) {
        const std::string& key = it.key();
        const nlohmann::json& value = it.value();
        try {
            if (value.is_object()) {
                visit(node.child(key), value, depth + 1);
            } else if (value.is_array()) {
                if (!value.empty() && value[0].is_object()) {
                    for (const ConfigNode& child : node.children(key)) (void)child.keyPath("x");
                } else {
                    (void)node.raw(key);
                }
            } else if (value.is_string()) {
                (void)node.quantity(key, DIMENSIONS[k % 8]);
            } else if (value.is_boolean()) {
                (void)node.boolean(key);
            } else if (value.is_number_integer()) {
                (void)node.integer(key);
            } else {
                (void)node.numberInRange(key, -1e6, 1e6);
            }
        } catch (const Error&) {}
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        // The first line, when it holds an '=', is also tried as a --set override.
        const size_t newline = text.find('\n');
        nlohmann::json document =
            parseJsonText(text.substr(newline == std::string::npos ? 0 : newline), "fuzz.json");
        if (newline != std::string::npos && text.find('=') < newline)
            applyOverride(document, text.substr(0, newline));
        ConfigNode root(document, "fuzz.json");
        visit(root, document, 0);
        root.checkUnknownKeys();
    } catch (const Error&) {}
    try {
        (void)parseQuantity(text.substr(0, 256), dim::DOSE, "k", "fuzz");
    } catch (const Error&) {}
    return 0;
}
