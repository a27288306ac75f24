#pragma once
/// @file
/// A component's config keys declared once (name, kind, dimension, default, range, choices,
/// doc) and read through that declaration. Planners, cure laws and exporters each own one
/// KeyTable; their factory reads its section with a KeyReader over it, so the default and range
/// a job gets, the `vpsim plan --list` output, the job estimate and the key tables of
/// examples/README.md all come from the same lines.
///
/// A KeyReader only reads keys of its table (reading another one is a programming error,
/// std::logic_error) and remembers which keys it was asked about, so a test can check that the
/// documented keys are exactly the keys read. It marks every table key as accepted at its node,
/// so an unknown key in the section is reported with the component's name and the nearest
/// accepted key, whether or not the job file uses it.

#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/units.h"

namespace vpsim {

/// What a key holds.
enum class KeyKind {
    Quantity,  ///< a number in base units or a string with units (dimension below)
    Number,    ///< a plain number
    Integer,
    Boolean,
    Choice,  ///< one of `choices`
    String,  ///< free text, or a value with its own syntax (e.g. "mean" or a dose)
    Table,   ///< structured JSON (an array or object) read by the component itself
};

/// One key of a component's section.
struct KeySpec {
    std::string name;
    KeyKind kind = KeyKind::Number;
    Dimension dimension = dim::DIMENSIONLESS;  ///< for KeyKind::Quantity
    /// The value a job gets when the key is absent, as it would be written in a job file
    /// ("78 mJ/cm^2", 0.01, "auto", false); null when the key is optional without a default
    /// (the component then behaves as documented) or required.
    nlohmann::json fallback;
    bool required = false;
    /// Inclusive range in base units (quantities, numbers, integers).
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool positive = false;             ///< strictly > 0 (on top of lo..hi)
    std::vector<std::string> choices;  ///< for KeyKind::Choice
    std::string doc;                   ///< what it sets (without the default: that is `fallback`)
    /// A valid value for a required key (contract tests create components from it).
    nlohmann::json example;

    /// Copies with a range, strictly positive, or required (with an example value).
    KeySpec in(double low, double high) const;
    KeySpec positiveOnly() const;
    KeySpec requiredLike(nlohmann::json exampleValue) const;
    /// A valid value for an optional key that the defaults section should carry (one of two
    /// alternatives, such as fpp's K or critical_dose).
    KeySpec withExample(nlohmann::json exampleValue) const;
};

/// The kinds of key, each with its default as a job file would write it (null: none).
KeySpec quantityKey(std::string name, Dimension dimension, nlohmann::json fallback,
                    std::string doc);
KeySpec numberKey(std::string name, nlohmann::json fallback, std::string doc);
KeySpec integerKey(std::string name, nlohmann::json fallback, std::string doc);
KeySpec booleanKey(std::string name, bool fallback, std::string doc);
KeySpec choiceKey(std::string name, std::vector<std::string> choices, std::string fallback,
                  std::string doc);
KeySpec stringKey(std::string name, nlohmann::json fallback, std::string doc);
KeySpec tableKey(std::string name, std::string doc);

/// The keys of one component, in documentation order.
class KeyTable {
public:
    KeyTable() = default;
    KeyTable(std::vector<KeySpec> keys);  // NOLINT: a braced list of specs reads naturally
    /// Appends `other`'s keys (a laser planner = the shared laser keys + its own).
    KeyTable& add(const KeyTable& other);

    const std::vector<KeySpec>& keys() const { return mKeys; }
    bool has(const std::string& name) const;
    /// @throw std::logic_error when `name` is not in the table (a programming error)
    const KeySpec& spec(const std::string& name) const;
    std::vector<std::string> names() const;

    /// [{"name", "kind", "dimension", "unit", "default", "required", "range", "choices", "doc"}]
    nlohmann::json toJson() const;
    /// A Markdown table (| key | default | dimension | doc |) for examples/README.md.
    std::string markdown() const;
    /// A section with every key that has an example (the required ones) and nothing else: "the
    /// defaults" from which a component must be creatable.
    nlohmann::json defaultsSection() const;

private:
    std::vector<KeySpec> mKeys;
};

/// Reads one component's section through its KeyTable: dimension, default and range come from
/// the table. Every getter throws InputError naming the file and key path on a bad value.
class KeyReader {
public:
    /// @param component for messages, e.g. "planner 'aces'"
    KeyReader(const KeyTable& table, const ConfigNode& section, std::string component);

    bool has(const std::string& name) const;
    double quantity(const std::string& name) const;
    std::optional<double> optionalQuantity(const std::string& name) const;
    double number(const std::string& name) const;
    std::optional<double> optionalNumber(const std::string& name) const;
    long long integer(const std::string& name) const;
    bool boolean(const std::string& name) const;
    std::string choice(const std::string& name) const;
    std::string string(const std::string& name) const;
    /// The raw JSON of a Table key. @throw InputError when absent and required
    const nlohmann::json& raw(const std::string& name) const;

    const ConfigNode& node() const { return mNode; }
    InputError error(const std::string& name, const std::string& reason) const;
    /// Table keys the component asked about (has() or a getter), sorted.
    const std::set<std::string>& asked() const { return mAsked; }

private:
    const KeySpec& use(const std::string& name) const;
    double checkedRange(const KeySpec& spec, double value) const;

    const KeyTable& mTable;
    ConfigNode mNode;
    std::string mComponent;
    mutable std::set<std::string> mAsked;
};

}  // namespace vpsim
