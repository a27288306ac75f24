#include "vpsim/core/key_table.h"

#include <cmath>
#include <stdexcept>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim {
namespace {

const char* kindName(KeyKind kind) {
    switch (kind) {
        case KeyKind::Quantity: return "quantity";
        case KeyKind::Number: return "number";
        case KeyKind::Integer: return "integer";
        case KeyKind::Boolean: return "boolean";
        case KeyKind::Choice: return "choice";
        case KeyKind::String: return "string";
        case KeyKind::Table: return "table";
    }
    return "?";
}

/// "length (mm)", "number", "one of a | b" for the docs.
std::string dimensionText(const KeySpec& spec) {
    if (spec.kind == KeyKind::Quantity)
        return spec.dimension.describe() + " (" + spec.dimension.baseUnit() + ")";
    if (spec.kind == KeyKind::Choice) {
        std::string list;
        for (const auto& c : spec.choices) list += (list.empty() ? "" : " \\| ") + c;
        return "one of " + list;
    }
    return kindName(spec.kind);
}

std::string defaultText(const KeySpec& spec) {
    if (spec.required) return "required";
    if (spec.fallback.is_null()) return "none";
    if (spec.fallback.is_string()) return "`\"" + spec.fallback.get<std::string>() + "\"`";
    return "`" + spec.fallback.dump() + "`";
}

std::string rangeText(const KeySpec& spec) {
    std::string text;
    if (spec.positive) text = "> 0";
    if (std::isfinite(spec.lo) || std::isfinite(spec.hi)) {
        text += (text.empty() ? "" : ", ") + std::string("[") +
                (std::isfinite(spec.lo) ? formatNumber(spec.lo) : "-inf") + ", " +
                (std::isfinite(spec.hi) ? formatNumber(spec.hi) : "inf") + "]";
    }
    return text;
}

}  // namespace

KeySpec KeySpec::in(double low, double high) const {
    KeySpec k = *this;
    k.lo = low, k.hi = high;
    return k;
}

KeySpec KeySpec::positiveOnly() const {
    KeySpec k = *this;
    k.positive = true;
    return k;
}

KeySpec KeySpec::requiredLike(nlohmann::json exampleValue) const {
    KeySpec k = *this;
    k.required = true;
    k.fallback = nullptr;
    k.example = std::move(exampleValue);
    return k;
}

KeySpec KeySpec::withExample(nlohmann::json exampleValue) const {
    KeySpec k = *this;
    k.example = std::move(exampleValue);
    return k;
}

namespace {

KeySpec makeKey(std::string name, KeyKind kind, nlohmann::json fallback, std::string doc) {
    KeySpec k;
    k.name = std::move(name);
    k.kind = kind;
    k.fallback = std::move(fallback);
    k.doc = std::move(doc);
    return k;
}

}  // namespace

KeySpec quantityKey(std::string name, Dimension dimension, nlohmann::json fallback,
                    std::string doc) {
    KeySpec k = makeKey(std::move(name), KeyKind::Quantity, std::move(fallback), std::move(doc));
    k.dimension = dimension;
    return k;
}

KeySpec numberKey(std::string name, nlohmann::json fallback, std::string doc) {
    return makeKey(std::move(name), KeyKind::Number, std::move(fallback), std::move(doc));
}

KeySpec integerKey(std::string name, nlohmann::json fallback, std::string doc) {
    return makeKey(std::move(name), KeyKind::Integer, std::move(fallback), std::move(doc));
}

KeySpec booleanKey(std::string name, bool fallback, std::string doc) {
    return makeKey(std::move(name), KeyKind::Boolean, fallback, std::move(doc));
}

KeySpec choiceKey(std::string name, std::vector<std::string> choices, std::string fallback,
                  std::string doc) {
    KeySpec k = makeKey(std::move(name), KeyKind::Choice, std::move(fallback), std::move(doc));
    k.choices = std::move(choices);
    return k;
}

KeySpec stringKey(std::string name, nlohmann::json fallback, std::string doc) {
    return makeKey(std::move(name), KeyKind::String, std::move(fallback), std::move(doc));
}

KeySpec tableKey(std::string name, std::string doc) {
    return makeKey(std::move(name), KeyKind::Table, nullptr, std::move(doc));
}

KeyTable::KeyTable(std::vector<KeySpec> keys) : mKeys(std::move(keys)) {
    for (size_t i = 0; i < mKeys.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (mKeys[i].name == mKeys[j].name)
                throw std::logic_error("key '" + mKeys[i].name + "' declared twice");
}

KeyTable& KeyTable::add(const KeyTable& other) {
    for (const KeySpec& key : other.mKeys) {
        if (has(key.name)) throw std::logic_error("key '" + key.name + "' declared twice");
        mKeys.push_back(key);
    }
    return *this;
}

bool KeyTable::has(const std::string& name) const {
    for (const KeySpec& key : mKeys)
        if (key.name == name) return true;
    return false;
}

const KeySpec& KeyTable::spec(const std::string& name) const {
    for (const KeySpec& key : mKeys)
        if (key.name == name) return key;
    throw std::logic_error("key '" + name + "' is read but not declared in the component's table");
}

std::vector<std::string> KeyTable::names() const {
    std::vector<std::string> out;
    for (const KeySpec& key : mKeys) out.push_back(key.name);
    return out;
}

nlohmann::json KeyTable::toJson() const {
    nlohmann::json out = nlohmann::json::array();
    for (const KeySpec& key : mKeys) {
        nlohmann::json item{{"name", key.name},
                            {"kind", kindName(key.kind)},
                            {"default", key.fallback},
                            {"required", key.required},
                            {"doc", key.doc}};
        item["dimension"] = key.kind == KeyKind::Quantity ? key.dimension.describe() : "";
        if (key.kind == KeyKind::Quantity) item["unit"] = key.dimension.baseUnit();
        const std::string range = rangeText(key);
        if (!range.empty()) item["range"] = range;
        if (!key.choices.empty()) item["choices"] = key.choices;
        if (!key.example.is_null()) item["example"] = key.example;
        out.push_back(std::move(item));
    }
    return out;
}

namespace {

/// Text inside a Markdown table cell: a bare '|' would end the cell.
std::string cellText(const std::string& text) {
    std::string out;
    for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
}

}  // namespace

std::string KeyTable::markdown() const {
    std::string out = "| key | default | kind | range | what it sets |\n|---|---|---|---|---|\n";
    for (const KeySpec& key : mKeys)
        out += "| `" + key.name + "` | " + defaultText(key) + " | " + dimensionText(key) + " | " +
               rangeText(key) + " | " + cellText(key.doc) + " |\n";
    return out;
}

nlohmann::json KeyTable::defaultsSection() const {
    nlohmann::json out = nlohmann::json::object();
    for (const KeySpec& key : mKeys)
        if (!key.example.is_null()) out[key.name] = key.example;
    return out;
}

KeyReader::KeyReader(const KeyTable& table, const ConfigNode& section, std::string component)
    : mTable(table), mNode(section), mComponent(std::move(component)) {
    for (const KeySpec& key : table.keys()) mNode.accept(key.name);
    mNode.setOwner(mComponent);
}

const KeySpec& KeyReader::use(const std::string& name) const {
    const KeySpec& spec = mTable.spec(name);
    mAsked.insert(name);
    return spec;
}

InputError KeyReader::error(const std::string& name, const std::string& reason) const {
    return mNode.error(name, reason);
}

double KeyReader::checkedRange(const KeySpec& spec, double value) const {
    if (spec.positive && !(value > 0.0))
        throw error(spec.name, "must be positive, got " + formatNumber(value));
    if (!std::isfinite(value)) throw error(spec.name, "must be finite");
    if (value < spec.lo || value > spec.hi)
        throw error(spec.name, "value " + formatNumber(value) + " is outside the allowed range " +
                                   rangeText(spec));
    return value;
}

bool KeyReader::has(const std::string& name) const {
    use(name);
    return mNode.has(name);
}

std::optional<double> KeyReader::optionalQuantity(const std::string& name) const {
    const KeySpec& spec = use(name);
    if (mNode.has(name)) return checkedRange(spec, mNode.quantity(name, spec.dimension));
    if (spec.fallback.is_null()) {
        if (spec.required) mNode.quantity(name, spec.dimension);  // throws "missing"
        return std::nullopt;
    }
    return checkedRange(
        spec, quantityFromJson(spec.fallback, spec.dimension, mNode.keyPath(name), mNode.file()));
}

double KeyReader::quantity(const std::string& name) const {
    std::optional<double> value = optionalQuantity(name);
    if (!value) throw std::logic_error("key '" + name + "' has no default: use optionalQuantity");
    return *value;
}

std::optional<double> KeyReader::optionalNumber(const std::string& name) const {
    const KeySpec& spec = use(name);
    if (mNode.has(name)) return checkedRange(spec, mNode.number(name));
    if (spec.fallback.is_null()) {
        if (spec.required) mNode.number(name);  // throws "missing"
        return std::nullopt;
    }
    return checkedRange(spec, spec.fallback.get<double>());
}

double KeyReader::number(const std::string& name) const {
    std::optional<double> value = optionalNumber(name);
    if (!value) throw std::logic_error("key '" + name + "' has no default: use optionalNumber");
    return *value;
}

long long KeyReader::integer(const std::string& name) const {
    const KeySpec& spec = use(name);
    std::optional<long long> fallback;
    if (!spec.fallback.is_null()) fallback = spec.fallback.get<long long>();
    const long long value = mNode.integer(name, fallback);
    checkedRange(spec, double(value));
    return value;
}

bool KeyReader::boolean(const std::string& name) const {
    const KeySpec& spec = use(name);
    std::optional<bool> fallback;
    if (!spec.fallback.is_null()) fallback = spec.fallback.get<bool>();
    return mNode.boolean(name, fallback);
}

std::string KeyReader::choice(const std::string& name) const {
    const KeySpec& spec = use(name);
    std::optional<std::string> fallback;
    if (!spec.fallback.is_null()) fallback = spec.fallback.get<std::string>();
    return mNode.choice(name, spec.choices, fallback);
}

std::string KeyReader::string(const std::string& name) const {
    const KeySpec& spec = use(name);
    std::optional<std::string> fallback;
    if (!spec.fallback.is_null()) fallback = spec.fallback.get<std::string>();
    return mNode.string(name, fallback);
}

const nlohmann::json& KeyReader::raw(const std::string& name) const {
    use(name);
    return mNode.raw(name);
}

}  // namespace vpsim
