#include "vpsim/core/config.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim {
namespace {

int lineOfByte(const std::string& text, size_t byte) {
    int line = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i)
        if (text[i] == '\n') ++line;
    return line;
}

std::string joinPath(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
}

}  // namespace

nlohmann::json loadJsonFile(const std::string& path) {
    std::string text = readFile(path);
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        std::string reason = e.what();
        size_t colon = reason.find("]");
        reason =
            "malformed JSON: " + (colon == std::string::npos ? reason : reason.substr(colon + 2));
        throw InputError(reason, path, "", lineOfByte(text, e.byte > 0 ? e.byte - 1 : 0));
    }
}

void applyOverride(nlohmann::json& document, const std::string& assignment) {
    size_t equals = assignment.find('=');
    if (equals == std::string::npos || equals == 0)
        throw InputError("--set expects key.path=value, got '" + assignment + "'");
    std::string path = assignment.substr(0, equals);
    std::string valueText = assignment.substr(equals + 1);
    nlohmann::json value;
    try {
        value = nlohmann::json::parse(valueText);
    } catch (const nlohmann::json::parse_error&) {
        value = valueText;
    }
    nlohmann::json* node = &document;
    size_t start = 0;
    while (true) {
        size_t dot = path.find('.', start);
        std::string key =
            path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        if (key.empty()) throw InputError("--set: empty key in '" + path + "'");
        if (node->is_null()) *node = nlohmann::json::object();
        if (!node->is_object())
            throw InputError("--set: '" + path.substr(0, start ? start - 1 : 0) +
                             "' is not an object");
        if (dot == std::string::npos) {
            (*node)[key] = value;
            return;
        }
        node = &(*node)[key];
        start = dot + 1;
    }
}

ConfigNode::ConfigNode(nlohmann::json document, std::string file)
    : mState(std::make_shared<State>()), mNode(nullptr) {
    mState->document = std::move(document);
    mState->file = std::move(file);
    mNode = &mState->document;
    if (!mNode->is_object())
        throw InputError("expected a JSON object at the top level", mState->file);
}

ConfigNode::ConfigNode(std::shared_ptr<State> state, const nlohmann::json* node, std::string path)
    : mState(std::move(state)), mNode(node), mPath(std::move(path)) {}

ConfigNode ConfigNode::load(const std::string& path, const std::vector<std::string>& overrides) {
    nlohmann::json document = loadJsonFile(path);
    for (const auto& assignment : overrides) applyOverride(document, assignment);
    return ConfigNode(std::move(document), path);
}

std::string ConfigNode::keyPath(const std::string& key) const {
    return joinPath(mPath, key);
}

InputError ConfigNode::error(const std::string& key, const std::string& reason) const {
    return InputError(reason, mState->file, keyPath(key));
}

const nlohmann::json* ConfigNode::find(const std::string& key) const {
    auto it = mNode->find(key);
    return it == mNode->end() ? nullptr : &*it;
}

const nlohmann::json& ConfigNode::require(const std::string& key) const {
    const nlohmann::json* value = find(key);
    if (!value) throw error(key, "missing required key");
    markRead(key);
    return *value;
}

void ConfigNode::markRead(const std::string& key, bool wholeSubtree) const {
    mState->readPaths.insert(keyPath(key));
    if (wholeSubtree) mState->readPaths.insert(keyPath(key) + "/*");
}

bool ConfigNode::has(const std::string& key) const {
    return find(key) != nullptr;
}

double ConfigNode::quantity(const std::string& key, Dimension dimension) const {
    return quantityFromJson(require(key), dimension, keyPath(key), mState->file);
}

double ConfigNode::quantity(const std::string& key, Dimension dimension, double fallback) const {
    return has(key) ? quantity(key, dimension) : fallback;
}

double ConfigNode::number(const std::string& key) const {
    const nlohmann::json& value = require(key);
    if (!value.is_number())
        throw error(key, std::string("expected a number, got ") + value.type_name());
    double number = value.get<double>();
    if (!std::isfinite(number)) throw error(key, "value is not finite");
    return number;
}

double ConfigNode::number(const std::string& key, double fallback) const {
    return has(key) ? number(key) : fallback;
}

double ConfigNode::numberInRange(const std::string& key, double lo, double hi,
                                 std::optional<double> fallback) const {
    if (!has(key) && fallback) return *fallback;
    double value = number(key);
    if (value < lo || value > hi) {
        std::ostringstream reason;
        reason << "value " << value << " is outside the allowed range [" << lo << ", " << hi << "]";
        throw error(key, reason.str());
    }
    return value;
}

long long ConfigNode::integer(const std::string& key, std::optional<long long> fallback) const {
    if (!has(key) && fallback) return *fallback;
    const nlohmann::json& value = require(key);
    if (!value.is_number_integer())
        throw error(key, std::string("expected an integer, got ") + value.dump());
    return value.get<long long>();
}

bool ConfigNode::boolean(const std::string& key, std::optional<bool> fallback) const {
    if (!has(key) && fallback) return *fallback;
    const nlohmann::json& value = require(key);
    if (!value.is_boolean()) throw error(key, "expected true or false, got " + value.dump());
    return value.get<bool>();
}

std::string ConfigNode::string(const std::string& key, std::optional<std::string> fallback) const {
    if (!has(key) && fallback) return *fallback;
    const nlohmann::json& value = require(key);
    if (!value.is_string()) throw error(key, "expected a string, got " + value.dump());
    return value.get<std::string>();
}

std::string ConfigNode::choice(const std::string& key, const std::vector<std::string>& choices,
                               std::optional<std::string> fallback) const {
    std::string value = string(key, fallback);
    for (const auto& c : choices)
        if (c == value) return value;
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    throw error(key, "'" + value + "' is not one of: " + list);
}

ConfigNode ConfigNode::child(const std::string& key) const {
    const nlohmann::json& value = require(key);
    if (!value.is_object())
        throw error(key, std::string("expected an object, got ") + value.type_name());
    return ConfigNode(mState, &value, keyPath(key));
}

std::vector<ConfigNode> ConfigNode::children(const std::string& key) const {
    const nlohmann::json& value = require(key);
    if (!value.is_array())
        throw error(key, std::string("expected an array, got ") + value.type_name());
    std::vector<ConfigNode> nodes;
    for (size_t i = 0; i < value.size(); ++i) {
        std::string path = keyPath(key) + "[" + std::to_string(i) + "]";
        if (!value[i].is_object()) throw InputError("expected an object", mState->file, path);
        mState->readPaths.insert(path);
        nodes.push_back(ConfigNode(mState, &value[i], path));
    }
    return nodes;
}

std::vector<std::string> ConfigNode::keys() const {
    std::vector<std::string> out;
    if (mNode->is_object())
        for (const auto& item : mNode->items()) out.push_back(item.key());
    return out;
}

const nlohmann::json& ConfigNode::raw(const std::string& key) const {
    const nlohmann::json& value = require(key);
    markRead(key, true);
    return value;
}

void ConfigNode::checkUnknownKeys() const {
    checkNode(*mNode, mPath);
}

void ConfigNode::checkNode(const nlohmann::json& node, const std::string& path) const {
    if (mState->readPaths.count(path + "/*")) return;
    if (node.is_object()) {
        for (auto it = node.begin(); it != node.end(); ++it) {
            std::string childPath = joinPath(path, it.key());
            if (!mState->readPaths.count(childPath)) {
                std::string known;
                for (auto k = node.begin(); k != node.end(); ++k)
                    if (mState->readPaths.count(joinPath(path, k.key())))
                        known += (known.empty() ? "" : ", ") + k.key();
                throw InputError(
                    "unknown key" + (known.empty() ? "" : " (keys used here: " + known + ")"),
                    mState->file, childPath);
            }
            checkNode(it.value(), childPath);
        }
    } else if (node.is_array()) {
        for (size_t i = 0; i < node.size(); ++i)
            if (node[i].is_object()) checkNode(node[i], path + "[" + std::to_string(i) + "]");
    }
}

}  // namespace vpsim
