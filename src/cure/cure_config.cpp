// Loading a CureModel from a material/resin config section (see cure_model.h for the keys).
#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"

namespace vpsim::cure {
namespace {

/// Penetration depth from "penetration_depth" (mm) or "attenuation" (1/mm, = 1/Dp); 0 if neither.
double readPenetrationDepth(const ConfigNode& node) {
    bool hasDepth = node.has("penetration_depth"), hasAttenuation = node.has("attenuation");
    if (hasDepth && hasAttenuation)
        throw node.error("attenuation",
                         "give either penetration_depth or attenuation (= 1/Dp), not both");
    if (hasDepth) {
        double depth = node.quantity("penetration_depth", dim::LENGTH);
        if (!(depth > 0.0) || !std::isfinite(depth))
            throw node.error("penetration_depth", "must be positive");
        return depth;
    }
    if (hasAttenuation) {
        double mu = node.quantity("attenuation", dim::INVERSE_LENGTH);
        if (!(mu > 0.0) || !std::isfinite(mu)) throw node.error("attenuation", "must be positive");
        return 1.0 / mu;
    }
    return 0.0;
}

double readPositiveQuantity(const ConfigNode& node, const std::string& key, Dimension dimension) {
    double value = node.quantity(key, dimension);
    if (!(value > 0.0) || !std::isfinite(value)) throw node.error(key, "must be positive");
    return value;
}

CureModel readSection(const ConfigNode& node) {
    std::string model = node.choice("model", {"threshold", "fpp"});
    double penetrationDepth = readPenetrationDepth(node);
    if (model == "threshold") {
        double criticalDose = readPositiveQuantity(node, "critical_dose", dim::DOSE);
        return CureModel::threshold(criticalDose, penetrationDepth);
    }
    double gelPoint = node.number("gel_point");
    if (!(gelPoint > 0.0 && gelPoint < 1.0))
        throw node.error("gel_point", "the gel point Phi_c must lie strictly between 0 and 1");
    bool hasK = node.has("K"), hasEc = node.has("critical_dose");
    if (hasK == hasEc)
        throw node.error(
            "K", "the fpp model needs exactly one of K (e.g. \"0.0053 cm^2/mJ\") or critical_dose");
    double rateConstant =
        hasK ? readPositiveQuantity(node, "K", dim::INVERSE_DOSE)
             : fppRateConstantFromCriticalDose(
                   readPositiveQuantity(node, "critical_dose", dim::DOSE), gelPoint);
    return CureModel::fpp(rateConstant, gelPoint, penetrationDepth);
}

}  // namespace

CureModel cureModelFromJson(const nlohmann::json& section, const std::string& file,
                            const std::string& keyPrefix) {
    if (!section.is_object())
        throw InputError(
            "the cure section must be a JSON object such as {\"model\": \"threshold\", ...}", file,
            keyPrefix);
    try {
        // A standalone node over the section, so checkUnknownKeys() covers exactly this section.
        ConfigNode node(section, file);
        CureModel model = readSection(node);
        node.checkUnknownKeys();
        return model;
    } catch (const InputError& e) {
        if (keyPrefix.empty()) throw;
        std::string key = e.key().empty() ? keyPrefix : keyPrefix + "." + e.key();
        throw InputError(e.reason(), e.file().empty() ? file : e.file(), key, e.line());
    }
}

CureModel cureModelFromConfig(const ConfigNode& parent, const std::string& key) {
    // raw() marks the whole section as read for the parent's own unknown-key check.
    return cureModelFromJson(parent.raw(key), parent.file(), parent.keyPath(key));
}

}  // namespace vpsim::cure
