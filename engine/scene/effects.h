// The effects a scene calls for, decided by value (a texture of a material no triangle uses, a BLEND material
// whose alpha is 1 everywhere, white vertex colours: none of these switch an effect on). The stages are
// compiled for exactly this set (layout.h EFFECT_*, specialization constant SPEC_EFFECTS).
#pragma once
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace fh {

struct EffectInfo {
    uint32_t bit;
    const char* name;  // as --stats and the EXR metadata print it
};
const std::vector<EffectInfo>& list_effects();

struct EffectDecision {
    uint32_t bit;
    const char* name;
    bool on;
    std::string why;  // which materials ask for it, or why it is off
};

struct SceneEffects {
    uint32_t bits = 0;
    std::vector<EffectDecision> decisions;  // one per list_effects() entry
};

// `environment`: the render has --env or --background. The light effects (EFFECT_LIGHTS) are left off: the
// light table decides them (decide_light_effects).
SceneEffects analyse_effects(const Scene& scene, bool environment);

// Adds the decisions of the light effects from the light table: `emitting_materials` of the triangles it holds
// (those that emit by value: non-black factor and texture, some area) and its `punctual_lights` of non-zero power.
void decide_light_effects(SceneEffects& effects, const std::set<uint32_t>& emitting_materials, size_t emitting_triangles,
                          size_t punctual_lights);

// Sets the light tree's decision (light-tree: NEE picks lights from the tree; scene/light/light_sampler.h), replacing an earlier one.
void decide_light_tree_effect(SceneEffects& effects, bool tree, std::string why);

// Sets the camera's decision (thin-lens: the render asks for an aperture above 0), replacing an earlier one.
void decide_camera_effects(SceneEffects& effects, bool thin_lens);

// --microfacet single: the rough metals' multiple-scattering lobe (EFFECT_GGX_MULTISCATTER) off, with the reason.
void decide_microfacet_effects(SceneEffects& effects, bool compensated);

// Sets the motion decision (motion-blur: a --shutter over which instances or the camera move), replacing an earlier one.
void decide_motion_effects(SceneEffects& effects, bool has_shutter, size_t moving_instances, bool camera_moves);

// The effect set the stages are compiled with: the analysed one, with --force-effect and --disable-effect
// applied to the switchable effects (EFFECT_SWITCHABLE; the environment and the thin lens follow the command line;
// motion blur, decided by the motion, may be switched off).
uint32_t select_effects(uint32_t analysed, uint32_t forced, uint32_t disabled);

// The bit of a switchable effect (EFFECT_SWITCHABLE) named as list_effects() names it; throws
// std::invalid_argument naming the switchable effects when `name` is not one of them.
uint32_t find_switchable_effect(const std::string& name);

// "base-color-texture,alpha,..." (or "none").
std::string describe_effects(uint32_t bits);

}  // namespace fh
