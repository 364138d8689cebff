// A window surface's swapchain, and the copy of a packed 8-bit RGBA buffer onto its next image.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <vector>
#include <vulkan/vulkan.h>

namespace fh::vk {

class Buffer;
class Context;

// Thrown when the device cannot present to the surface at all (no queue with present support, no formats).
struct PresentUnsupported : std::runtime_error {
    using runtime_error::runtime_error;
};

class Swapchain {
public:
    // Takes ownership of `surface` (destroyed with the swapchain). `extent` is used when the surface leaves the
    // size to the application. Throws PresentUnsupported when the context's queue cannot present to it.
    Swapchain(const Context& context, VkSurfaceKHR surface, VkExtent2D extent);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    // Rebuilds the images for a new window size (after a resize or an out-of-date present).
    void recreate(VkExtent2D extent);
    VkExtent2D extent() const { return extent_; }
    // True when the image bytes are B, G, R, A in memory (else R, G, B, A).
    bool bgra() const { return bgra_; }
    // True when the image format applies the sRGB transfer function itself (the writer should stay linear).
    bool srgb_format() const { return srgb_; }

    // Copies `pixels` (width x height packed 32-bit texels in the image's byte order, written by an earlier
    // submission) to the top-left corner of the next image, clears the rest, presents, and waits.
    // Returns false when the swapchain is out of date or suboptimal and should be recreated.
    bool present(const Buffer& pixels, uint32_t width, uint32_t height);

private:
    void create(VkExtent2D extent);
    void destroy_swapchain();

    const Context& context_;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkSurfaceFormatKHR format_{};
    VkExtent2D extent_{};
    bool bgra_ = true;
    bool srgb_ = false;
    std::vector<VkImage> images_;
    std::vector<VkSemaphore> rendered_;  // one per image: signalled by the copy, waited on by the present
    VkSemaphore acquired_ = VK_NULL_HANDLE;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
};

}  // namespace fh::vk
