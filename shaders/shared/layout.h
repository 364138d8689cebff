// Buffer layouts, binding numbers and constants shared by the GLSL stages and the C++ host: the one place
// where a struct crossing the host/device boundary is defined (tests/unit/scene/test_layout.cpp checks offsets).
//
// Rules that keep GLSL std430 and C++ in agreement without padding surprises:
// - structs hold only 32-bit scalars (float, uint, int) and vec4, with every vec4 before any scalar;
// - no vec3 in a buffer (std430 aligns it to 16 bytes);
// - fields are named for what they hold.
#ifndef FREDHOLM_SHARED_LAYOUT_H
#define FREDHOLM_SHARED_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace fh::gpu {
using uint = std::uint32_t;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
#define FH_CONST inline constexpr
#else
#define FH_CONST const
#endif

// ---- Dispatch shape -------------------------------------------------------------------------------------
FH_CONST uint WORKGROUP_SIZE = 64u;  // lavapipe: 8-lane subgroups, 64..256 per group measured best

// ---- Descriptor bindings (set 0, shared by every stage) ------------------------------------------------------
// The scene's read-only arrays of structs (marked TEXELS) are uniform texel buffers of RGBA32UI texels, one per 16
// bytes, read by the loaders make_texel_loaders.py writes from the structs below: on lavapipe a texel fetch is one
// gather for all lanes, where a storage-buffer load loops over the lanes with a bounds check per word (the extend
// stage measured 2.2x faster on a 1.3M-triangle mesh, and faster than uniform buffers on the Cornell box), and a
// texel buffer reaches maxTexelBufferElements x 16 bytes (2 GiB on lavapipe) where a storage buffer stops at
// maxStorageBufferRange (128 MiB). The others are storage buffers, but for the one uniform buffer.
FH_CONST uint BINDING_PARAMS = 0u;          // FrameParams, one element
FH_CONST uint BINDING_BVH_NODES = 1u;       // TEXELS BvhWideNode[], root at 0, children after their parent, siblings consecutive
FH_CONST uint BINDING_TRI_POSITIONS = 2u;   // TEXELS TrianglePositions[], in BVH leaf order
FH_CONST uint BINDING_TRI_SHADING = 3u;     // TEXELS TriangleShading[], same order
FH_CONST uint BINDING_MATERIALS = 4u;       // TEXELS Material[]
FH_CONST uint BINDING_EMITTERS = 5u;        // TEXELS Emitter[] (alias table over emissive triangles and punctual lights)
FH_CONST uint BINDING_COUNTERS = 6u;        // QueueCounters, one element (also the indirect-dispatch source)
FH_CONST uint BINDING_PATHS = 7u;           // PathState[wave capacity]
FH_CONST uint BINDING_RAYS = 8u;            // RayItem[2 * wave capacity]: two queues, by depth parity
FH_CONST uint BINDING_HITS = 9u;            // HitItem[wave capacity], aligned with the current ray queue
FH_CONST uint BINDING_SHADOW_RAYS = 10u;    // ShadowRayItem[wave capacity]
FH_CONST uint BINDING_FILM = 11u;           // FilmPixel[width * height]
FH_CONST uint BINDING_GGX_ALBEDO_UNIFORM = 12u;  // uniform buffer: the BSDF's albedo tables (ggx_albedo_table.glsl, ...)
FH_CONST uint BINDING_PUNCTUAL_LIGHTS = 13u;    // TEXELS PunctualLight[] (KHR_lights_punctual), read by NEE only
FH_CONST uint BINDING_TRI_ATTRIBUTES = 14u;     // TEXELS TriangleAttributes[] (BVH leaf order), when EFFECT_ATTRIBUTES
FH_CONST uint BINDING_TEXTURE_SLOTS = 15u;      // TEXELS TextureSlot[]: a material's reference to a texture
FH_CONST uint BINDING_TEXTURE_IMAGES = 16u;     // TEXELS TextureImage[]: where each image's texels start
FH_CONST uint BINDING_TEXELS = 17u;             // TEXELS uint[]: RGBA8 image texels, rows top to bottom, four per
                                                // RGBA32UI texel (texture.glsl load_image_texel)
FH_CONST uint BINDING_ENV_RADIANCE = 18u;       // vec4[]: environment radiance (rgb), equirectangular rows
FH_CONST uint BINDING_ENV_CDF = 19u;            // float[]: marginal CDF (height + 1), then one CDF per row
FH_CONST uint BINDING_INSTANCES = 20u;       // TEXELS Instance[] (two-level BVH), when the scene has instances
FH_CONST uint BINDING_MATERIAL_LAYERS = 21u; // TEXELS MaterialLayers[] (KHR material extensions), parallel to Material[]
FH_CONST uint BINDING_PATH_MEDIA = 22u;      // uvec4[wave capacity]: the volumes a path is in (EFFECT_VOLUME, _ABSORPTION)
// A path remembers the volumes it is inside, innermost first (material indices, INVALID_INDEX past the last): entering
// a volume puts it in front, leaving one takes it out (nested dielectrics, lib/material/transmission.glsl). A fifth is dropped.
FH_CONST uint MEDIUM_STACK_SIZE = 4u;
FH_CONST uint BINDING_PATH_SPECTRA = 23u;    // PathSpectrum[wave capacity]: a path's wavelengths (EFFECT_SPECTRAL)
FH_CONST uint BINDING_GLASS_ALBEDO = 24u;    // float[]: glass_albedo_table.glsl (EFFECT_GLASS_MULTISCATTER; else one word)
FH_CONST uint BINDING_PATH_TIMES = 25u;     // float[wave capacity]: a path's time in the shutter, 0..1 (EFFECT_MOTION_BLUR)
// Bidirectional path tracing (`--integrator bdpt`; else one element each): the stored light-subpath vertices,
// FrameParams.light_vertex_slots per path (LightVertex[wave capacity x slots]), and each path's MIS quantities.
FH_CONST uint BINDING_LIGHT_VERTICES = 26u;
FH_CONST uint BINDING_PATH_MIS = 27u;         // PathMis[wave capacity]
// The ray queue's sorted order (`--sort-rays`; else one word): uint words, RAY_SORT_BINS counts, RAY_SORT_BINS
// offsets and RAY_SORT_BLOCKS block sums, then per queued ray its key, then its rank within the key, then the queue
// index of the i-th ray in key order (RAY_SORT_COUNTS .. RAY_SORT_WORDS_PER_RAY below; lib/core/ray_order.glsl).
FH_CONST uint BINDING_RAY_SORT = 28u;
// The wave's arrays again, as RGBA32UI uniform texel buffers over the same memory, for the stages that read what an
// earlier dispatch wrote (TEXELS loaders load_path_state, load_ray_item, load_hit_item, load_shadow_ray). Writes stay
// storage-buffer stores. On lavapipe a storage-buffer load runs a loop over the 8 lanes per 32-bit word; a texel
// fetch loads 16 bytes for all lanes without one (tests/bench/RESULTS.md "Speed": shade read 21 words per path vertex so).
FH_CONST uint BINDING_PATH_TEXELS = 29u;        // TEXELS PathState[wave capacity] (BINDING_PATHS' memory)
FH_CONST uint BINDING_RAY_TEXELS = 30u;         // TEXELS RayItem[2 * wave capacity] (BINDING_RAYS' memory)
FH_CONST uint BINDING_HIT_TEXELS = 31u;         // TEXELS HitItem[wave capacity] (BINDING_HITS' memory)
FH_CONST uint BINDING_SHADOW_RAY_TEXELS = 32u;  // TEXELS ShadowRayItem[wave capacity] (BINDING_SHADOW_RAYS' memory)
// The light tree (`--light-sampler tree`, EFFECT_LIGHT_TREE; else one node each): its nodes, and per path the shading
// point whose tree probabilities NEE used, for the MIS weight of the emitter the path's next ray hits (lib/light/light_tree.glsl).
FH_CONST uint BINDING_LIGHT_TREE = 33u;       // TEXELS LightTreeNode[]: interior nodes, then one leaf per tree light
FH_CONST uint BINDING_PATH_LIGHT_POINTS = 34u;  // uvec4[wave capacity]: position bits and packed normal (light_tree.glsl)
// The AOVs (`--aov`, SPEC_AOVS; else one element each): what each path's first non-specular hit showed, and their sums
// per pixel (lib/core/aov.glsl).
FH_CONST uint BINDING_PATH_AOVS = 35u;       // PathAov[wave capacity]
FH_CONST uint BINDING_AOV_FILM = 36u;        // AovPixel[width * height]
// Adaptive sampling (`--adaptive`, SPEC_PIXEL_LIST; else one word each): the film's pixels in the order the waves
// take them, those that get the most samples first (render/adaptive_render.h; a wave's pixel range indexes this list),
// and the work its samples took, per path and summed per pixel, in units of PATH_WORK_* (the pilot's cost per sample).
FH_CONST uint BINDING_PIXEL_LIST = 37u;      // uint[film width * film height]
FH_CONST uint BINDING_PATH_WORK = 38u;       // uint[wave capacity]
FH_CONST uint BINDING_PIXEL_WORK = 39u;      // uint[film width * film height]
// The volumes each light stands in, innermost first (light tracing and BDPT with EFFECT_VOLUME; else one element):
// where its subpaths start (render/light_media.h).
FH_CONST uint BINDING_LIGHT_MEDIA = 40u;       // uvec4[emitter count]: per Emitter entry, as PathMedia
// Vertex merging (`--integrator vcm`; else one element each; shaders/lib/integrator/vertex_merging.glsl): per stored
// light vertex its position and its dvm (LightVertex's slots), per path its subpath's dvm, and the hash grid over the
// wave's light vertices: FrameParams.merge_grid_cells counts, as many cell starts, then the vertices' slots by cell.
FH_CONST uint BINDING_MERGE_POINTS = 41u;      // vec4[wave capacity x light_vertex_slots]: xyz, w = dvm
FH_CONST uint BINDING_PATH_DVM = 42u;          // float[wave capacity]
FH_CONST uint BINDING_MERGE_GRID = 43u;        // uint words
// The white anisotropic GGX lobe's albedo (ggx_anisotropic_albedo_table.glsl) for the anisotropic lobes'
// multiple scattering: with EFFECT_ANISOTROPY and EFFECT_GGX_MULTISCATTER, else one word.
FH_CONST uint BINDING_ANISOTROPIC_ALBEDO = 44u;  // float[]
FH_CONST uint BINDING_COUNT = 45u;
// Measured on DamagedHelmet under the courtyard (tests/bench/RESULTS.md "2026-11-29: adaptive sampling"), from the
// stage seconds of two renders with different mixes: a vertex on a surface (extend and shade) 1.2 us, one whose ray
// escaped 0.28 us, a shadow ray (connect) 0.33 us.
FH_CONST uint PATH_WORK_HIT = 4u;
FH_CONST uint PATH_WORK_ESCAPE = 1u;
FH_CONST uint PATH_WORK_SHADOW_RAY = 1u;
FH_CONST uint TEXEL_BYTES = 16u;             // one RGBA32UI texel of a TEXELS binding

// ---- Specialization constants (constant_id) -------------------------------------------------------------
FH_CONST uint SPEC_DISABLED_TECHNIQUES = 0u;       // TECHNIQUE_* bits switched off (cost measurements only)
FH_CONST uint SPEC_EFFECTS = 1u;                   // EFFECT_* bits: what the scene calls for (scene/effects.h)
FH_CONST uint SPEC_HAS_INSTANCES = 2u;             // bool: two-level BVH (meshes drawn by several nodes)
FH_CONST uint SPEC_SAMPLER = 3u;                   // SAMPLER_*: where a path's random numbers come from
FH_CONST uint SPEC_SORT_RAYS = 4u;                 // bool: the ray sort's stages are built (shade bins what it pushes)
FH_CONST uint SPEC_EFFECTS_2 = 5u;                 // EFFECT2_* bits: the effects beyond the first word's 32
FH_CONST uint SPEC_AOVS = 6u;                      // bool: shade records and accumulate sums the AOVs (`--aov`)
FH_CONST uint SPEC_PIXEL_LIST = 7u;                // bool: a wave's pixels come from BINDING_PIXEL_LIST (`--adaptive`)
FH_CONST uint SPEC_SPLATS_BY_PATH = 8u;            // bool: light subpaths' splats land by film position (motion blur,
                                                    // the Gaussian filter; lib/integrator/light_tracing.glsl)
FH_CONST uint SPEC_CONSTANT_COUNT = 9u;

// ---- Effects (engine/scene/effects.h decides them by value; a stage compiles only the code of those set) ----
FH_CONST uint EFFECT_BASE_COLOR_TEXTURE = 1u;      // some visible material has a baseColorTexture
FH_CONST uint EFFECT_METALLIC_ROUGHNESS_TEXTURE = 2u;
FH_CONST uint EFFECT_NORMAL_TEXTURE = 4u;          // normal mapping
FH_CONST uint EFFECT_EMISSIVE_TEXTURE = 8u;        // textured emitters
FH_CONST uint EFFECT_VERTEX_COLORS = 16u;          // COLOR_0 that is not white
FH_CONST uint EFFECT_ALPHA = 32u;                  // alphaMode MASK or BLEND: tested during traversal
FH_CONST uint EFFECT_ENVIRONMENT = 64u;            // --env / --background: escaping rays see light
FH_CONST uint EFFECT_TRANSMISSION = 128u;          // KHR_materials_transmission: the dielectric BTDF
FH_CONST uint EFFECT_TRANSMISSION_TEXTURE = 256u;  // transmissionTexture
FH_CONST uint EFFECT_VOLUME = 512u;                // KHR_materials_volume: refraction into closed meshes
FH_CONST uint EFFECT_ABSORPTION = 1024u;           // Beer-Lambert absorption inside volumes (path media buffer)
FH_CONST uint EFFECT_CLEARCOAT = 2048u;            // KHR_materials_clearcoat: the coat lobe over the base
FH_CONST uint EFFECT_CLEARCOAT_TEXTURE = 4096u;    // clearcoatTexture, clearcoatRoughnessTexture
FH_CONST uint EFFECT_CLEARCOAT_NORMAL_TEXTURE = 8192u;  // clearcoatNormalTexture
FH_CONST uint EFFECT_UNLIT = 16384u;               // KHR_materials_unlit: base colour to camera rays, black otherwise
FH_CONST uint EFFECT_SHEEN = 32768u;               // KHR_materials_sheen: the Charlie sheen lobe over the base
FH_CONST uint EFFECT_SHEEN_TEXTURE = 65536u;       // sheenColorTexture, sheenRoughnessTexture
FH_CONST uint EFFECT_DIFFUSE_TRANSMISSION = 131072u;          // KHR_materials_diffuse_transmission
FH_CONST uint EFFECT_DIFFUSE_TRANSMISSION_TEXTURE = 262144u;  // its two textures
FH_CONST uint EFFECT_ANISOTROPY = 524288u;         // KHR_materials_anisotropy: anisotropic GGX for the base's specular
FH_CONST uint EFFECT_ANISOTROPY_TEXTURE = 1048576u;  // anisotropyTexture
FH_CONST uint EFFECT_IRIDESCENCE = 2097152u;       // KHR_materials_iridescence: a thin film's Fresnel on the specular
FH_CONST uint EFFECT_IRIDESCENCE_TEXTURE = 4194304u;  // iridescenceTexture, iridescenceThicknessTexture
FH_CONST uint EFFECT_SPECTRAL = 8388608u;          // KHR_materials_dispersion: paths carry four wavelengths (hero
                                                   // wavelength sampling), not RGB; shaders/lib/spectral/spectrum.glsl
FH_CONST uint EFFECT_EMISSIVE_TRIANGLES = 16777216u;  // some triangle emits (NEE picks it; rays that hit it see it)
FH_CONST uint EFFECT_PUNCTUAL_LIGHTS = 33554432u;     // KHR_lights_punctual lights of non-zero power (NEE only)
FH_CONST uint EFFECT_GLASS_MULTISCATTER = 67108864u;  // rough glass: the energy single scattering loses, given
                                                      // back (shaders/lib/bsdf/glass_multiscatter.glsl)
FH_CONST uint EFFECT_SPECULAR = 134217728u;  // the base's GGX reflection (dielectric specular layer, metal): off when
                                             // every visible material is Lambertian (metallic 0, specularFactor 0)
FH_CONST uint EFFECT_THIN_LENS = 268435456u;  // --aperture / --aperture-radius > 0: camera rays from a lens disk or
                                              // polygon, focused on a plane (lib/geometry/camera.glsl); else the pinhole
FH_CONST uint EFFECT_MOTION_BLUR = 536870912u;  // --shutter over which an instance or the camera moves: each path has
                                                // a time, and moving transforms are interpolated (lib/geometry/motion.glsl)
FH_CONST uint EFFECT_LIGHT_TREE = 1073741824u;  // --light-sampler tree: NEE picks lights by their importance at the
                                                // shading point (lib/light/light_tree.glsl), not from the power alias table
FH_CONST uint EFFECT_GGX_MULTISCATTER = 2147483648u;  // --microfacet compensated and a rough metal or specular layer:
                                                      // the energy its GGX loses, given back (lib/bsdf/ggx_multiscatter.glsl)
FH_CONST uint EFFECT_ATTRIBUTES = EFFECT_BASE_COLOR_TEXTURE | EFFECT_METALLIC_ROUGHNESS_TEXTURE |
                                  EFFECT_NORMAL_TEXTURE | EFFECT_EMISSIVE_TEXTURE | EFFECT_VERTEX_COLORS |
                                  EFFECT_ALPHA | EFFECT_TRANSMISSION_TEXTURE | EFFECT_CLEARCOAT_TEXTURE |
                                  EFFECT_CLEARCOAT_NORMAL_TEXTURE | EFFECT_SHEEN_TEXTURE |
                                  EFFECT_DIFFUSE_TRANSMISSION_TEXTURE | EFFECT_IRIDESCENCE_TEXTURE |
                                  EFFECT_ANISOTROPY;  // effects that read TriangleAttributes (anisotropy: tangents)
FH_CONST uint EFFECT_MATERIAL = EFFECT_ATTRIBUTES | EFFECT_TRANSMISSION | EFFECT_VOLUME | EFFECT_ABSORPTION |
                                EFFECT_CLEARCOAT | EFFECT_UNLIT | EFFECT_SHEEN |
                                EFFECT_DIFFUSE_TRANSMISSION | EFFECT_ANISOTROPY |
                                EFFECT_ANISOTROPY_TEXTURE | EFFECT_IRIDESCENCE |
                                EFFECT_IRIDESCENCE_TEXTURE | EFFECT_SPECTRAL |
                                EFFECT_GLASS_MULTISCATTER | EFFECT_SPECULAR |
                                EFFECT_GGX_MULTISCATTER;  // decided by the materials
FH_CONST uint EFFECT_LIGHTS = EFFECT_EMISSIVE_TRIANGLES | EFFECT_PUNCTUAL_LIGHTS;  // decided by the light table
// What --force-effect / --disable-effect may switch (to measure an effect's cost): all but the environment,
// which follows --env / --background.
// Motion blur may be switched off: everything then stands where it is at the shutter's centre.
FH_CONST uint EFFECT_SWITCHABLE = EFFECT_MATERIAL | EFFECT_LIGHTS | EFFECT_MOTION_BLUR;

// ---- Effects of the second word (SPEC_EFFECTS_2; C++ holds them above bit 31 of an EffectBits, scene/effects.h) ----
FH_CONST uint EFFECT2_SPECULAR_TEXTURE = 1u;    // KHR_materials_specular specularTexture (A) / specularColorTexture
                                                // (RGB, sRGB), and the specular colour of a specular-glossiness map
FH_CONST uint EFFECT2_GLOSSINESS_TEXTURE = 2u;  // KHR_materials_pbrSpecularGlossiness: roughness = 1 - glossiness from
                                                // the specular colour texture's alpha (MATERIAL_GLOSSINESS_IN_ALPHA)
FH_CONST uint EFFECT2_ATTRIBUTES = EFFECT2_SPECULAR_TEXTURE | EFFECT2_GLOSSINESS_TEXTURE;  // read TriangleAttributes
FH_CONST uint EFFECT2_SWITCHABLE = EFFECT2_ATTRIBUTES;  // all decided by the materials

// ---- Robustness techniques (all on by default; `--disable-technique` turns one off to measure its cost and
// to show what goes wrong without it). tests/README.md "Numerical stability" has the table.
FH_CONST uint TECHNIQUE_WATERTIGHT = 1u;        // Woop et al. 2013 triangle test (off: Moller-Trumbore 1997)
FH_CONST uint TECHNIQUE_CONSERVATIVE_BOX = 2u;  // padded slab test without 0 x inf (off: plain slab test)
FH_CONST uint TECHNIQUE_ERROR_OFFSETS = 4u;     // error-bound ray origins (off: fixed epsilon along the normal)
FH_CONST uint TECHNIQUE_FINITE_GUARD = 8u;      // non-finite samples dropped before the film (off: added)
FH_CONST uint TECHNIQUE_EXACT_FILM = 16u;       // fixed-point film sums, exact and associative (off: plain float sums)
FH_CONST uint TECHNIQUE_TIE_BREAK = 32u;        // equal-t hits resolved by scene triangle index (off: visit order)
FH_CONST uint TECHNIQUE_REBASE = 64u;           // host: render space centred on the scene (off: world space)

// ---- Constants -----------------------------------------------------------------------------------------
FH_CONST uint INVALID_INDEX = 0xffffffffu;
FH_CONST uint CAMERA_PERSPECTIVE = 0u;
FH_CONST uint CAMERA_ORTHOGRAPHIC = 1u;
FH_CONST uint FILTER_BOX = 0u;             // one pixel wide
FH_CONST uint FILTER_GAUSSIAN = 1u;        // truncated Gaussian, importance sampled (weight 1)
FH_CONST uint SAMPLER_INDEPENDENT = 0u;    // each path's own PCG stream (lib/sampling/rng.glsl)
FH_CONST uint SAMPLER_SOBOL = 1u;          // Owen-scrambled Sobol', four dimensions per block (lib/sampling/sobol.glsl)
FH_CONST uint INTEGRATOR_PATH = 0u;        // FH_INTEGRATOR (lib/core/bindings.glsl): path tracing (NEE and MIS)
FH_CONST uint INTEGRATOR_LIGHT = 1u;       // light tracing: the t = 1 strategies alone
FH_CONST uint INTEGRATOR_BDPT = 2u;        // bidirectional path tracing, every (s, t) combined by MIS
FH_CONST uint INTEGRATOR_VCM = 3u;         // vertex connection and merging: BDPT's strategies and merges, by MIS
FH_CONST uint PATH_MIS_LIGHT_AT_INFINITY = 1u;  // PathMis.flags: the light subpath left a directional light or the
                                                // environment (its first segment has no distance to convert)
FH_CONST uint PATH_MIS_TREE_LIGHT_SHIFT = 8u;   // PathMis.flags >> this: EFFECT_LIGHT_TREE, the light subpath's tree light
                                                // (Emitter entry + 1; 0: none), whose NEE density its first hit folds in
FH_CONST uint MATERIAL_DOUBLE_SIDED = 1u;  // Material.flags
FH_CONST uint MATERIAL_UNLIT = 2u;         // Material.flags: KHR_materials_unlit (EFFECT_UNLIT)
FH_CONST uint MATERIAL_GLOSSINESS_IN_ALPHA = 4u;  // Material.flags: specular_color_texture's alpha is glossiness
                                                  // (KHR_materials_pbrSpecularGlossiness; EFFECT2_GLOSSINESS_TEXTURE)
FH_CONST uint PATH_SECONDARIES_TERMINATED = 1u;  // PathSpectrum.flags: only the hero wavelength goes on
FH_CONST uint LAYERS_VOLUME = 1u;          // MaterialLayers.flags: the mesh bounds a volume (thicknessFactor > 0)
FH_CONST uint TRIANGLE_HAS_NORMALS = 1u;   // TriangleShading.flags: vertex normals present
// TriangleShading.flags bits 8-31 with EFFECT_LIGHT_TREE: the triangle's Emitter entry + 1 (0: not in the light tree).
FH_CONST uint TRIANGLE_LIGHT_SHIFT = 8u;
FH_CONST uint MAX_TREE_LIGHTS = 1u << 24u;  // entries that fit in those bits (--light-sampler tree refuses more)
FH_CONST uint LIGHT_NODE_LEAF = 1u;        // LightTreeNode.flags: one light (else two children)
FH_CONST uint LIGHT_NODE_TWO_SIDED = 2u;   // LightTreeNode.flags: emits on both sides of its normals' cone
FH_CONST uint LIGHT_TREE_MAX_DEPTH = 32u;  // levels below the root: a leaf's path fits in one word
FH_CONST uint TRIANGLE_ALPHA_TESTED = 1u;  // TrianglePositions.flags: its material is not ALPHA_OPAQUE (EFFECT_ALPHA)
FH_CONST uint RENDER_NEE = 1u;             // FrameParams.flags: next-event estimation
FH_CONST uint RENDER_MIS = 2u;             // combine NEE and BSDF sampling by MIS (else NEE only)
FH_CONST uint RENDER_RR = 4u;              // Russian roulette
FH_CONST uint RENDER_LIGHT_PICK_REUSE = 8u;  // NEE picks the light with its point's 2D sample (lights.glsl)
FH_CONST uint BVH_LEAF_COUNT_BITS = 16u;   // BvhNode.count_and_axis: low bits count, high bits axis
FH_CONST uint BVH_WIDTH = 4u;              // children per BvhWideNode
// The largest coordinate (render space: the scene's triangles and bounds, cameras, lights) the GPU's box tests are
// exact for (intersect.glsl make_safe_inverse_dir); the host refuses a scene or camera beyond it.
FH_CONST float MAX_RENDER_COORDINATE = 1e29f;
FH_CONST uint WIDE_COUNT_BITS = 4u;        // a BvhWideNode slot's kind, and a traversal stack entry: index << 4 | kind
FH_CONST uint WIDE_MAX_LEAF = 13u;         // kinds 1 .. 13: a leaf of that many triangles (0: a wide node)
FH_CONST uint WIDE_INSTANCE_COUNT = 14u;   // the kind of a top-level leaf (index = Instance)
FH_CONST uint WIDE_NO_CHILD = 15u;         // the kind of an empty slot
FH_CONST uint WIDE_KIND_SHIFT = 24u;       // BvhWideNode.exponents and .first_node: two slots' kinds in bits 24-31
FH_CONST uint WIDE_MAX_FIRST_NODE = 0xffffffu;  // BvhWideNode.first_node's index bits
FH_CONST uint WIDE_MAX_INDEX = 0x3fffffeu; // the largest triangle or Instance index a child names (the loader's 2^26)
FH_CONST uint TRAVERSAL_STACK_SIZE = 96u;  // entries; the host checks that a BVH never needs more (wide_bvh.h)
FH_CONST uint PUNCTUAL_LIGHT_BIT = 0x80000000u;  // Emitter.light: set = PunctualLight index, clear = triangle
FH_CONST uint ENVIRONMENT_LIGHT = 0x7fffffffu;  // Emitter.light: the environment (EFFECT_ENVIRONMENT)
FH_CONST uint ALPHA_OPAQUE = 0u;           // Material.alpha_mode (glTF alphaMode)
FH_CONST uint ALPHA_MASK = 1u;             // opaque where alpha >= alpha_cutoff, else absent
FH_CONST uint ALPHA_BLEND = 2u;            // present with probability alpha (stochastic, unbiased)
FH_CONST uint WRAP_REPEAT = 0u;            // TextureSlot.addressing bits 0-1 (s) and 2-3 (t)
FH_CONST uint WRAP_CLAMP_TO_EDGE = 1u;
FH_CONST uint WRAP_MIRRORED_REPEAT = 2u;
FH_CONST uint SAMPLER_NEAREST = 16u;       // TextureSlot.addressing: nearest texel (else bilinear)
FH_CONST uint SAMPLER_SRGB = 32u;          // TextureSlot.addressing: texels are sRGB-encoded colour
FH_CONST uint SAMPLER_TEXCOORD_1 = 64u;    // TextureSlot.addressing: read TEXCOORD_1 (else TEXCOORD_0)
FH_CONST uint LIGHT_POINT = 0u;            // PunctualLight.type
FH_CONST uint LIGHT_SPOT = 1u;
FH_CONST uint LIGHT_DIRECTIONAL = 2u;


// ---- Scene ---------------------------------------------------------------------------------------------
// One node of the linear BVH (pbrt-v4 LinearBVHNode, 32 bytes). Interior nodes: first child is the next
// node, `child_or_first` is the second child; leaves: `child_or_first` is the first triangle.
struct BvhNode {
    float min_x, min_y, min_z;
    uint child_or_first;
    float max_x, max_y, max_z;
    uint count_and_axis;  // triangle count (0 = interior) | split axis << BVH_LEAF_COUNT_BITS
};

// What the GPU traverses: a 4-wide BVH with quantised child boxes, 48 bytes (three texels) for four children where
// two-child nodes of full floats took 128 (Ylitie et al. 2017, "Efficient Incoherent Ray Traversal on GPUs Through
// Compressed Wide BVHs", with four children). One visit tests four boxes: half the visits and half the node words of
// the binary tree (scene/bvh/wide_bvh.h collapses the binary BVH into it).
// Child k's box along an axis is [origin + lo * step, origin + hi * step] with lo, hi byte k of lo_x.. / hi_x..
// and step = 2^(exponent - 127), rounded outwards on the host so that the float sums the shader computes contain the
// child's exact box. Each slot has a 4-bit kind: 0 another wide node, 1 .. WIDE_MAX_LEAF a leaf of that many
// triangles, WIDE_INSTANCE_COUNT a top-level leaf (one Instance), WIDE_NO_CHILD none. Indices are implicit, as in
// Ylitie et al.: a node's interior children are consecutive nodes from first_node on, its leaves' triangles (or
// instances) consecutive from first_leaf on, both in slot order; so the host orders the triangles and instances
// by wide node (wide_bvh.h WideBvh::leaf_order). Traversal pushes a child as one word, index << WIDE_COUNT_BITS |
// kind. Indices stay below 2^26 (WIDE_MAX_INDEX; nodes below 2^24): the loader refuses more than 2^26 triangles,
// lavapipe's texel buffers (2^27 texels of 16 bytes; a triangle takes 3, a node 3) end sooner, and the host checks
// every index (wide_bvh.cpp).
struct BvhWideNode {
    float origin_x, origin_y, origin_z;
    uint exponents;  // the step's biased float exponent per axis: x in bits 0-7, y 8-15, z 16-23; kinds of slots 0, 1
    uint lo_x, lo_y, lo_z;  // byte k: child k's low corner, in steps above origin
    uint hi_x, hi_y, hi_z;  // byte k: its high corner
    uint first_node;  // bits 0-23: the first interior child; kinds of slots 2, 3 in bits 24-31
    uint first_leaf;  // the first triangle (top level: Instance) of the leaf children
};

// One placement of a mesh in a two-level BVH (SPEC_HAS_INSTANCES): a top-level leaf (kind WIDE_INSTANCE_COUNT) enters
// the mesh's own BVH with the ray mapped to object space. Rows of 3x4 affine maps; render space is world space
// minus Scene::origin. Normals go to render space by the transpose of object_from_render's linear part.
struct Instance {
    vec4 object_from_render_0, object_from_render_1, object_from_render_2;
    vec4 render_from_object_0, render_from_object_1, render_from_object_2;
    uint root_node;         // the mesh BVH's root BvhWideNode
    uint first_triangle;    // the mesh's triangles (TrianglePositions order) start here
    uint material;          // replaces the triangles' material (meshes sharing geometry), else INVALID_INDEX
    // Motion blur: INVALID_INDEX for an instance that stands still; else the first of FrameParams.motion_segments + 1
    // Instance records (past those the BVH names) whose render_from_object rows hold its transform at shutter times
    // k / motion_segments; between two, it moves linearly (lib/geometry/motion.glsl). The rows above are then its transform
    // at the shutter's centre on that path.
    uint motion;
};
// World-space vertex positions of one triangle; only these are read during traversal (9 words). Padded to
// 48 bytes: three whole texels.
struct TrianglePositions {
    float p0_x, p0_y, p0_z;
    float p1_x, p1_y, p1_z;
    float p2_x, p2_y, p2_z;
    uint source_index;  // the triangle's index in scene order: equal-t hits go to the lowest (BVH-independent)
    uint flags;         // TRIANGLE_ALPHA_TESTED: a hit on it waits for the material's coverage (traverse.glsl)
    float pad;
};

// What the shade stage needs of a hit triangle besides its positions.
struct TriangleShading {
    float n0_x, n0_y, n0_z;  // world-space vertex normals (valid when flags & TRIANGLE_HAS_NORMALS)
    float n1_x, n1_y, n1_z;
    float n2_x, n2_y, n2_z;
    uint material;
    uint flags;
    float light_pdf_area;  // probability of picking this triangle as a light / its area (0: not an emitter)
};

// glTF 2.0 metallic-roughness material. Each *_texture is a TextureSlot index (INVALID_INDEX: none) whose
// texel multiplies the factor, as the glTF spec says.
struct Material {
    vec4 base_color;        // rgb linear, a = alpha
    vec4 emission;          // rgb radiance = emissiveFactor * emissiveStrength, a unused
    vec4 specular_color;    // KHR_materials_specular: rgb = specularColorFactor, a = specularFactor
    float metallic;
    float roughness;        // perceptual; alpha = roughness^2
    float ior;              // KHR_materials_ior (1.5 by default)
    uint flags;             // MATERIAL_DOUBLE_SIDED, MATERIAL_UNLIT, MATERIAL_GLOSSINESS_IN_ALPHA
    uint base_color_texture;
    uint metallic_roughness_texture;
    uint normal_texture;
    uint emissive_texture;
    uint alpha_mode;        // ALPHA_OPAQUE / ALPHA_MASK / ALPHA_BLEND
    float alpha_cutoff;     // MASK: present where alpha >= alpha_cutoff
    uint specular_texture;        // KHR_materials_specular specularTexture (A: specularFactor), or INVALID_INDEX
    uint specular_color_texture;  // specularColorTexture (RGB, sRGB), or INVALID_INDEX
};

// What the KHR material extensions add to a Material (same index), in its own array so that a scene whose
// materials use none of them never reads it: each effect reads only its own fields.
struct MaterialLayers {
    vec4 attenuation;              // KHR_materials_volume: rgb = absorption coefficient per scene unit,
                                   // -ln(attenuationColor) / attenuationDistance (0: none), a unused
    vec4 sheen;                    // KHR_materials_sheen: rgb = sheenColorFactor, a = sheenRoughnessFactor
    vec4 diffuse_transmission;     // KHR_materials_diffuse_transmission: rgb = diffuseTransmissionColorFactor,
                                   // a = diffuseTransmissionFactor
    float transmission;            // KHR_materials_transmission transmissionFactor
    uint transmission_texture;     // TextureSlot (R channel), or INVALID_INDEX
    uint flags;                    // LAYERS_VOLUME
    float clearcoat;               // KHR_materials_clearcoat clearcoatFactor
    float clearcoat_roughness;     // clearcoatRoughnessFactor (perceptual; alpha = roughness^2)
    uint clearcoat_texture;        // TextureSlot (R channel), or INVALID_INDEX
    uint clearcoat_roughness_texture;  // TextureSlot (G channel), or INVALID_INDEX
    uint clearcoat_normal_texture;     // TextureSlot (its scale in the slot), or INVALID_INDEX
    uint sheen_color_texture;          // TextureSlot (RGB, sRGB), or INVALID_INDEX
    uint sheen_roughness_texture;      // TextureSlot (A channel), or INVALID_INDEX
    uint diffuse_transmission_texture;        // TextureSlot (A channel), or INVALID_INDEX
    uint diffuse_transmission_color_texture;  // TextureSlot (RGB, sRGB), or INVALID_INDEX
    float anisotropy_strength;     // KHR_materials_anisotropy anisotropyStrength
    float anisotropy_cos;          // cos and sin of anisotropyRotation (counter-clockwise from the tangent)
    float anisotropy_sin;
    uint anisotropy_texture;       // TextureSlot (RG: direction, B: strength; linear), or INVALID_INDEX
    float iridescence;             // KHR_materials_iridescence iridescenceFactor (0 also where the film is 0 nm thick)
    float iridescence_ior;         // iridescenceIor: the film's index of refraction
    float iridescence_thickness_min;  // iridescenceThicknessMinimum, nm (thickness texture G = 0)
    float iridescence_thickness_max;  // iridescenceThicknessMaximum, nm (G = 1, or no texture)
    uint iridescence_texture;      // TextureSlot (R channel: strength), or INVALID_INDEX
    uint iridescence_thickness_texture;  // TextureSlot (G channel: thickness), or INVALID_INDEX
    float iridescence_albedo_f0;   // the film's Fresnel bound F <= a (1 - (1 - cos)^5) + b (1 - cos)^5: a,
    float iridescence_albedo_f90;  // and b (scene/thin_film_bound.h)
    float dispersion;              // KHR_materials_dispersion: 20 / Abbe number (0: none); volumes only
    float pad0, pad1, pad2;
};

// A material's use of a texture (glTF textureInfo): which image, how it is addressed, and
// KHR_texture_transform as two rows of a 2x3 matrix: uv' = (dot(transform_u.xyz, (u, v, 1)), dot(transform_v...)).
struct TextureSlot {
    vec4 transform_u;
    vec4 transform_v;
    uint image;             // TextureImage index
    uint addressing;        // WRAP_* of s | WRAP_* of t << 2 | SAMPLER_* bits
    float scale;            // normalTexture.scale (1 for other slots)
    uint pad;
};

// One decoded image: width x height RGBA8 texels (one uint each, r in the low byte) from texel_offset on.
struct TextureImage {
    uint texel_offset;
    uint width;
    uint height;
    uint pad;
};

// Per-triangle vertex attributes for textures and vertex colours (BVH leaf order, like TriangleShading).
// Tangents (TANGENT, world space, w = bitangent sign; w = 0 when the mesh has none) and COLOR_0 are stored as
// half floats, two per word (packHalf2x16: x in the low half).
struct TriangleAttributes {
    vec4 uv0_c01;           // TEXCOORD_0 at corners 0 and 1: (u0, v0, u1, v1)
    vec4 uv0_c2_uv1_c0;     // TEXCOORD_0 at corner 2, TEXCOORD_1 at corner 0
    vec4 uv1_c12;           // TEXCOORD_1 at corners 1 and 2
    uint color0_rg, color0_ba, color1_rg, color1_ba, color2_rg, color2_ba;
    uint tangent0_xy, tangent0_zw, tangent1_xy, tangent1_zw, tangent2_xy, tangent2_zw;
};

// One entry of the alias table over every light: emissive triangles and punctual lights (Walker 1977;
// Vose 1991).
struct Emitter {
    uint light;             // triangle index (TrianglePositions order), or PUNCTUAL_LIGHT_BIT | PunctualLight index
    float alias_threshold;  // keep this entry if u < threshold, else take `alias`
    uint alias;
    float pick_pdf;         // probability of picking this light (power / total power)
};

// A node of the light tree over the lights that have a place (emissive triangles, point and spot lights; Conty
// Estevez & Kulla 2018, pbrt-v4's BVHLightSampler): what bounds the light of everything below it, from which NEE
// weighs the two children of a node at a shading point (lib/light/light_tree.glsl light_importance). Nodes are
// [interior nodes in depth-first order, root at 0][one leaf per tree light, leaf k = node (tree lights - 1) + k for
// Emitter entry k]; a tree of one light is its leaf alone. Built on the host (scene/light/light_tree.h).
struct LightTreeNode {
    float min_x, min_y, min_z;
    float power;            // emitted power of the lights below (the alias table's weight)
    float max_x, max_y, max_z;
    float cos_theta_o;      // every emitting normal lies within theta_o of the axis
    float axis_x, axis_y, axis_z;
    float cos_theta_e;      // and emits within theta_e beyond it (pi/2 for a surface, the falloff for a spot)
    uint child0;            // interior: the children's node indices; leaf: child0 = the path from the root (bit k set:
    uint child1;            // the second child at level k), child1 = the leaf's depth
    uint flags;             // LIGHT_NODE_LEAF, LIGHT_NODE_TWO_SIDED
    uint emitter;           // leaf: its Emitter entry
};

// A KHR_lights_punctual light placed in world space. Intensities are taken as the scene's radiometric units:
// point and spot lights give radiant intensity (radiance-units x m^2), directional lights irradiance.
struct PunctualLight {
    vec4 position;          // xyz (point, spot)
    vec4 direction;         // xyz: unit direction the light travels (spot axis; directional light)
    vec4 intensity;         // rgb = color * intensity
    uint type;              // LIGHT_POINT / LIGHT_SPOT / LIGHT_DIRECTIONAL
    float cos_inner;        // spot: full intensity inside this cone
    float cos_outer;        // spot: none outside this cone
    float pad;
};

// ---- Per-render parameters (uploaded once per render) ----------------------------------------------------
struct FrameParams {
    vec4 camera_origin;     // xyz world position
    vec4 camera_right;      // xyz: world right, scaled so that NDC x = 1 maps to it (at unit distance)
    vec4 camera_up;         // xyz: world up, scaled likewise for NDC y = 1
    vec4 camera_forward;    // xyz: world view direction (unit)
    vec4 scene_min;         // xyz: scene bounds (for offsets and diagnostics)
    vec4 scene_max;
    uint width;
    uint height;
    uint max_depth;         // segments after the camera; 0 = unlimited
    uint seed;
    uint camera_type;       // CAMERA_PERSPECTIVE / CAMERA_ORTHOGRAPHIC
    uint filter_type;       // FILTER_BOX / FILTER_GAUSSIAN
    float filter_radius;    // pixels (Gaussian: truncation radius; sigma = radius / 3)
    uint flags;             // RENDER_NEE | RENDER_MIS | RENDER_RR | RENDER_LIGHT_PICK_REUSE
    uint emitter_count;
    uint rr_start_depth;    // Russian roulette starts at this segment count
    uint wave_capacity;     // paths per wave = length of PathState, HitItem, ShadowRayItem; half of RayItem
    uint triangle_count;
    // Environment (EFFECT_ENVIRONMENT): an equirectangular map, +Y up (mapping: shaders/lib/light/environment.glsl).
    uint env_width;
    uint env_height;
    float env_rotation;     // radians about +Y (--env-rotation)
    float env_pick_pdf;     // probability that NEE picks the environment
    // Thin lens (EFFECT_THIN_LENS): the aperture in render units, the distance of the plane in focus along the view
    // direction, the blades of a polygonal aperture (0: a disk) and its rotation in radians.
    float lens_radius;
    float focus_distance;
    uint aperture_blades;
    float aperture_rotation;
    // Motion blur (EFFECT_MOTION_BLUR): the camera above stands where it is at the shutter's centre; at shutter time s
    // its origin moves by (s - 1/2) x camera_motion_translation.xyz and its axes turn by (s - 1/2) x
    // camera_motion_rotation.w radians about the unit axis camera_motion_rotation.xyz (open to close).
    vec4 camera_motion_translation;
    vec4 camera_motion_rotation;
    uint motion_segments;   // moving instances move linearly over this many equal parts of the shutter (Instance)
    // The film covers pixels [crop_x, crop_x + film_width) x [crop_y, crop_y + film_height) of the width x height
    // image (--crop; else all of it). Film pixel p is image pixel (crop_y + p / film_width, crop_x + p % film_width).
    uint crop_x, crop_y, film_width, film_height;
    // The volumes (material indices) the camera stands in, innermost first, where paths start
    // (render/camera/camera_medium.h); INVALID_INDEX past the last: outside every volume, and always without EFFECT_VOLUME.
    uint camera_medium;
    uint camera_medium_outer, camera_medium_outermost;
    // `--integrator bdpt`: light-subpath vertices stored per path (bdpt_depth - 2); `vcm`: bdpt_depth - 1 (a merge at
    // the first camera vertex takes a light vertex one segment short of the path); else 0
    uint light_vertex_slots;
    uint bdpt_strategy;       // --bdpt-strategy: s << 16 | t, that strategy alone and unweighted; 0: all, by MIS
    // Russian roulette keeps a camera path with probability min(0.95, rr_survival_scale x its largest throughput
    // component) (--rr-survival-scale; shade.comp).
    float rr_survival_scale;
    // EFFECT_LIGHT_TREE: Emitter entries [0, light_tree_lights) are the tree's leaves, the rest (the environment,
    // directional lights) are picked uniformly, each as often as the whole tree (lib/light/light_tree.glsl).
    uint light_tree_lights;
    // `--integrator bdpt` and `vcm`: paths of up to this many segments are made by every strategy (the light subpaths
    // stop there); longer ones by the camera subpath's next-event estimation and light hits alone, weighted as path
    // tracing weights them (render/light_tracing.h bdpt_depth). 0 for the other integrators.
    uint bdpt_depth;
    // `--integrator vcm`: the hash grid's cell count (a power of two; BINDING_MERGE_GRID), else 0.
    uint merge_grid_cells;
    // The probability that a light subpath starts on the environment (its Emitter entry's pick_pdf): env_pick_pdf but
    // with EFFECT_LIGHT_TREE, where NEE picks by the tree's rule and light subpaths still by power.
    float env_emission_pick_pdf;
    uint frame_pad2;
};

// Push constants: what changes per wave and per depth.
struct StagePush {
    uint depth;             // segments traced so far (0 while tracing camera rays)
    uint pixel_begin;       // the wave covers pixels [pixel_begin, pixel_begin + pixel_count) (of the pixel list
                            // with SPEC_PIXEL_LIST)
    uint pixel_count;
    uint sample_begin;      // and sample indices [sample_begin, sample_begin + sample_count)
    uint sample_count;
    uint ray_order;         // RAY_ORDER_*: extend takes the queue as it is, or through the sorted order
    uint bin_pushed_rays;   // 1: shade bins the rays it pushes for the next extend's sort (lib/core/ray_order.glsl)
    uint count_handed_shadow_rays;  // 1: advance counts the shadow queue it hands on as traced (connect traces it all)
    uint count_escaped_rays;  // 1: extend counts the rays that left the scene (the ray tracer); 0: shade counts them
    // `--integrator vcm`: the wave's merging radius (it shrinks with the sample index; render/vertex_merging.h)
    float merge_radius;
};

// Ray order for extend (StagePush.ray_order): the queue as shade filled it, or sorted by a key of each ray's direction
// and origin (lib/core/ray_order.glsl): rays that start close and point the same way visit the same BVH nodes, so the 8
// lanes of a SIMD group diverge less (tests/bench/RESULTS.md "Speed", "Ray order").
FH_CONST uint RAY_ORDER_QUEUE = 0u;
FH_CONST uint RAY_ORDER_SORTED = 1u;
FH_CONST uint RAY_SORT_DIRECTION_BITS = 3u;  // per axis of the octahedral map: 8 x 8 direction cells
FH_CONST uint RAY_SORT_ORIGIN_BITS = 3u;     // per axis of the scene's box: 8 x 8 x 8 origin cells, Morton order
FH_CONST uint RAY_SORT_BINS = 1u << (2u * RAY_SORT_DIRECTION_BITS + 3u * RAY_SORT_ORIGIN_BITS);  // 32768 keys
// The keys' prefix sum runs in blocks, one workgroup of RAY_SORT_SCAN_LANES lanes per block (sum_ray_bins, then
// scan_ray_bins): a GPU spreads the scan over its cores, lavapipe over its threads.
FH_CONST uint RAY_SORT_SCAN_LANES = 128u;  // the least maxComputeWorkGroupInvocations Vulkan guarantees
FH_CONST uint RAY_SORT_BINS_PER_LANE = 16u;
FH_CONST uint RAY_SORT_BLOCK_BINS = RAY_SORT_SCAN_LANES * RAY_SORT_BINS_PER_LANE;  // 2048
FH_CONST uint RAY_SORT_BLOCKS = RAY_SORT_BINS / RAY_SORT_BLOCK_BINS;                // 16
// Where the ray-sort buffer's parts start (BINDING_RAY_SORT, in words): the counts, the offsets, the block sums,
// then RAY_SORT_WORDS_PER_RAY arrays of wave-capacity words (key, rank, order) from RAY_SORT_FIXED_WORDS on.
FH_CONST uint RAY_SORT_COUNTS = 0u;
FH_CONST uint RAY_SORT_OFFSETS = RAY_SORT_COUNTS + RAY_SORT_BINS;
FH_CONST uint RAY_SORT_BLOCK_SUMS = RAY_SORT_OFFSETS + RAY_SORT_BINS;
FH_CONST uint RAY_SORT_FIXED_WORDS = RAY_SORT_BLOCK_SUMS + RAY_SORT_BLOCKS;
FH_CONST uint RAY_SORT_WORDS_PER_RAY = 3u;

// ---- Wavefront state -------------------------------------------------------------------------------------
struct DispatchArgs {
    uint x, y, z;
};

// Queue lengths, indirect dispatch sizes and device-side diagnostic counters.
struct QueueCounters {
    uint ray_count[2];          // rays in queue [depth & 1]
    uint shadow_count;          // shadow rays pushed by the current shade
    uint shadow_count_active;   // shadow rays the current connect consumes
    DispatchArgs extend_args;   // indirect dispatch for extend and shade of the next depth
    DispatchArgs connect_args;  // indirect dispatch for connect
    // Diagnostics for the current wave (zeroed by generate, read by the host after each wave).
    uint nonfinite_samples;     // samples whose radiance was NaN/Inf (counted before the guard)
    uint escaped_rays;          // extension rays that left the scene
    uint traced_rays;           // closest-hit rays traced
    uint traced_shadow_rays;    // shadow rays traced
};

// Per-path state, 8 words; index = path id within the wave.
struct PathState {
    float throughput_r, throughput_g, throughput_b;
    float bsdf_pdf;             // solid-angle pdf of the last sampled direction (0: camera or delta)
    float radiance_r, radiance_g, radiance_b;
    uint rng;
};

// What a path carries besides PathState when the scene is rendered spectrally (EFFECT_SPECTRAL): its four
// wavelengths follow from wavelength_u (shaders/lib/spectral/spectrum.glsl); PathState's throughput_r, _g, _b hold the
// throughput at wavelengths 0 (the hero), 1 and 2, and throughput_3 the fourth's.
struct PathSpectrum {
    float wavelength_u;         // in [0, 1): the hero wavelength's sample
    float throughput_3;
    uint flags;                 // PATH_SECONDARIES_TERMINATED
    float pad;
};

// Bidirectional path tracing: what a path carries for the MIS weights of every strategy (the recursive quantities of
// Georgiev 2012, "Implementing vertex connection and merging", for connections only; lib/integrator/bdpt.glsl), and how many of
// its light subpath's vertices are stored.
struct PathMis {
    float dvcm;
    float dvc;
    uint light_vertices;        // stored LightVertex entries of the path's light subpath
    uint flags;                 // PATH_MIS_LIGHT_AT_INFINITY, the tree light above PATH_MIS_TREE_LIGHT_SHIFT
};

// A vertex of a light subpath kept for the camera subpath of the same (pixel, sample) to connect to: where it is
// (the surface is reloaded from the hit), the direction back towards the light, the throughput that reached it, its
// MIS quantities, the refraction ratio of its volumes and, rendered spectrally, the fourth wavelength's throughput and
// whether the subpath dispersed (PATH_SECONDARIES_TERMINATED). 60 bytes.
struct LightVertex {
    float throughput_r, throughput_g, throughput_b;
    float dvcm;
    float to_light_x, to_light_y, to_light_z;
    float dvc;
    uint triangle;
    float b1, b2;
    uint instance;              // the Instance hit, or INVALID_INDEX
    float eta_front;            // a volume's n behind the front face / n in front, by the subpath's volumes; else 1
    float throughput_3;         // EFFECT_SPECTRAL: the throughput at the subpath's fourth wavelength (PathSpectrum's)
    uint spectrum_flags;        // EFFECT_SPECTRAL: PathSpectrum.flags
    uint pad;                   // whole texels: 4 uvec4 loads and stores (make_texel_loaders.py), not 15 words
};

// A ray waiting for its closest hit.
struct RayItem {
    float origin_x, origin_y, origin_z;
    uint path;
    float dir_x, dir_y, dir_z;
    uint origin_triangle;       // the triangle it leaves (INVALID_INDEX: camera ray); see traverse.glsl
};

// Result of the extend stage for the ray at the same queue index.
// Whole texels (BINDING_HIT_TEXELS): shade reads the first without instances, and the compiler drops the second fetch.
struct HitItem {
    float t;
    uint triangle;              // INVALID_INDEX: the ray escaped
    float b1, b2;               // barycentrics of p1 and p2
    uint instance;              // Instance hit (SPEC_HAS_INSTANCES), else INVALID_INDEX
    uint pad0, pad1, pad2;
};

// A shadow ray and the contribution it carries if unoccluded (next-event estimation).
struct ShadowRayItem {
    float origin_x, origin_y, origin_z;
    uint path;
    float dir_x, dir_y, dir_z;
    float t_max;
    float contrib_r, contrib_g, contrib_b;
    uint origin_triangle;       // the triangle it leaves
};

// Accumulated film pixel: per channel the sum of the samples' radiance in fixed point, radiance x 2^FILM_FRACTION_BITS
// rounded to the nearest integer, as a 128-bit two's complement integer (FILM_WORDS words, least significant first).
// Integer sums are associative, so parts of a render (sample ranges, resumed runs, machines) add up to the same bits
// in any order (shaders/lib/core/film.glsl, engine/render/film.h). A sample must have |radiance| < 2^FILM_MAX_LOG2 to be
// added: 2^24 samples of that fit with the sign bit to spare.
FH_CONST uint FILM_WORDS = 4u;
FH_CONST int FILM_FRACTION_BITS = 56;
FH_CONST int FILM_MAX_LOG2 = 47;
// A sum of -2^127 (only this top word set), which no samples reach: the pixel a non-finite sample reached with the
// finite guard off; it reads as NaN.
FH_CONST uint FILM_NAN_TOP_WORD = 0x80000000u;

// The AOVs of one path (`--aov`, lib/core/aov.glsl): at its first non-specular hit (a surface that is not a smooth
// mirror or glass) the surface's base colour and its shading normal (world space, towards the camera); at its first
// hit the distance from the camera. Zero where the path escaped first. 32 bytes.
struct PathAov {
    float albedo_r, albedo_g, albedo_b;
    float depth;                // distance along the camera ray to the first hit
    float normal_x, normal_y, normal_z;
    uint flags;                 // AOV_CAPTURED, AOV_HIT
};
FH_CONST uint AOV_CAPTURED = 1u;  // albedo and normal are set (a non-specular surface was reached)
FH_CONST uint AOV_HIT = 2u;       // the camera ray hit a surface (depth is set)
// A surface whose every lobe is GGX at most this alpha (roughness 0.1) and that has no diffuse part passes the AOVs on
// to what it reflects or refracts (Intel Open Image Denoise's advice for mirrors and glass).
FH_CONST float AOV_SPECULAR_ALPHA = 0.01f;

// The AOVs' sums per pixel, exact like the film's (same fixed point, FILM_WORDS words each): albedo, normal, the
// depth of the samples that hit something and how many did.
struct AovPixel {
    uint albedo_r[FILM_WORDS];
    uint albedo_g[FILM_WORDS];
    uint albedo_b[FILM_WORDS];
    uint normal_x[FILM_WORDS];
    uint normal_y[FILM_WORDS];
    uint normal_z[FILM_WORDS];
    uint depth[FILM_WORDS];
    uint hit_count;
};
struct FilmPixel {
    uint sum_r[FILM_WORDS];
    uint sum_g[FILM_WORDS];
    uint sum_b[FILM_WORDS];
    uint sample_count;
};

#ifdef __cplusplus
}  // namespace fh::gpu
#endif
#undef FH_CONST
#endif
