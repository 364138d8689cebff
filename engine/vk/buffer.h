// Storage buffers: creation, memory, and host<->device copies (mapped where possible, staged otherwise).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vulkan/vulkan.h>

namespace fh::vk {

class Context;

enum class MemoryUse {
    device,   // device-local; filled and read through staging copies
    host,     // host-visible and coherent (mapped), device-local too where the device offers it
};

class Buffer {
public:
    Buffer() = default;
    Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use);
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; }  // nullptr unless host-visible

private:
    void release();
    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    VkDeviceSize allocated_ = 0;  // the allocation's size (at least size_), counted in device_memory_in_use
    void* mapped_ = nullptr;
};

// Vulkan memory this process holds through Buffers now, over every device: what soak tests watch for leaks.
struct DeviceMemoryInUse {
    uint64_t bytes = 0;
    uint64_t allocations = 0;
};
DeviceMemoryInUse device_memory_in_use();

// Copies host data into a buffer (staging when it is not mapped); waits for completion.
void upload_to_buffer(const Context& context, Buffer& target, const void* data, size_t size, size_t offset = 0);
// Copies buffer contents back to the host; waits for completion.
void download_from_buffer(const Context& context, const Buffer& source, void* data, size_t size, size_t offset = 0);

}  // namespace fh::vk
