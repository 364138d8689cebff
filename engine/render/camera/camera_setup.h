// Fills the camera part of FrameParams from a glTF camera and the film size.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "shared/layout.h"

namespace fh {

// The image aspect is width / height; perspective uses the glTF yfov, orthographic the glTF ymag (and
// ymag * aspect horizontally, so pixels stay square). The camera is in world space; `render_origin`
// (Scene::origin) is subtracted in double so the frame is in the scene's render space.
void set_frame_camera(gpu::FrameParams& frame, const SceneCamera& camera, uint32_t width, uint32_t height,
                      const glm::dvec3& render_origin);

// The camera a render uses: index < 0 picks the scene's first camera, or a default framing camera.
// Throws SceneError for an index the scene does not have.
SceneCamera choose_camera(const Scene& scene, int index);

}  // namespace fh
