// Material files: slurry form (Mie-derived optics) and plain bulk-optics form.

#include <cmath>
#include <sstream>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/optics/material_file.h"

namespace vpsim::optics {
namespace {

constexpr double MAX_VOLUME_FRACTION = 0.74;

double positiveQuantity(const ConfigNode& node, const std::string& key, Dimension dimension) {
    double v = node.quantity(key, dimension);
    if (!(v > 0.0))
        throw node.error(key,
                         "must be positive, got " + formatNumber(v) + " " + dimension.baseUnit());
    return v;
}

double positiveNumber(const ConfigNode& node, const std::string& key) {
    double v = node.number(key);
    if (!(v > 0.0)) throw node.error(key, "must be positive, got " + formatNumber(v));
    return v;
}

Complex particleIndex(const ConfigNode& node, const std::string& key) {
    const nlohmann::json& value = node.raw(key);
    Complex m;
    if (value.is_number()) {
        m = {value.get<double>(), 0.0};
    } else if (value.is_string()) {
        try {
            m = parseRefractiveIndex(value.get<std::string>());
        } catch (const InputError& e) {
            throw node.error(key, e.reason());
        }
    } else {
        throw node.error(
            key, "expected a number or a string such as \"1.75-0.001i\", got " + value.dump());
    }
    if (!(m.real() > 0.0) || !std::isfinite(m.real()))
        throw node.error(key, "must have a positive real part, got " + formatRefractiveIndex(m));
    return m;
}

SizeDistribution sizeDistribution(const ConfigNode& particles) {
    SizeDistribution size;
    if (!particles.has("size_distribution")) return size;
    ConfigNode d = particles.child("size_distribution");
    std::string type = d.choice("type", {"monodisperse", "lognormal"});
    if (type == "monodisperse") return size;
    size.kind = SizeDistribution::Kind::LogNormal;
    size.sigmaG = d.number("sigma_g");
    if (!(size.sigmaG >= 1.0 && size.sigmaG <= 5.0))
        throw d.error("sigma_g", "geometric standard deviation must be in [1, 5], got " +
                                     formatNumber(size.sigmaG));
    long long points = d.integer("points", 96);
    if (points < 8 || points > 4096)
        throw d.error("points", "must be in [8, 4096], got " + std::to_string(points));
    size.points = static_cast<int>(points);
    return size;
}

SlurrySpec readSlurry(const ConfigNode& root) {
    SlurrySpec s;
    s.wavelength = positiveQuantity(root, "wavelength", dim::LENGTH);
    ConfigNode resin = root.child("resin");
    s.resinIndex = positiveNumber(resin, "refractive_index");
    s.resinPenetrationDepth = positiveQuantity(resin, "penetration_depth", dim::LENGTH);
    s.absorptionScaledByResinFraction = resin.choice("absorption", {"pure_resin", "resin_fraction"},
                                                     std::string("pure_resin")) == "resin_fraction";
    ConfigNode particles = root.child("particles");
    s.particleIndex = particleIndex(particles, "refractive_index");
    s.radius = positiveQuantity(particles, "radius", dim::LENGTH);
    s.volumeFraction = particles.number("volume_fraction");
    if (!(s.volumeFraction > 0.0 && s.volumeFraction < MAX_VOLUME_FRACTION))
        throw particles.error("volume_fraction",
                              "must be in (0, 0.74) (0.74 is the densest packing "
                              "of spheres), got " +
                                  formatNumber(s.volumeFraction));
    s.size = sizeDistribution(particles);
    long long table = root.integer("phase_table_size", DEFAULT_PHASE_TABLE_SIZE);
    if (table < 16 || table > (1 << 22))
        throw root.error("phase_table_size",
                         "must be in [16, 4194304], got " + std::to_string(table));
    s.phaseTableSize = static_cast<int>(table);
    try {
        validateSlurrySpec(s);
    } catch (const InputError& e) {
        throw root.error("particles", e.reason());
    }
    return s;
}

MediumOptics readPlainOptics(const ConfigNode& root) {
    ConfigNode o = root.child("optics");
    MediumOptics m;
    m.mua = o.quantity("mua", dim::INVERSE_LENGTH);
    if (!(m.mua >= 0.0))
        throw o.error("mua", "must not be negative, got " + formatNumber(m.mua) + " 1/mm");
    m.mus = o.quantity("mus", dim::INVERSE_LENGTH);
    if (!(m.mus >= 0.0))
        throw o.error("mus", "must not be negative, got " + formatNumber(m.mus) + " 1/mm");
    if (!(m.mua + m.mus > 0.0))
        throw o.error("mus", "mua + mus must be positive (an empty medium)");
    m.g = o.number("g", 0.0);
    if (!(std::fabs(m.g) < 1.0)) throw o.error("g", "must be in (-1, 1), got " + formatNumber(m.g));
    o.choice("phase", {"hg"}, std::string("hg"));
    m.phase = PhaseModel::HenyeyGreenstein;
    m.refractiveIndex = o.number("refractive_index", 1.0);
    if (!(m.refractiveIndex > 0.0))
        throw o.error("refractive_index",
                      "must be positive, got " + formatNumber(m.refractiveIndex));
    m.wavelength = o.quantity("wavelength", dim::LENGTH, 0.0);
    if (m.wavelength < 0.0) throw o.error("wavelength", "must not be negative");
    return m;
}

}  // namespace

MaterialDefinition loadMaterialDefinition(const std::string& path,
                                          const std::vector<std::string>& overrides) {
    ConfigNode root = ConfigNode::load(path, overrides);
    MaterialDefinition material;
    material.file = path;
    material.name = root.string("name", std::string());
    root.string("description", std::string());
    const bool plain = root.has("optics");
    const bool slurry = root.has("wavelength") || root.has("resin") || root.has("particles");
    if (plain && slurry)
        throw root.error("optics",
                         "a material file gives either bulk 'optics' or a slurry "
                         "('wavelength', 'resin', 'particles'), not both");
    if (!plain && !slurry)
        throw InputError(
            "not a material file: expected 'optics' (bulk mua/mus/g) or 'wavelength', "
            "'resin' and 'particles' (slurry)",
            path);
    material.isSlurry = slurry;
    if (slurry)
        material.slurry = readSlurry(root);
    else
        material.optics = readPlainOptics(root);
    root.checkUnknownKeys();
    return material;
}

SlurryOptics computeSlurryOptics(const MaterialDefinition& material) {
    if (!material.isSlurry)
        throw InputError("not a slurry material (it gives bulk optics directly, no Mie parameters)",
                         material.file);
    try {
        return computeSlurryOptics(material.slurry);
    } catch (const InputError& e) {
        throw InputError(e.reason(), material.file, e.key());
    }
}

MediumOptics loadMediumOptics(const std::string& path, const std::vector<std::string>& overrides) {
    MaterialDefinition material = loadMaterialDefinition(path, overrides);
    if (!material.isSlurry) return material.optics;
    return computeSlurryOptics(material).medium;
}

}  // namespace vpsim::optics
