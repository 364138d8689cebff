// Runs shaders/present.comp over the film and hands the packed texels to the swapchain.
#include "app/view/viewer_present.h"

#include <array>
#include <cmath>

#include "shaders/present.spv.h"
#include "shared/present.h"
#include "vk/swapchain.h"

namespace fh {
namespace {

std::array<VkDescriptorType, gpu::PRESENT_BINDING_COUNT> present_binding_types() {
    std::array<VkDescriptorType, gpu::PRESENT_BINDING_COUNT> types;
    types.fill(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    return types;
}

}  // namespace

FilmPresenter::FilmPresenter(const vk::Context& context)
    : context_(context),
      table_(context, present_binding_types(), sizeof(gpu::PresentPush)),
      pipeline_(context, table_, "present", spv_present),
      recorder_(context) {}

bool FilmPresenter::present(const vk::Buffer& film, uint32_t width, uint32_t height, float exposure_ev,
                            ToneCurve curve, vk::Swapchain& swapchain) {
    const VkDeviceSize bytes = VkDeviceSize(width) * height * sizeof(uint32_t);
    if (pixels_.size() < bytes) {
        pixels_ = vk::Buffer(context_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::device);
        table_.bind_buffer(gpu::PRESENT_BINDING_PIXELS, pixels_);
    }
    // Bound every frame: a resize or a settings change rebuilds the renderer, and with it the film buffer.
    // The set is not in use (every submission is waited for), so updating it is allowed.
    table_.bind_buffer(gpu::PRESENT_BINDING_FILM, film);
    gpu::PresentPush push{};
    push.width = width;
    push.height = height;
    push.exposure_scale = std::exp2(exposure_ev);
    push.tone_curve = curve == ToneCurve::aces ? gpu::PRESENT_TONE_ACES : gpu::PRESENT_TONE_CLAMP;
    push.flags = (swapchain.bgra() ? gpu::PRESENT_BGRA : 0u) | (swapchain.srgb_format() ? 0u : gpu::PRESENT_ENCODE_SRGB);
    recorder_.begin();
    recorder_.bind_table(table_);
    recorder_.push_constants(&push, sizeof(push));
    const uint64_t pixels = uint64_t(width) * height;
    recorder_.dispatch(pipeline_, uint32_t((pixels + gpu::PRESENT_WORKGROUP_SIZE - 1) / gpu::PRESENT_WORKGROUP_SIZE));
    recorder_.submit_and_wait();
    return swapchain.present(pixels_, width, height);
}

}  // namespace fh
