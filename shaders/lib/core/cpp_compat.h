// Lets the physics libraries in shaders/lib/*.glsl compile as C++ (with GLM) so the CPU unit tests exercise
// the very code the stages run. Include this, then the .glsl file, from C++ only.
//
// The shared subset of GLSL and C++ these libraries are written in:
// - no `in`/`out`/`inout` parameters: return a struct instead;
// - no struct constructors (`S(a, b)`): declare, assign fields, return;
// - literals with an `f` suffix only where both accept it (GLSL does: `1.0f`);
// - built-ins limited to those GLM also provides, plus the few defined below.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

namespace fh::glsl {
using namespace glm;
using uint = std::uint32_t;

inline float uintBitsToFloat(uint u) { float f; std::memcpy(&f, &u, 4); return f; }
inline uint floatBitsToUint(float f) { uint u; std::memcpy(&u, &f, 4); return u; }
inline int floatBitsToInt(float f) { int i; std::memcpy(&i, &f, 4); return i; }
inline float intBitsToFloat(int i) { float f; std::memcpy(&f, &i, 4); return f; }
inline bool isnan(float x) { return std::isnan(x); }
inline bool isinf(float x) { return std::isinf(x); }
// GLSL's fma on vectors (GLM has the scalar one only); fused, as the GPU may do it.
inline vec3 fma(vec3 a, vec3 b, vec3 c) { return vec3(std::fma(a.x, b.x, c.x), std::fma(a.y, b.y, c.y), std::fma(a.z, b.z, c.z)); }
}  // namespace fh::glsl
