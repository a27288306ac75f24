#pragma once
/// @file
/// A registry of named components (planners, cure laws, exporters) created from their config
/// section. Each entry owns its key table (core/key_table.h): the factory reads the section
/// through a KeyReader over it, so defaults, ranges and docs are declared once.
/// There is no global instance: the caller fills one with an explicit registerBuiltins() call
/// (static self-registration is dropped by static libraries) and passes it down, so two runs
/// never share state.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/key_table.h"

namespace vpsim {

template <class Component>
class Registry {
public:
    /// Creates a component from its config section, read through the entry's key table.
    using Factory = std::function<std::unique_ptr<Component>(const KeyReader& keys)>;

    struct Entry {
        std::string name;
        std::string description;
        KeyTable keys;
        Factory factory;
        /// "planner 'aces'": how messages name the component.
        std::string label(const std::string& kind) const { return kind + " '" + name + "'"; }
    };

    /// @param kind what the registry holds, for messages ("planner", "exporter")
    explicit Registry(std::string kind) : mKind(std::move(kind)) {}

    /// @throw std::logic_error when `entry.name` is registered already (a programming error)
    void add(Entry entry) {
        if (mEntries.count(entry.name))
            throw std::logic_error(mKind + " '" + entry.name + "' registered twice");
        std::string name = entry.name;
        mEntries.emplace(name, std::move(entry));
    }

    bool has(const std::string& name) const { return mEntries.count(name) != 0; }

    /// @throw InputError naming the known names when `name` is not registered
    const Entry& entry(const std::string& name) const {
        auto it = mEntries.find(name);
        if (it == mEntries.end())
            throw InputError("unknown " + mKind + " '" + name + "' (known: " + namesText() + ")");
        return it->second;
    }

    /// Creates `name` from `section`. @throw InputError from the lookup or the factory
    std::unique_ptr<Component> create(const std::string& name, const ConfigNode& section) const {
        const Entry& e = entry(name);
        return e.factory(KeyReader(e.keys, section, e.label(mKind)));
    }

    /// Registered names, sorted.
    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const auto& [name, entry] : mEntries) out.push_back(name);
        return out;
    }

    const std::map<std::string, Entry>& entries() const { return mEntries; }
    const std::string& kind() const { return mKind; }

private:
    std::string namesText() const {
        std::string text;
        for (const auto& [name, entry] : mEntries) text += (text.empty() ? "" : ", ") + name;
        return text;
    }

    std::string mKind;
    std::map<std::string, Entry> mEntries;
};

}  // namespace vpsim
