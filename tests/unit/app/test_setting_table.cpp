// The table of render settings (engine/app/cli/setting_table.h): each option's word comes back as the metadata spells
// it, keys are unique, resume matches what must match, and converge --vary takes only what can vary.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "app/cli/resume.h"
#include "app/cli/setting_table.h"

namespace fh {
namespace {

// A word that is not the default, for every setting that has its own option: the metadata (and the command line a
// converge report prints) must spell it back the same, or a resumed render or a printed command would differ.
const std::map<std::string, std::string>& sample_words() {
    static const std::map<std::string, std::string> words = {
        {"seed", "4294967295"},    {"max-depth", "100000"},          {"camera", "3"},
        {"filter", "gaussian"},    {"filter-radius", "2.5"},  {"sampler", "independent"},
        {"integrator", "vcm"},     {"merge-radius", "0.00390625"},   {"nee", "off"},                   {"mis", "off"},
        {"rr", "off"},             {"rr-start-depth", "7"},          {"rr-survival-scale", "0.123456791"},
        {"light-pick", "separate"}, {"light-sampler", "tree"},       {"wave-paths", "2048"},
        {"sort-rays", "on"},       {"wide-stores", "off"},           {"bvh-leaf-size", "2"},
        {"variant", "Yellow"},     {"instancing", "off"},            {"microfacet", "single"},
        {"tangents", "triangle"},  {"memory-limit", "104857600"}};
    return words;
}

bool has_own_option(const SettingInfo& e) { return e.values && e.parse; }

TEST(SettingTable, EveryOptionsWordComesBackAsTheMetadataSpellsIt) {
    for (const SettingInfo& e : setting_table()) {
        if (!has_own_option(e)) continue;
        auto word = sample_words().find(e.name);
        ASSERT_NE(word, sample_words().end()) << e.name << ": give it a sample word in this test";
        RenderSettings s;
        e.parse(s, word->second);
        EXPECT_EQ(e.describe(s), word->second) << e.name;
        EXPECT_NE(e.describe(s), e.describe(RenderSettings{})) << e.name << ": the sample word is the default";
        EXPECT_NE(describe_changed_options(s).find(std::string("--") + e.name + " " + word->second), std::string::npos)
            << e.name;
        EXPECT_FALSE(same_settings(s, RenderSettings{})) << e.name;
    }
}

TEST(SettingTable, NamesAndKeysAreUnique) {
    std::set<std::string> names, metadata, stats;
    for (const SettingInfo& e : setting_table()) {
        EXPECT_TRUE(names.insert(e.name).second) << e.name;
        if (e.metadata_key) EXPECT_TRUE(metadata.insert(e.metadata_key).second) << e.metadata_key;
        if (e.stats_key) EXPECT_TRUE(stats.insert(e.stats_key).second) << e.stats_key;
        EXPECT_TRUE(e.describe) << e.name;
        EXPECT_TRUE(has_own_option(e) || e.options_by) << e.name << ": which function adds its options?";
        if (e.must_match || e.before_it_existed) EXPECT_TRUE(e.metadata_key) << e.name;
        if (e.can_vary) EXPECT_TRUE(e.parse) << e.name;
    }
}

TEST(SettingTable, ResumeMatchesEverySettingThatMustMatch) {
    const std::vector<std::string>& keys = matching_film_keys();
    const std::set<std::string> matched(keys.begin(), keys.end());
    for (const SettingInfo& e : setting_table())
        if (e.metadata_key) EXPECT_EQ(matched.count(e.metadata_key), e.must_match ? 1u : 0u) << e.metadata_key;
    for (const char* key : {"fredholm:renderer", "fredholm:scene", "fredholm:scene_hash", "fredholm:image_size"})
        EXPECT_EQ(matched.count(key), 1u) << key;
}

TEST(SettingTable, VaryTakesWhatCanVaryAndSaysWhatCan) {
    RenderSettings s;
    apply_vary("light-sampler", "power", s);
    EXPECT_EQ(s.light_sampler, LightSampler::power);
    apply_vary("effect:transmission", "on", s);
    EXPECT_NE(s.forced_effects, 0u);
    try {
        apply_vary("seed", "1", s);  // a seed is not a configuration: converge draws its own
        FAIL() << "seed varied";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("light-sampler"), std::string::npos) << e.what();
    }
    EXPECT_THROW(apply_vary("integrator", "auto", s), std::invalid_argument);
    EXPECT_THROW(apply_vary("nee", "maybe", s), std::invalid_argument);
    EXPECT_THROW(apply_vary("max-depth", "-1", s), std::invalid_argument);
}

TEST(SettingTable, ParsersRefuseWhatTheOptionsRefused) {
    RenderSettings s;
    for (auto [name, word] : std::map<std::string, std::string>{{"max-depth", "100001"}, {"rr-start-depth", "0"},
                                                                {"filter-radius", "9"}, {"camera", "-1"},
                                                                {"wave-paths", "1023"}, {"seed", "4294967296"},
                                                                {"sampler", "halton"}, {"bvh-leaf-size", "0"}})
        EXPECT_THROW(find_setting(name).parse(s, word), std::invalid_argument) << name << " " << word;
    find_setting("nee").parse(s, "OFF");  // as before: words in any case
    EXPECT_FALSE(s.nee);
}

}  // namespace
}  // namespace fh
