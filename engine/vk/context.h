// The Vulkan instance, the chosen physical device, its logical device and one compute queue.
#pragma once
#include <atomic>
#include <memory>
#include <string>
#include <vector>
#include <vulkan/vulkan.h>

namespace fh::vk {

class PipelineStore;

struct ContextOptions {
    bool validation = false;                     // enable VK_LAYER_KHRONOS_validation and count its messages
    std::string device_filter;                   // pick the first device whose name contains this
    std::vector<const char*> instance_extensions;  // e.g. surface extensions for the viewer
    std::vector<const char*> device_extensions;    // e.g. VK_KHR_swapchain
};

class Context {
public:
    explicit Context(const ContextOptions& options);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physical_device() const { return physical_device_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    uint32_t queue_family() const { return queue_family_; }
    const VkPhysicalDeviceProperties& properties() const { return properties_; }
    const std::string& device_name() const { return device_name_; }
    bool has_timestamps() const { return timestamp_bits_ > 0; }
    // Validation messages seen so far (warnings and errors); the test suite requires zero.
    uint32_t validation_message_count() const { return validation_messages_.load(); }
    // The compute pipelines built on this device (pipeline.h), kept until the Context ends.
    PipelineStore& pipeline_store() const { return *pipeline_store_; }

private:
    void create_instance(const ContextOptions& options);
    void pick_physical_device(const ContextOptions& options);
    void create_device(const ContextOptions& options);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queue_family_ = 0;
    uint32_t timestamp_bits_ = 0;
    VkPhysicalDeviceProperties properties_{};
    std::string device_name_;
    std::atomic<uint32_t> validation_messages_{0};
    std::unique_ptr<PipelineStore> pipeline_store_;
};

}  // namespace fh::vk
