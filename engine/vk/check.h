// Turns failing Vulkan calls into exceptions that name the call, the VkResult and the source location.
#pragma once
#include <stdexcept>
#include <string>
#include <vulkan/vulkan.h>

namespace fh::vk {

struct VulkanError : std::runtime_error {
    VkResult result;
    VulkanError(const std::string& what, VkResult r) : std::runtime_error(what), result(r) {}
};

const char* result_name(VkResult result);
[[noreturn]] void throw_vk_error(VkResult result, const char* call, const char* file, int line);

}  // namespace fh::vk

#define FH_VK_CHECK(call)                                                         \
    do {                                                                          \
        VkResult fh_vk_result_ = (call);                                          \
        if (fh_vk_result_ != VK_SUCCESS)                                          \
            ::fh::vk::throw_vk_error(fh_vk_result_, #call, __FILE__, __LINE__);   \
    } while (0)
