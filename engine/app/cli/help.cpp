// One table says which help group every option of every command belongs to; the formatter prints each option on
// one line with its value words (aces|clamp, UINT x 3) instead of CLI11's validator text.
#include "app/cli/help.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstring>
#include <map>
#include <regex>
#include <string>

namespace fh {
namespace {

const char* const DIAGNOSTICS = "Measurement and diagnostics (--help-all)";

// Option (long name without dashes) -> group. An option missing here keeps its command's own "Options" group.
const std::map<std::string, std::string>& help_groups() {
    static const std::map<std::string, std::string> groups = [] {
        std::map<std::string, std::string> g;
        auto put = [&g](const char* group, std::initializer_list<const char*> names) {
            for (const char* n : names) g[n] = group;
        };
        put("Output", {"output", "png", "exposure", "tonemap", "stats", "quiet", "resume", "aov"});
        put("Quality", {"width", "height", "spp", "max-depth", "seed", "sampler", "integrator", "merge-radius", "filter",
                        "filter-radius", "microfacet"});
        put("Accuracy", {"target-error", "max-spp", "max-seconds", "adaptive"});
        put("Camera and lens", {"camera", "look-from", "look-at", "up", "yfov", "aperture", "aperture-radius",
                                "sensor-height", "focus-distance", "focus-on", "aperture-blades",
                                "aperture-rotation"});
        put("Lighting", {"env", "env-intensity", "env-rotation", "background", "light-sampler"});
        put("Scene and animation", {"variant", "animation", "time", "shutter", "frames", "fps"});
        put("Splitting a render", {"samples", "crop"});
        put("Device", {"device"});
        put(DIAGNOSTICS, {"nee", "mis", "rr", "rr-start-depth", "rr-survival-scale", "light-pick", "wave-paths",
                          "sort-rays", "wide-stores", "bdpt-strategy", "disable-technique", "bvh-leaf-size",
                          "disable-effect", "force-effect", "instancing", "tangents", "validate"});
        return g;
    }();
    return groups;
}

// "ENUM:value in {aces->1,clamp->0} OR {1,0}" -> "aces|clamp"; "TEXT:{auto,on,off}" -> "auto|on|off";
// "UINT:UINT in [1 - 16384]" -> "UINT".
std::string value_words(const std::string& type_name) {
    static const std::regex choices(R"(\{([^}]*)\})");
    std::smatch m;
    if (std::regex_search(type_name, m, choices)) {
        std::string words, item;
        std::string list = m[1].str() + ",";
        for (char c : list) {
            if (c != ',') {
                item += c;
                continue;
            }
            std::string word = item.substr(0, item.find("->"));
            words += (words.empty() ? "" : "|") + word;
            item.clear();
        }
        if (std::count(words.begin(), words.end(), '|') > 6) {  // 0|3|4|...|16 -> 0|3|...|16
            const size_t second = words.find('|', words.find('|') + 1);
            words = words.substr(0, second) + "|..." + words.substr(words.rfind('|'));
        }
        if (words.size() <= 40) return words;
    }
    return type_name.substr(0, type_name.find(':'));
}

// The groups in the order a user reads them; a command's own options ("Options") after the shared ones.
const char* const GROUP_ORDER[] = {"Output", "Quality", "Accuracy", "Camera and lens", "Lighting", "Scene and animation",
                                   "Splitting a render", "Options", "Device", DIAGNOSTICS, "Help"};

// Hidden options (group "") would lose their names in CLI11's error messages, so the measurement switches keep their
// group and the formatter leaves it out unless asked for everything.
class CompactFormatter : public CLI::Formatter {
  public:
    explicit CompactFormatter(bool show_all) : show_all_(show_all) {}

    std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override {
        if (mode == CLI::AppFormatMode::Sub) return make_expanded(app);
        std::string out = make_description(app) + make_usage(app, name) + make_positionals(app);
        std::vector<std::string> order(std::begin(GROUP_ORDER), std::end(GROUP_ORDER));
        for (const std::string& g : app->get_groups())
            if (std::find(order.begin(), order.end(), g) == order.end()) order.push_back(g);
        for (const std::string& group : order) {
            auto opts = app->get_options(
                [&group](const CLI::Option* opt) { return opt->get_group() == group && opt->nonpositional(); });
            if (group.empty() || opts.empty() || (group == DIAGNOSTICS && !show_all_)) continue;
            out += make_group(group, false, opts);
        }
        return out + make_subcommands(app, mode) + "\n" + make_footer(app);
    }

    std::string make_option_opts(const CLI::Option* opt) const override {
        if (!opt->get_option_text().empty()) return " " + opt->get_option_text();
        if (opt->get_type_size() == 0) return "";
        std::string out = " " + value_words(opt->get_type_name());
        if (opt->get_expected_max() == CLI::detail::expected_max_vector_size) out += " ...";
        else if (opt->get_expected_min() > 1) out += " x " + std::to_string(opt->get_expected());
        if (opt->get_required()) out += " REQUIRED";
        return out;
    }

  private:
    bool show_all_;
};

}  // namespace

bool take_help_all(int argc, char** argv) {
    bool found = false;
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--help-all") == 0) {
            argv[i] = const_cast<char*>("--help");
            found = true;
        }
    return found;
}

void arrange_help(CLI::App& command, bool show_all, const std::string& example,
                  const std::set<std::string>& keep_group) {
    auto formatter = std::make_shared<CompactFormatter>(show_all);
    formatter->column_width(42);
    command.formatter(formatter);
    command.get_help_ptr()->group("Help");
    command.add_flag("--help-all")
        ->description("also list the measurement and diagnostic switches")->group("Help");
    for (CLI::Option* opt : command.get_options()) {
        const std::string name = opt->get_lnames().empty() ? "" : opt->get_lnames().front();
        auto found = help_groups().find(name);
        if (found == help_groups().end() || keep_group.count(name)) continue;
        opt->group(found->second);
    }
    command.footer("Example: " + example);
}

}  // namespace fh
