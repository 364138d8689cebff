// The effects a scene calls for, decided by value (a texture of a material no triangle uses, a BLEND material
// whose alpha is 1 everywhere, white vertex colours: none of these switch an effect on). The stages are
// compiled for exactly this set (layout.h EFFECT_* and EFFECT2_*, specialization constants SPEC_EFFECTS and
// SPEC_EFFECTS_2).
#pragma once
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "scene/effect_bits.h"
#include "scene/scene.h"

namespace fh {

// The second word's effects as EffectBits.
constexpr EffectBits EFFECT_SPECULAR_TEXTURE = effect2_bit(gpu::EFFECT2_SPECULAR_TEXTURE);
constexpr EffectBits EFFECT_GLOSSINESS_TEXTURE = effect2_bit(gpu::EFFECT2_GLOSSINESS_TEXTURE);
// layout.h's groups over both words: what reads TriangleAttributes, and what --force-effect / --disable-effect may
// switch.
constexpr EffectBits ATTRIBUTE_EFFECTS = gpu::EFFECT_ATTRIBUTES | effect2_bit(gpu::EFFECT2_ATTRIBUTES);
constexpr EffectBits SWITCHABLE_EFFECTS = gpu::EFFECT_SWITCHABLE | effect2_bit(gpu::EFFECT2_SWITCHABLE);

struct EffectInfo {
    EffectBits bit;
    const char* name;  // as --stats and the EXR metadata print it
};
const std::vector<EffectInfo>& list_effects();

struct EffectDecision {
    EffectBits bit;
    const char* name;
    bool on;
    std::string why;  // which materials ask for it, or why it is off
};

struct SceneEffects {
    EffectBits bits = 0;
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
// applied to the switchable effects (SWITCHABLE_EFFECTS; the environment and the thin lens follow the command line;
// motion blur, decided by the motion, may be switched off).
EffectBits select_effects(EffectBits analysed, EffectBits forced, EffectBits disabled);

// The bit of a switchable effect (SWITCHABLE_EFFECTS) named as list_effects() names it; throws
// std::invalid_argument naming the switchable effects when `name` is not one of them.
EffectBits find_switchable_effect(const std::string& name);

// "base-color-texture,alpha,..." (or "none").
std::string describe_effects(EffectBits bits);

}  // namespace fh
