// The viewer's display pass: tone-maps the renderer's film on the device and presents it to the swapchain.
#pragma once
#include <cstdint>
#include <memory>

#include "io/tone_curve.h"
#include "vk/buffer.h"
#include "vk/commands.h"
#include "vk/pipeline.h"

namespace fh {

namespace vk {
class Context;
class Swapchain;
}  // namespace vk

class FilmPresenter {
public:
    explicit FilmPresenter(const vk::Context& context);
    // Display texels for a film of width x height (read in place from `film`), then a copy onto the next
    // swapchain image. Returns false when the swapchain must be recreated.
    bool present(const vk::Buffer& film, uint32_t width, uint32_t height, float exposure_ev, ToneCurve curve,
                 vk::Swapchain& swapchain);

private:
    const vk::Context& context_;
    vk::BindingTable table_;
    vk::ComputePipeline pipeline_;
    vk::CommandRecorder recorder_;
    vk::Buffer pixels_;
};

}  // namespace fh
