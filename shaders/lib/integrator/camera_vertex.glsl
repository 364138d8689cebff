// A camera subpath's vertex y at a queued ray's hit, as the stages that join it to light vertices see it after extend
// and before shade moves the path on (connect_subpaths.comp, merge.comp): the throughput up to y (Beer-Lambert along
// the segment included; a dispersive y stops the secondary wavelengths, as shade will), the BSDF for the eye's side,
// the volumes y stands in, and the subpath's MIS quantities with the segment to y accounted.
#ifndef FH_CAMERA_VERTEX_GLSL
#define FH_CAMERA_VERTEX_GLSL
#include "lib/bsdf/surface_bsdf.glsl"
#include "lib/integrator/bdpt.glsl"
#include "lib/spectral/path_color.glsl"

struct CameraVertex {
    PathState state;
    vec4 beta;               // spectral: at the path's four wavelengths (path_color.glsl); else RGB in xyz
    SpectralFrame spectral;
    uint spectrum_flags;     // PathSpectrum.flags, with y's dispersion
    vec3 wo;                 // from y back along the ray
    float time;              // both subpaths' shutter time (motion blur)
    ShadingPoint y;
    bool front;              // wo is on y's front side
    uvec4 media;             // the volumes on wo's side of y, innermost first
    SurfaceBsdf at_y;
    PathMis mis;             // at y
};

// False where y sends nothing back along wo: a grazing ray, a black throughput, an unlit surface (black to all but
// the camera's own ray). mis: the path's quantities as loaded; segments: the camera segments up to y.
bool load_camera_vertex(RayItem ray, HitItem hit, PathMis mis, uint segments, out CameraVertex c) {
    uint path = ray.path;
    c.state = load_path_state(path);
    c.beta = vec4(c.state.throughput_r, c.state.throughput_g, c.state.throughput_b, 0.0f);
    c.spectrum_flags = 0u;
    if (effect_on(EFFECT_SPECTRAL)) {
        PathSpectrum spectrum = path_spectra[path];
        c.beta.w = spectrum.throughput_3;
        c.spectrum_flags = spectrum.flags;
        c.spectral = make_spectral_frame(spectrum.wavelength_u);
    }
    c.wo = -vec3(ray.dir_x, ray.dir_y, ray.dir_z);
    c.time = load_path_time(path);
    c.y = load_shading_point(hit.triangle, hit.b1, hit.b2, hit.instance, c.time);
    c.front = dot(c.y.s.ng, c.wo) > 0.0f;
    c.media = tracks_media() ? path_media[path] : uvec4(INVALID_INDEX);
    if (disperse_at(c.y, c.spectral.lambda.x) && (c.spectrum_flags & PATH_SECONDARIES_TERMINATED) == 0u) {
        c.beta = terminate_secondary_wavelengths(c.beta);
        c.spectrum_flags |= PATH_SECONDARIES_TERMINATED;
    }
    set_media(c.y, c.media, c.front);
    if (effect_on(EFFECT_ABSORPTION)) c.beta *= eval_path_medium_transmittance(c.spectral, c.media.x, hit.t);
    c.at_y = make_surface_bsdf(c.y, c.wo);
    c.mis = mis;
    float cos_wo = dot(c.wo, c.at_y.ng);
    bool unlit = effect_on(EFFECT_UNLIT) && (c.y.m.flags & MATERIAL_UNLIT) != 0u;
    if (!(cos_wo > 0.0f) || !(max_path_component(c.beta) > 0.0f) || unlit) return false;
    account_segment(c.mis, hit.t, cos_wo, camera_segment_has_distance(segments));
    return true;
}
#endif
