#include "vpsim/cure/cure_law.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/checks.h"
#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"

namespace vpsim::cure {

void CureLaw::conversionRange(const float* dose, size_t count, float* conversion) const {
    for (size_t i = 0; i < count; ++i) conversion[i] = float(this->conversion(dose[i]));
}

float CureLaw::floatAtLeast(double value) {
    // Rounding to nearest lands on the float just below or just above (or on) the value.
    float f = float(value);
    if (double(f) < value) f = std::nextafter(f, INFINITY);
    return f;
}

double CureLaw::cureDepth(double surfaceDose) const {
    if (!hasPenetrationDepth())
        throw InputError("the " + name() +
                         " cure law has no penetration depth, so it gives no cure depth");
    return jacobsCureDepth(surfaceDose, criticalDose(), penetrationDepth());
}

KeyTable resinKeyTable() {
    return {{
        quantityKey("penetration_depth", dim::LENGTH, nullptr,
                    "Dp of the resin (optional; or attenuation = 1/Dp)")
            .positiveOnly(),
        quantityKey("attenuation", dim::INVERSE_LENGTH, nullptr, "1/Dp (optional)").positiveOnly(),
    }};
}

double readPenetrationDepth(const KeyReader& keys) {
    bool hasDepth = keys.has("penetration_depth"), hasAttenuation = keys.has("attenuation");
    if (hasDepth && hasAttenuation)
        throw keys.error("attenuation",
                         "give either penetration_depth or attenuation (= 1/Dp), not both");
    if (hasDepth) return *keys.optionalQuantity("penetration_depth");
    if (hasAttenuation) return 1.0 / *keys.optionalQuantity("attenuation");
    return 0.0;
}

std::unique_ptr<CureLaw> cureLawFromJson(const CureLawRegistry& registry,
                                         const nlohmann::json& section, const std::string& file,
                                         const std::string& keyPrefix) {
    if (!section.is_object())
        throw InputError(
            "the cure section must be a JSON object such as {\"model\": \"threshold\", ...}", file,
            keyPrefix);
    try {
        // A standalone node over the section, so checkUnknownKeys() covers exactly this section.
        ConfigNode node(section, file);
        std::unique_ptr<CureLaw> law =
            registry.create(node.choice("model", registry.names()), node);
        node.checkUnknownKeys();
        return law;
    } catch (const InputError& e) {
        if (keyPrefix.empty()) throw;
        std::string key = e.key().empty() ? keyPrefix : keyPrefix + "." + e.key();
        throw InputError(e.reason(), e.file().empty() ? file : e.file(), key, e.line());
    }
}

std::unique_ptr<CureLaw> cureLawFromConfig(const CureLawRegistry& registry,
                                           const ConfigNode& parent, const std::string& key) {
    // raw() marks the whole section as read for the parent's own unknown-key check.
    return cureLawFromJson(registry, parent.raw(key), parent.file(), parent.keyPath(key));
}

}  // namespace vpsim::cure
