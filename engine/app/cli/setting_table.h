// The render settings, each declared once: its option, help, parser, EXR metadata key, statistics key, whether a
// resume or merge must match it and whether `converge --vary` can vary it. Every consumer reads this table: the
// commands' options, converge's --vary and the command line it prints, resume and merge, the EXR metadata and the
// JSON statistics. Adding a setting is one entry here plus its use
// (engine/README.md "How a setting flows from the CLI to a shader").
#pragma once
#include <functional>
#include <initializer_list>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "render/settings.h"

namespace CLI {
class App;
}

namespace fh {

struct SettingInfo {
    const char* name;  // the option without its dashes, and converge's --vary key ("max-depth")
    // The words the option takes, for --help ("on|off", "UINT"); nullptr: the option is added by its own function
    // (several options, or a list), named in `options_by`.
    const char* values;
    const char* help;
    const char* metadata_key;  // "fredholm:max_depth" in the EXR metadata; nullptr: not written
    const char* stats_key;     // "max_depth" in --stats JSON; nullptr: not written (or written with what it resolved to)
    bool must_match;           // a resumed render and the parts of a merge must agree on it
    bool can_vary;             // converge --vary NAME=V1,V2 takes it
    // The metadata value of a film written before the setting existed (nullptr: every film has it).
    const char* before_it_existed;
    // Reads one word into the settings; throws std::invalid_argument saying what the word should be.
    std::function<void(RenderSettings&, const std::string&)> parse;
    // The value as the metadata (and a printed command line) spells it.
    std::function<std::string(const RenderSettings&)> describe;
    // The value in --stats JSON (default: `describe`'s text).
    std::function<nlohmann::json(const RenderSettings&)> stats;
    const char* options_by = nullptr;  // with values == nullptr: the function that adds its options
};

// Every render setting, in the order the metadata and a printed command line list them.
const std::vector<SettingInfo>& setting_table();

// The entry of that name; throws std::invalid_argument listing the names when there is none.
const SettingInfo& find_setting(const std::string& name);

// Adds the options of these table entries (by name) to a command, each parsed by its entry.
void add_setting_options(CLI::App& app, RenderSettings& settings, std::initializer_list<const char*> names);

// One entry's option for a command that keeps the value elsewhere: `take` gets default settings with the word parsed
// into them.
void add_setting_option(CLI::App& app, const char* name, std::function<void(const RenderSettings&)> take);

// converge --vary KEY=VALUE: the entry's parser, for the entries that can vary; throws std::invalid_argument naming
// the keys that can.
void apply_vary(const std::string& key, const std::string& value, RenderSettings& settings);

// The --vary keys, comma separated, for help and errors.
std::string vary_keys();

// "--name value" for each setting whose value differs from the default's (a command line that renders the same).
std::string describe_changed_options(const RenderSettings& settings);

// True when every setting has the same value in both (as the metadata would spell them).
bool same_settings(const RenderSettings& a, const RenderSettings& b);

}  // namespace fh
