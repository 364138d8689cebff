// What a render is asked to do: film size, samples, path length, sampling switches.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "scene/effect_bits.h"
#include "scene/instancing.h"
#include "scene/light/light_sampler.h"
#include "scene/memory_limit.h"

namespace fh {

enum class PixelFilter { box, gaussian };

// The thin lens the command line asks for (engine/render/README.md "Depth of field"); glTF cameras have none. All zero: a pinhole.
struct LensSettings {
    double f_number = 0.0;          // --aperture N: radius = focal length / (2 N), focal length from yfov and the sensor
    double aperture_radius = 0.0;   // --aperture-radius R, world units (instead of --aperture)
    double sensor_height_mm = 24.0; // --sensor-height: the film height yfov spans (35 mm full frame: 24)
    double focus_distance = 0.0;    // --focus-distance D, world units along the view; 0: --focus-on or the centre
    bool focus_on_given = false;    // --focus-on X,Y: focus on the surface seen at that pixel
    double focus_on[2] = {0.0, 0.0};
    uint32_t blades = 0;            // --aperture-blades: 0 a disk, 3 or more a regular polygon
    double rotation_degrees = 0.0;  // --aperture-rotation
    bool on() const { return f_number > 0.0 || aperture_radius > 0.0; }
};
// How the light transport equation is solved (shaders/lib/integrator/README.md "Light tracing", "Bidirectional path tracing"): path tracing from
// the camera with next-event estimation and MIS, light tracing (light subpaths splatted onto the film through the
// camera; the t = 1 strategies of bidirectional path tracing alone), or bidirectional path tracing (every strategy
// (s, t), combined by MIS), or vertex connection and merging (BDPT's strategies and vertex merging, combined by MIS:
// consistent, not unbiased; "Vertex connection and merging").
// `automatic` (--integrator auto, fredholm render only) is resolved by a pilot before any Renderer is built.
enum class Integrator { path, light, bdpt, vcm, automatic };
// BDPT and VCM store light subpaths and join them to camera subpaths by every connection strategy.
inline bool connects_subpaths(Integrator integrator) {
    return integrator == Integrator::bdpt || integrator == Integrator::vcm;
}

// --microfacet: rough GGX lobes (metals, dielectric specular layers) give back the energy single-scattering GGX loses
// (shaders/lib/bsdf/ggx_multiscatter.glsl), or keep the glTF spec's single scattering.
enum class Microfacet { compensated, single };

// --tangents: without TANGENT, the loader's MikkTSpace tangents (engine/scene/gltf/gltf_tangents.h), or each
// triangle's own frame from its texture coordinates (what Fredholm did before, kept for comparison).
enum class Tangents { mikktspace, triangle };

// Where a path's random numbers come from (shaders/lib/sampling/path_sampler.glsl).
enum class Sampler { independent, sobol };

struct RenderSettings {
    uint32_t width = 512;
    uint32_t height = 512;
    uint32_t spp = 64;
    uint32_t max_depth = 0;        // segments after the camera; 0 = unlimited (Russian roulette ends paths)
    uint32_t seed = 0;
    int camera = -1;               // glTF camera index in scene order; -1 = first camera or default framing
    PixelFilter filter = PixelFilter::box;
    Sampler sampler = Sampler::sobol;  // --sampler: Owen-scrambled Sobol' (stratified) or independent
    Integrator integrator = Integrator::path;  // --integrator path|light|bdpt|vcm
    // --merge-radius: vertex merging's radius at the first sample, as a fraction of the scene's bounding-sphere
    // radius; it shrinks with the sample index (render/vertex_merging.h).
    float merge_radius = 0.001f;
    // --bdpt-strategy S,T: bidirectional path tracing's strategy with S light and T camera vertices alone, unweighted
    // (a check: each converges to the part of the image made by paths of S + T - 1 segments). T = 0: all, by MIS.
    uint32_t bdpt_strategy_s = 0, bdpt_strategy_t = 0;
    float filter_radius = 1.5f;    // Gaussian truncation radius in pixels
    bool nee = true;               // next-event estimation
    bool mis = true;               // MIS between NEE and BSDF sampling
    bool russian_roulette = true;
    uint32_t rr_start_depth = 3;   // roulette from this many segments on
    // A camera path survives roulette with probability min(0.95, this x its largest throughput component): 2, chosen
    // by measured efficiency (tests/bench/RESULTS.md "Speed"; 1 is the textbook's and Mitsuba's).
    float rr_survival_scale = 2.0f;
    // --light-pick reuse|separate: NEE picks the light with the first coordinate of its point's 2D sample and reuses the
    // rest (up to 16 lights; shaders/lib/light/lights.glsl), or with a sampler dimension of its own (shaders/lib/integrator/README.md "Sampling").
    bool light_pick_reuse = true;
    // --light-sampler: how NEE picks a light (scene/light/light_sampler.h); auto: the tree where the lights differ.
    LightSampler light_sampler = LightSampler::automatic;
    uint32_t wave_paths = 0;  // paths in flight per wave; 0: chosen for the device (render/device_defaults.h)
    // --sort-rays: extend takes each bounce's rays sorted by direction and origin (render/ray_sort.h). Unset (auto):
    // chosen for the device and scene by with_device_defaults (render/device_defaults.h; tests/bench/RESULTS.md "Ray order").
    std::optional<bool> sort_rays;
    // --wide-stores: shade stores its structs a texel (uvec4) at a time; off: field by field (to measure what the
    // wide stores buy). The image is the same.
    bool wide_stores = true;
    bool aovs = false;  // --aov albedo, normal or depth: shade records them and accumulate sums them (lib/core/aov.glsl)
    // --adaptive: waves take their pixels from a list (lib/core/wave_pixels.glsl), so that each pixel can get its own
    // number of samples (render/adaptive_render.h).
    bool adaptive = false;
    Microfacet microfacet = Microfacet::compensated;
    uint32_t disabled_techniques = 0;  // layout.h TECHNIQUE_* bits switched off (cost measurements only)
    uint32_t bvh_max_leaf_size = 4;    // triangles per BVH leaf at most
    EffectBits disabled_effects = 0;     // --disable-effect: layout.h EFFECT_* bits compiled out (measurement only)
    EffectBits forced_effects = 0;       // --force-effect: EFFECT_* bits compiled in although unused (measurement)
    std::string variant;               // --variant: KHR_materials_variants name (empty: the file's default)
    Instancing instancing = Instancing::automatic;  // --instancing auto|on|off
    Tangents tangents = Tangents::mikktspace;       // --tangents mikktspace|triangle
    // --memory-limit: bytes the scene on the host and the render's device buffers may take (their sum on a CPU
    // device, whose device memory is host memory); 0: default_memory_limit() (scene/memory_limit.h).
    uint64_t memory_limit = 0;
    uint64_t resolved_memory_limit() const { return memory_limit ? memory_limit : default_memory_limit(); }
    // Light from outside the scene (engine/scene/README.md "Environment light"): an equirectangular map, or a constant.
    std::string environment_file;      // --env (OpenEXR or Radiance .hdr); empty: none
    float environment_intensity = 1.0f;   // --env-intensity: radiance scale
    float environment_rotation = 0.0f;    // --env-rotation, degrees about +Y
    bool has_background = false;          // --background R,G,B
    float background[3] = {0.0f, 0.0f, 0.0f};
    LensSettings lens;                    // depth of field (EFFECT_THIN_LENS when on())
    // glTF animation (engine/scene/gltf/README.md "Animation"): --time poses the scene at that time by --animation (default the first).
    bool animate = false;
    std::string animation;
    double time = 0.0;                    // seconds
    // Motion blur (engine/render/README.md "Motion blur"): --shutter OPEN,CLOSE, seconds relative to `time`; equal: none.
    double shutter_open = 0.0, shutter_close = 0.0;
    bool has_shutter() const { return shutter_close > shutter_open; }
    // --crop: only pixels [crop_x0, crop_x1) x [crop_y0, crop_y1) of the width x height image are rendered, into a
    // film of that size (each with the samples it has in the whole image). All zero: the whole image.
    uint32_t crop_x0 = 0, crop_y0 = 0, crop_x1 = 0, crop_y1 = 0;
    bool has_crop() const { return crop_x1 > crop_x0; }
    uint32_t film_width() const { return has_crop() ? crop_x1 - crop_x0 : width; }
    uint32_t film_height() const { return has_crop() ? crop_y1 - crop_y0 : height; }
};

const char* to_string(PixelFilter filter);
const char* to_string(Sampler sampler);
const char* to_string(Integrator integrator);

}  // namespace fh
