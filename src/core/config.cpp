#include "vpsim/core/config.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"

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

/// A JSON value for a message: scalars as written (escaped, cut), containers by their type.
std::string describeValue(const nlohmann::json& value) {
    if (value.is_structured()) return std::string("an ") + value.type_name();
    if (value.is_string()) return quoteUser(value.get_ref<const std::string&>());
    return escaped(value.dump());
}

/// Refuses documents nested deeper than MAX_JSON_DEPTH before parsing: a job nested 1e5 levels
/// deep would otherwise overflow the stack in the recursive code that walks it.
void checkNestingDepth(const std::string& text, const std::string& file) {
    int depth = 0;
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '{' || c == '[') {
            if (++depth > MAX_JSON_DEPTH)
                throw InputError(
                    "JSON nested more than " + std::to_string(MAX_JSON_DEPTH) + " levels deep",
                    file, "", lineOfByte(text, i));
        } else if (c == '}' || c == ']') {
            --depth;
        }
    }
}

/// Parser callback that follows the key path and refuses, while parsing, what JSON allows but a
/// config must not have: duplicate keys (JSON keeps the last silently), huge strings or keys, and
/// numbers beyond MAX_JSON_NUMBER.
class JsonChecker {
public:
    explicit JsonChecker(std::string file) : mFile(std::move(file)) {}

    nlohmann::json::parser_callback_t callback() {
        return [this](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
            handle(event, parsed);
            return true;
        };
    }
    /// Dotted path of the value being parsed ("" at the top level).
    std::string currentPath() const {
        std::string path;
        for (const Frame& frame : mFrames) {
            if (frame.array) {
                if (frame.index >= 0) path += "[" + std::to_string(frame.index) + "]";
            } else if (!frame.key.empty()) {
                path = joinPath(path, frame.key);
            }
        }
        return path;
    }

private:
    struct Frame {
        bool array = false;
        long long index = -1;
        std::string key;
        std::set<std::string> keys;
    };
    using Event = nlohmann::json::parse_event_t;

    void handle(Event event, const nlohmann::json& parsed) {
        switch (event) {
            case Event::object_start:
            case Event::array_start:
                nextElement();
                mFrames.push_back(Frame{event == Event::array_start, -1, {}, {}});
                break;
            case Event::object_end:
            case Event::array_end:
                if (!mFrames.empty()) mFrames.pop_back();
                break;
            case Event::key: onKey(parsed.get<std::string>()); break;
            case Event::value:
                nextElement();
                checkValue(parsed);
                break;
        }
    }
    void nextElement() {
        if (!mFrames.empty() && mFrames.back().array) ++mFrames.back().index;
    }
    void onKey(const std::string& key) {
        if (key.size() > MAX_JSON_KEY)
            throw InputError("key longer than " + std::to_string(MAX_JSON_KEY) +
                                 " characters: " + quoteUser(key),
                             mFile, currentPath());
        if (mFrames.empty()) return;
        Frame& frame = mFrames.back();
        frame.key = key;
        if (!frame.keys.insert(key).second)
            throw InputError("duplicate key (JSON would silently keep the last)", mFile,
                             currentPath());
    }
    void checkValue(const nlohmann::json& value) const {
        if (value.is_string() && value.get_ref<const std::string&>().size() > MAX_JSON_STRING)
            throw InputError("string of " +
                                 std::to_string(value.get_ref<const std::string&>().size()) +
                                 " characters is longer than the " +
                                 std::to_string(MAX_JSON_STRING) + " accepted",
                             mFile, currentPath());
        if (value.is_number() && !(std::fabs(value.get<double>()) <= MAX_JSON_NUMBER))
            throw InputError("number " + formatNumber(value.get<double>()) +
                                 " out of range (beyond +-" + formatNumber(MAX_JSON_NUMBER) + ")",
                             mFile, currentPath());
    }

    std::string mFile;
    std::vector<Frame> mFrames;
};

}  // namespace

nlohmann::json parseJsonText(const std::string& text, const std::string& file) {
    checkNestingDepth(text, file);
    JsonChecker checker(file);
    try {
        return nlohmann::json::parse(text, checker.callback());
    } catch (const nlohmann::json::parse_error& e) {
        std::string reason = e.what();
        size_t colon = reason.find("]");
        reason =
            "malformed JSON: " + (colon == std::string::npos ? reason : reason.substr(colon + 2));
        throw InputError(reason, file, "", lineOfByte(text, e.byte > 0 ? e.byte - 1 : 0));
    } catch (const nlohmann::json::out_of_range&) {
        // The lexer read a number beyond double (1e400); the checker knows which key it was.
        throw InputError("number out of range (beyond +-" + formatNumber(MAX_JSON_NUMBER) + ")",
                         file, checker.currentPath());
    }
}

nlohmann::json loadJsonFile(const std::string& path) {
    return parseJsonText(readFile(path, MAX_JSON_FILE_BYTES), path);
}

void applyOverride(nlohmann::json& document, const std::string& assignment) {
    size_t equals = assignment.find('=');
    if (equals == std::string::npos || equals == 0)
        throw InputError("--set expects key.path=value, got " + quoteUser(assignment));
    std::string path = assignment.substr(0, equals);
    std::string valueText = assignment.substr(equals + 1);
    if (valueText.size() > MAX_JSON_STRING)
        throw InputError(
            "--set value longer than " + std::to_string(MAX_JSON_STRING) + " characters", "", path);
    nlohmann::json value;
    try {
        value = parseJsonText(valueText, "--set");
    } catch (const InputError& e) {
        // Not JSON: taken as a string ("50 um"). Valid JSON that breaks a limit stays an error.
        if (e.reason().rfind("malformed JSON", 0) != 0) {
            const std::string inner = e.key();
            const std::string key =
                inner.empty() ? path : path + (inner[0] == '[' ? "" : ".") + inner;
            throw InputError(e.reason(), "--set", key);
        }
        value = valueText;
    }
    nlohmann::json* node = &document;
    size_t start = 0;
    while (true) {
        size_t dot = path.find('.', start);
        std::string key =
            path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        if (key.empty()) throw InputError("--set: empty key in " + quoteUser(path));
        if (node->is_null()) *node = nlohmann::json::object();
        if (!node->is_object())
            throw InputError("--set: " + quoteUser(path.substr(0, start ? start - 1 : 0)) +
                             " is not an object");
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
    accept(key);
    auto it = mNode->find(key);
    return it == mNode->end() ? nullptr : &*it;
}

const nlohmann::json& ConfigNode::require(const std::string& key) const {
    const nlohmann::json* value = find(key);
    if (!value) throw error(key, "missing required key");
    markRead(key);
    return *value;
}

void ConfigNode::accept(const std::string& key) const {
    mState->accepted[mPath].insert(key);
}

void ConfigNode::setOwner(const std::string& owner) const {
    mState->owners[mPath] = owner;
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
        throw error(key, "expected an integer, got " + describeValue(value));
    return value.get<long long>();
}

bool ConfigNode::boolean(const std::string& key, std::optional<bool> fallback) const {
    if (!has(key) && fallback) return *fallback;
    const nlohmann::json& value = require(key);
    if (!value.is_boolean())
        throw error(key, "expected true or false, got " + describeValue(value));
    return value.get<bool>();
}

std::string ConfigNode::string(const std::string& key, std::optional<std::string> fallback) const {
    if (!has(key) && fallback) return *fallback;
    const nlohmann::json& value = require(key);
    if (!value.is_string()) throw error(key, "expected a string, got " + describeValue(value));
    return value.get<std::string>();
}

std::string ConfigNode::choice(const std::string& key, const std::vector<std::string>& choices,
                               std::optional<std::string> fallback) const {
    std::string value = string(key, fallback);
    for (const auto& c : choices)
        if (c == value) return value;
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    throw error(key, quoteUser(value) + " is not one of: " + list);
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

InputError ConfigNode::unknownKey(const std::string& path, const std::string& key) const {
    std::string reason = "unknown key";
    const auto owner = mState->owners.find(path);
    if (owner != mState->owners.end()) reason += " for " + owner->second;
    std::vector<std::string> accepted;
    const auto keys = mState->accepted.find(path);
    if (keys != mState->accepted.end()) accepted.assign(keys->second.begin(), keys->second.end());
    const std::string nearest = nearestKey(key, accepted);
    if (!nearest.empty()) reason += "; did you mean " + quoteUser(nearest) + "?";
    if (!accepted.empty()) {
        std::string list;
        for (const auto& k : accepted) list += (list.empty() ? "" : ", ") + k;
        reason += " (accepted here: " + escaped(list, 400) + ")";
    }
    return InputError(reason, mState->file, joinPath(path, key));
}

void ConfigNode::checkNode(const nlohmann::json& node, const std::string& path) const {
    if (mState->readPaths.count(path + "/*")) return;
    if (node.is_object()) {
        for (auto it = node.begin(); it != node.end(); ++it) {
            std::string childPath = joinPath(path, it.key());
            if (!mState->readPaths.count(childPath)) throw unknownKey(path, it.key());
            checkNode(it.value(), childPath);
        }
    } else if (node.is_array()) {
        for (size_t i = 0; i < node.size(); ++i)
            if (node[i].is_object()) checkNode(node[i], path + "[" + std::to_string(i) + "]");
    }
}

}  // namespace vpsim
