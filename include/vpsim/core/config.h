#pragma once
/// @file
/// JSON configuration (jobs, materials, machines) with unit-aware getters, unknown-key errors
/// and `--set key.path=value` overrides.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/units.h"

namespace vpsim {

/// Limits on every JSON document vpsim reads (jobs, materials, plans, --set values): beyond them
/// a document is refused with the file and key, never parsed into a crash or a silent overflow.
constexpr int MAX_JSON_DEPTH = 64;                           ///< nesting of objects and arrays
constexpr size_t MAX_JSON_STRING = 4096;                     ///< characters in a string value
constexpr size_t MAX_JSON_KEY = 256;                         ///< characters in a key
constexpr double MAX_JSON_NUMBER = 1e18;                     ///< magnitude of any number
constexpr uint64_t MAX_JSON_FILE_BYTES = uint64_t(1) << 30;  ///< 1 GiB (plans with DLP masks)

/// Parses JSON text from `source` (a file name, used in messages) under the limits above;
/// duplicate keys are errors. @throw InputError naming the source, line or key and the reason.
nlohmann::json parseJsonText(const std::string& text, const std::string& source);

/// Reads a JSON file with parseJsonText. @throw InputError naming the file and line on a missing
/// file, a syntax error or a broken limit.
nlohmann::json loadJsonFile(const std::string& path);

/// Applies "a.b.c=value" to a document: the value is parsed as JSON when it is valid JSON
/// (numbers, true, arrays...), otherwise taken as a string ("50 um"). Creates missing objects.
/// @throw InputError when the assignment has no '=' or walks through a non-object.
void applyOverride(nlohmann::json& document, const std::string& assignment);

/// The key of `candidates` nearest to `key` by edit distance, or "" when none is close (more
/// than a third of the longer name differs).
std::string nearestKey(const std::string& key, const std::vector<std::string>& candidates);

/// A view of one JSON object in a config document. Getters record which keys were read;
/// checkUnknownKeys() on the root then reports the first key nobody read, so typos are errors.
class ConfigNode {
public:
    /// Root node of a document loaded from `file` ("" for documents built in code).
    ConfigNode(nlohmann::json document, std::string file);
    static ConfigNode load(const std::string& path, const std::vector<std::string>& overrides = {});

    bool has(const std::string& key) const;
    /// Quantity in base units (see units.h). @throw InputError when missing or of wrong dimension.
    double quantity(const std::string& key, Dimension dimension) const;
    double quantity(const std::string& key, Dimension dimension, double fallback) const;
    /// Plain number, optionally range-checked (inclusive). @throw InputError on type or range.
    double number(const std::string& key) const;
    double number(const std::string& key, double fallback) const;
    double numberInRange(const std::string& key, double lo, double hi,
                         std::optional<double> fallback = std::nullopt) const;
    long long integer(const std::string& key,
                      std::optional<long long> fallback = std::nullopt) const;
    bool boolean(const std::string& key, std::optional<bool> fallback = std::nullopt) const;
    std::string string(const std::string& key,
                       std::optional<std::string> fallback = std::nullopt) const;
    /// A string that must be one of `choices`. @throw InputError listing the choices otherwise.
    std::string choice(const std::string& key, const std::vector<std::string>& choices,
                       std::optional<std::string> fallback = std::nullopt) const;
    /// A nested object. @throw InputError when missing or not an object.
    ConfigNode child(const std::string& key) const;
    /// Elements of an array of objects.
    std::vector<ConfigNode> children(const std::string& key) const;
    /// The raw JSON value (marks the whole subtree as known). @throw InputError when missing.
    const nlohmann::json& raw(const std::string& key) const;
    /// This node's JSON value as read (overrides applied), without marking anything read.
    const nlohmann::json& json() const { return *mNode; }
    /// The keys of this object node (none for other kinds), without marking them read.
    std::vector<std::string> keys() const;

    /// @throw InputError "unknown key 'x'" for the first key in the whole document never read,
    /// naming the component that owns its section and the nearest key accepted there.
    void checkUnknownKeys() const;

    /// Records `key` as accepted at this node without reading it: unknown-key messages suggest
    /// the nearest accepted key (every key a getter or has() was asked about is accepted too).
    void accept(const std::string& key) const;
    /// Names the component that owns this node ("planner 'aces'") in unknown-key messages.
    void setOwner(const std::string& owner) const;

    const std::string& file() const { return mState->file; }
    /// Dotted path of this node ("" for the root), used in messages.
    const std::string& path() const { return mPath; }
    /// Full dotted path of a key of this node.
    std::string keyPath(const std::string& key) const;
    /// Builds an InputError naming this file and the key.
    InputError error(const std::string& key, const std::string& reason) const;

private:
    struct State {
        nlohmann::json document;
        std::string file;
        std::set<std::string> readPaths;  ///< keys read; a subtree read whole ends with "/*"
        std::map<std::string, std::set<std::string>> accepted;  ///< node path -> keys asked
        std::map<std::string, std::string> owners;              ///< node path -> component
    };
    ConfigNode(std::shared_ptr<State> state, const nlohmann::json* node, std::string path);
    const nlohmann::json& require(const std::string& key) const;
    const nlohmann::json* find(const std::string& key) const;
    void markRead(const std::string& key, bool wholeSubtree = false) const;
    void checkNode(const nlohmann::json& node, const std::string& path) const;
    InputError unknownKey(const std::string& path, const std::string& key) const;

    std::shared_ptr<State> mState;
    const nlohmann::json* mNode;
    std::string mPath;
};

}  // namespace vpsim
