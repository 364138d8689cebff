// The effect set the stages are compiled for (layout.h EFFECT_*, chosen by engine/scene/effects.cpp): code
// behind an effect that is off is removed when the pipeline is specialised, so a scene pays only for its own.
#ifndef FH_EFFECTS_GLSL
#define FH_EFFECTS_GLSL
layout(constant_id = SPEC_EFFECTS) const uint scene_effects = 0u;
layout(constant_id = SPEC_EFFECTS_2) const uint scene_effects_2 = 0u;

bool effect_on(uint effect) { return (scene_effects & effect) != 0u; }     // EFFECT_* (the first word)
bool effect2_on(uint effect) { return (scene_effects_2 & effect) != 0u; }  // EFFECT2_* (the second word)
#endif
