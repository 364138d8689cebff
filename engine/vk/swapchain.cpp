// Swapchain creation for a window surface, and presenting a packed RGBA buffer by a transfer copy (no
// graphics pipeline: the renderer is compute-only, so a buffer-to-image copy is all presentation needs).
#include "vk/swapchain.h"

#include <algorithm>

#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"

namespace fh::vk {
namespace {

VkSurfaceFormatKHR choose_format(const std::vector<VkSurfaceFormatKHR>& formats, bool& bgra, bool& srgb) {
    // Prefer UNORM formats: the present shader encodes sRGB itself and the copy is then bit-exact.
    const VkFormat preferred[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                                  VK_FORMAT_R8G8B8A8_SRGB};
    for (VkFormat wanted : preferred)
        for (const VkSurfaceFormatKHR& f : formats)
            if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
                bgra = wanted == VK_FORMAT_B8G8R8A8_UNORM || wanted == VK_FORMAT_B8G8R8A8_SRGB;
                srgb = wanted == VK_FORMAT_B8G8R8A8_SRGB || wanted == VK_FORMAT_R8G8B8A8_SRGB;
                return f;
            }
    throw PresentUnsupported("the window surface offers no 8-bit RGBA/BGRA sRGB format");
}

VkPresentModeKHR choose_present_mode(VkPhysicalDevice device, VkSurfaceKHR surface) {
    uint32_t count = 0;
    FH_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(device, surface, &count, nullptr));
    std::vector<VkPresentModeKHR> modes(count);
    FH_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(device, surface, &count, modes.data()));
    // Each frame waits for its copy anyway; MAILBOX keeps a slow frame from also waiting for vertical blank.
    if (std::find(modes.begin(), modes.end(), VK_PRESENT_MODE_MAILBOX_KHR) != modes.end())
        return VK_PRESENT_MODE_MAILBOX_KHR;
    return VK_PRESENT_MODE_FIFO_KHR;  // always supported
}

VkImageMemoryBarrier image_barrier(VkImage image, VkImageLayout from, VkImageLayout to, VkAccessFlags src,
                                   VkAccessFlags dst) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = src;
    b.dstAccessMask = dst;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    return b;
}

}  // namespace

Swapchain::Swapchain(const Context& context, VkSurfaceKHR surface, VkExtent2D extent)
    : context_(context), surface_(surface) {
    try {
        VkBool32 supported = VK_FALSE;
        FH_VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(context.physical_device(), context.queue_family(), surface,
                                                         &supported));
        if (!supported)
            throw PresentUnsupported("the Vulkan device '" + context.device_name() +
                                     "' cannot present to this window from its compute queue");
        uint32_t count = 0;
        FH_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(context.physical_device(), surface, &count, nullptr));
        std::vector<VkSurfaceFormatKHR> formats(count);
        FH_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(context.physical_device(), surface, &count, formats.data()));
        format_ = choose_format(formats, bgra_, srgb_);

        VkDevice device = context.device();
        VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pool_info.queueFamilyIndex = context.queue_family();
        FH_VK_CHECK(vkCreateCommandPool(device, &pool_info, nullptr, &pool_));
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = pool_;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        FH_VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &cmd_));
        VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        FH_VK_CHECK(vkCreateFence(device, &fence_info, nullptr, &fence_));
        VkSemaphoreCreateInfo semaphore_info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        FH_VK_CHECK(vkCreateSemaphore(device, &semaphore_info, nullptr, &acquired_));
        create(extent);
    } catch (...) {
        this->~Swapchain();
        throw;
    }
}

Swapchain::~Swapchain() {
    VkDevice device = context_.device();
    if (device) vkDeviceWaitIdle(device);
    destroy_swapchain();
    if (acquired_) vkDestroySemaphore(device, acquired_, nullptr);
    if (fence_) vkDestroyFence(device, fence_, nullptr);
    if (pool_) vkDestroyCommandPool(device, pool_, nullptr);
    if (surface_) vkDestroySurfaceKHR(context_.instance(), surface_, nullptr);
    acquired_ = VK_NULL_HANDLE;
    fence_ = VK_NULL_HANDLE;
    pool_ = VK_NULL_HANDLE;
    surface_ = VK_NULL_HANDLE;
}

void Swapchain::destroy_swapchain() {
    for (VkSemaphore s : rendered_) vkDestroySemaphore(context_.device(), s, nullptr);
    rendered_.clear();
    images_.clear();
    if (swapchain_) vkDestroySwapchainKHR(context_.device(), swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
}

void Swapchain::recreate(VkExtent2D extent) {
    FH_VK_CHECK(vkDeviceWaitIdle(context_.device()));
    create(extent);
}

void Swapchain::create(VkExtent2D extent) {
    VkSurfaceCapabilitiesKHR caps;
    FH_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(context_.physical_device(), surface_, &caps));
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        throw PresentUnsupported("the window's swapchain images cannot be written by a transfer copy");
    if (caps.currentExtent.width != UINT32_MAX) {
        extent = caps.currentExtent;
    } else {
        extent.width = std::clamp(extent.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(extent.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    VkSwapchainKHR old = swapchain_;
    for (VkSemaphore s : rendered_) vkDestroySemaphore(context_.device(), s, nullptr);
    rendered_.clear();
    images_.clear();
    swapchain_ = VK_NULL_HANDLE;
    extent_ = extent;
    if (extent.width == 0 || extent.height == 0) {  // minimised: nothing to present to until it reappears
        if (old) vkDestroySwapchainKHR(context_.device(), old, nullptr);
        return;
    }

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface_;
    info.minImageCount = caps.minImageCount + 1;
    if (caps.maxImageCount > 0) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
    info.imageFormat = format_.format;
    info.imageColorSpace = format_.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                            ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                            : caps.currentTransform;
    info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha &
                                                            ~(caps.supportedCompositeAlpha - 1));
    info.presentMode = choose_present_mode(context_.physical_device(), surface_);
    info.clipped = VK_TRUE;
    info.oldSwapchain = old;
    VkResult result = vkCreateSwapchainKHR(context_.device(), &info, nullptr, &swapchain_);
    if (old) vkDestroySwapchainKHR(context_.device(), old, nullptr);
    FH_VK_CHECK(result);

    uint32_t count = 0;
    FH_VK_CHECK(vkGetSwapchainImagesKHR(context_.device(), swapchain_, &count, nullptr));
    images_.resize(count);
    FH_VK_CHECK(vkGetSwapchainImagesKHR(context_.device(), swapchain_, &count, images_.data()));
    VkSemaphoreCreateInfo semaphore_info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    rendered_.resize(count);
    for (VkSemaphore& s : rendered_) FH_VK_CHECK(vkCreateSemaphore(context_.device(), &semaphore_info, nullptr, &s));
}

bool Swapchain::present(const Buffer& pixels, uint32_t width, uint32_t height) {
    if (!swapchain_) return false;
    VkDevice device = context_.device();
    uint32_t index = 0;
    VkResult acquired = vkAcquireNextImageKHR(device, swapchain_, UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) return false;
    if (acquired != VK_SUBOPTIMAL_KHR) FH_VK_CHECK(acquired);
    VkImage image = images_[index];

    FH_VK_CHECK(vkResetCommandBuffer(cmd_, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    FH_VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
    // The pixels were written by a compute shader in an earlier submission (barriers reach back through
    // submission order).
    VkMemoryBarrier written{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    written.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    written.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkImageMemoryBarrier to_transfer = image_barrier(image, VK_IMAGE_LAYOUT_UNDEFINED,
                                                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                                                     VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &written, 0, nullptr, 1, &to_transfer);
    const uint32_t copy_w = std::min(width, extent_.width), copy_h = std::min(height, extent_.height);
    if (copy_w < extent_.width || copy_h < extent_.height) {
        // The film lags a resize by a frame: show black around it rather than stale contents.
        VkClearColorValue black{};
        VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmd_, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
        VkImageMemoryBarrier cleared = image_barrier(image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                                     VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
        vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr,
                             0, nullptr, 1, &cleared);
    }
    if (copy_w > 0 && copy_h > 0) {
        VkBufferImageCopy region{};
        region.bufferRowLength = width;
        region.bufferImageHeight = height;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {copy_w, copy_h, 1};
        vkCmdCopyBufferToImage(cmd_, pixels.handle(), image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    }
    VkImageMemoryBarrier to_present = image_barrier(image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                                    VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_ACCESS_TRANSFER_WRITE_BIT, 0);
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, nullptr,
                         0, nullptr, 1, &to_present);
    FH_VK_CHECK(vkEndCommandBuffer(cmd_));

    VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.waitSemaphoreCount = 1;
    submit.pWaitSemaphores = &acquired_;
    submit.pWaitDstStageMask = &wait_stage;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &rendered_[index];
    FH_VK_CHECK(vkResetFences(device, 1, &fence_));
    FH_VK_CHECK(vkQueueSubmit(context_.queue(), 1, &submit, fence_));

    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &rendered_[index];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_;
    present.pImageIndices = &index;
    VkResult presented = vkQueuePresentKHR(context_.queue(), &present);
    FH_VK_CHECK(vkWaitForFences(device, 1, &fence_, VK_TRUE, UINT64_MAX));
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) return false;
    FH_VK_CHECK(presented);
    return acquired != VK_SUBOPTIMAL_KHR;
}

}  // namespace fh::vk
