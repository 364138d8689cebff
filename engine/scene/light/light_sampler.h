// How next-event estimation picks a light (`--light-sampler`): from the light tree by each light's importance at the
// shading point (scene/light/light_tree.h), in proportion to power from one alias table for the whole scene, or uniformly.
#pragma once
#include <string>

namespace fh {

struct PackedScene;  // scene/pack.h

enum class LightSampler { automatic, tree, power, uniform };

// "auto", "tree", "power", "uniform"; parse_light_sampler throws std::invalid_argument naming the choices.
const char* light_sampler_name(LightSampler sampler);
LightSampler parse_light_sampler(const std::string& name);

// Sets up `packed`'s lights for `requested`: a tree (emitter table reordered: tree lights first, then the environment
// and directional lights; EFFECT_LIGHT_TREE), or an alias table of equal weights (uniform), or the power table as
// pack_scene made it. `automatic` takes the tree where the scene has lights of more than one kind or material, more
// than 16 lights, or lights with a place beside an environment or a directional light (the tree then measured better:
// tests/bench/RESULTS.md), the power table otherwise.
// next_event false (light tracing): nothing picks a light but the light subpaths' start, by the table, so the tree is
// refused (std::invalid_argument) and auto keeps the power table. BDPT and VCM start light subpaths by the table too,
// and pick by the tree for next-event estimation alone (s = 1; their weights carry both probabilities). Throws
// SceneError when the tree would hold more than MAX_TREE_LIGHTS lights.
void choose_light_sampler(PackedScene& packed, LightSampler requested, bool next_event);

// "tree over 290 of 291 lights: depth 12, 579 nodes, 36.2 KiB (128 bytes per light), built in 0.0004 s", or
// "power table over 291 lights" (info, bench, --stats).
std::string describe_light_sampler(const PackedScene& packed);

}  // namespace fh
