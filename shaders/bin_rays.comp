// Stage "bin_rays", the first of the ray sort (lib/core/ray_order.glsl): each queued ray's key and its rank among the rays
// of that key (the count before it), and how many rays have each key. Reads: rays[queue depth & 1],
// counters.ray_count, params (scene bounds). Writes: the ray-sort buffer's keys, ranks and counts (scan_ray_bins
// leaves the counts zero for the next depth).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/ray_order.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint parity = push.depth & 1u;
    if (i >= counters.ray_count[parity]) return;
    uint slot = ray_slot(parity, i);
    RayItem ray = load_ray_item(slot);
    vec3 origin = vec3(ray.origin_x, ray.origin_y, ray.origin_z);
    vec3 dir = vec3(ray.dir_x, ray.dir_y, ray.dir_z);
    bin_ray(i, origin, dir);
}
