// Resolves the command line's thin lens onto the camera; the focus ray goes through the extend stage itself.
#include "render/camera/lens.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "render/camera/camera_setup.h"
#include "render/ray_tracer.h"

namespace fh {

double focal_length(const SceneCamera& camera, double sensor_height_mm) {
    return 0.5 * sensor_height_mm * 1e-3 / std::tan(0.5 * camera.yfov);
}

double resolve_aperture_radius(const SceneCamera& camera, const LensSettings& lens) {
    if (lens.f_number <= 0.0) return lens.aperture_radius;
    if (camera.orthographic)
        throw std::invalid_argument("--aperture (an f-number) needs a perspective camera: an orthographic one has no "
                                    "focal length; give --aperture-radius instead");
    return focal_length(camera, lens.sensor_height_mm) / (2.0 * lens.f_number);
}

double find_focus_distance(const vk::Context& context, const PackedScene& scene, const SceneCamera& camera,
                           uint32_t width, uint32_t height, double pixel_x, double pixel_y) {
    SceneCamera pinhole = camera;
    pinhole.aperture_radius = 0.0;
    gpu::FrameParams frame{};
    set_frame_camera(frame, pinhole, width, height, scene.origin);
    // As lib/geometry/camera.glsl makes the pinhole's ray (in double here: one ray).
    const double ndc_x = 2.0 * pixel_x / double(width) - 1.0, ndc_y = 1.0 - 2.0 * pixel_y / double(height);
    const glm::dvec3 right(frame.camera_right), up(frame.camera_up), forward(frame.camera_forward);
    glm::dvec3 origin(frame.camera_origin), dir = forward;
    if (camera.orthographic) origin += ndc_x * right + ndc_y * up;
    else dir = glm::normalize(forward + ndc_x * right + ndc_y * up);
    gpu::RayItem ray{float(origin.x), float(origin.y), float(origin.z), 0u,
                     float(dir.x),    float(dir.y),    float(dir.z),    gpu::INVALID_INDEX};
    RayTracer tracer(context, scene, 1);
    const TracedRays traced = tracer.trace({ray});
    const gpu::HitItem& hit = traced.hits.at(0);
    if (hit.triangle == gpu::INVALID_INDEX) {
        char text[160];
        std::snprintf(text, sizeof text, "the ray through pixel %.6g,%.6g meets no surface to focus on; give "
                      "--focus-distance or --focus-on another pixel", pixel_x, pixel_y);
        throw std::runtime_error(text);
    }
    return double(hit.t) * glm::dot(dir, forward);
}

SceneCamera apply_lens(const vk::Context& context, const PackedScene& scene, SceneCamera camera,
                       const RenderSettings& settings) {
    const LensSettings& lens = settings.lens;
    if (!lens.on()) return camera;
    camera.aperture_radius = resolve_aperture_radius(camera, lens);
    camera.aperture_blades = lens.blades;
    camera.aperture_rotation = lens.rotation_degrees * 3.14159265358979323846 / 180.0;
    if (lens.focus_distance > 0.0) {
        camera.focus_distance = lens.focus_distance;
    } else {
        if (lens.focus_on_given && !(lens.focus_on[0] >= 0.0 && lens.focus_on[0] < settings.width &&
                                     lens.focus_on[1] >= 0.0 && lens.focus_on[1] < settings.height))
            throw std::invalid_argument("--focus-on " + std::to_string(lens.focus_on[0]) + "," +
                                        std::to_string(lens.focus_on[1]) + " is outside the " +
                                        std::to_string(settings.width) + "x" + std::to_string(settings.height) + " image");
        const double x = lens.focus_on_given ? lens.focus_on[0] + 0.5 : 0.5 * settings.width;
        const double y = lens.focus_on_given ? lens.focus_on[1] + 0.5 : 0.5 * settings.height;
        camera.focus_distance = find_focus_distance(context, scene, camera, settings.width, settings.height, x, y);
    }
    return camera;
}

std::string describe_lens(const LensSettings& lens) {
    if (!lens.on()) return "pinhole";
    char text[256];
    std::string out;
    if (lens.f_number > 0.0) std::snprintf(text, sizeof text, "f/%.9g sensor %.9g mm", lens.f_number, lens.sensor_height_mm);
    else std::snprintf(text, sizeof text, "radius %.9g", lens.aperture_radius);
    out = text;
    if (lens.focus_distance > 0.0) std::snprintf(text, sizeof text, ", focus %.9g", lens.focus_distance);
    else if (lens.focus_on_given) std::snprintf(text, sizeof text, ", focus-on %.9g,%.9g", lens.focus_on[0], lens.focus_on[1]);
    else std::snprintf(text, sizeof text, ", focus on the centre");
    out += text;
    if (lens.blades >= 3) {
        std::snprintf(text, sizeof text, ", %u blades rotated %.9g deg", lens.blades, lens.rotation_degrees);
        out += text;
    }
    return out;
}

std::string format_lens_options(const LensSettings& lens) {
    if (!lens.on()) return "";
    char text[256];
    std::string out;
    if (lens.f_number > 0.0) {
        std::snprintf(text, sizeof text, "--aperture %.9g", lens.f_number);
        out = text;
        if (lens.sensor_height_mm != LensSettings{}.sensor_height_mm) {
            std::snprintf(text, sizeof text, " --sensor-height %.9g", lens.sensor_height_mm);
            out += text;
        }
    } else {
        std::snprintf(text, sizeof text, "--aperture-radius %.9g", lens.aperture_radius);
        out = text;
    }
    if (lens.focus_distance > 0.0) std::snprintf(text, sizeof text, " --focus-distance %.9g", lens.focus_distance);
    else if (lens.focus_on_given) std::snprintf(text, sizeof text, " --focus-on %.9g,%.9g", lens.focus_on[0], lens.focus_on[1]);
    else text[0] = 0;
    out += text;
    if (lens.blades >= 3) {
        std::snprintf(text, sizeof text, " --aperture-blades %u --aperture-rotation %.9g", lens.blades, lens.rotation_degrees);
        out += text;
    }
    return out;
}

}  // namespace fh
