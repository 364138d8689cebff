// When a mesh drawn by several nodes (or EXT_mesh_gpu_instancing) is stored once and placed by instances in a
// two-level BVH, instead of copied into world space once per placement (LoadOptions::instancing).
#pragma once
#include <cstddef>

namespace fh {

// automatic: when its copies would store at least MIN_TRIANGLES_SAVED_BY_INSTANCING more triangles (a small
// shared mesh costs less copied than traversed through an instance); always: every shared mesh that emits no
// light; never: every placement copied (to compare the two).
enum class Instancing { automatic, always, never };
inline constexpr size_t MIN_TRIANGLES_SAVED_BY_INSTANCING = 16384;

}  // namespace fh
