// Per-vertex tangents for primitives without TANGENT, computed as MikkTSpace does (Mikkelsen 2008, the tangent space
// the glTF spec says clients SHOULD compute, and that normal maps are baked against): each corner's tangent is the
// angle-weighted average, over the triangles around its vertex that share edges and texture orientation with it, of
// their texture-space u directions projected onto the vertex normal's plane; w is the bitangent's sign.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace fh::gltf {

// One tangent per corner of `triangles` (vertex indices into `positions`, `normals` and `uvs`, whose xy are the
// glTF texture coordinates, v down). Vertices with equal position, normal and texture coordinates are one vertex,
// as MikkTSpace welds them. w = +1 or -1 is the bitangent's sign: bitangent = cross(normal, tangent) w. A corner
// that gets no tangent (its triangles all have no texture-space extent, or a normal of zero length) is vec4(0): the
// shader then derives the frame per triangle, as without TANGENT before.
std::vector<std::array<glm::vec4, 3>> generate_tangents(const std::vector<std::array<uint32_t, 3>>& triangles,
                                                        const std::vector<glm::vec3>& positions,
                                                        const std::vector<glm::vec3>& normals,
                                                        const std::vector<glm::vec4>& uvs);

}  // namespace fh::gltf
