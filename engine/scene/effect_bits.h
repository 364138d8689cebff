// An effect set: layout.h's EFFECT_* bits in the low 32 bits, its EFFECT2_* bits (the second specialization
// constant, SPEC_EFFECTS_2) in the high 32. scene/effects.h decides them and names them.
#pragma once
#include <cstdint>

namespace fh {

using EffectBits = uint64_t;

constexpr EffectBits effect2_bit(uint32_t effect2) { return EffectBits(effect2) << 32; }  // an EFFECT2_* bit
constexpr uint32_t low_effect_word(EffectBits bits) { return uint32_t(bits); }             // SPEC_EFFECTS
constexpr uint32_t high_effect_word(EffectBits bits) { return uint32_t(bits >> 32); }      // SPEC_EFFECTS_2

}  // namespace fh
