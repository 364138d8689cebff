// Buffer allocation (one allocation per buffer: the renderer owns a dozen) and staged transfers.
#include "vk/buffer.h"

#include <atomic>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "vk/check.h"
#include "vk/commands.h"
#include "vk/context.h"

namespace fh::vk {
namespace {

std::atomic<uint64_t> live_bytes{0}, live_allocations{0};

uint32_t find_memory_type(const Context& context, uint32_t allowed, VkMemoryPropertyFlags wanted) {
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(context.physical_device(), &props);
    for (uint32_t i = 0; i < props.memoryTypeCount; ++i)
        if ((allowed & (1u << i)) && (props.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
    return UINT32_MAX;
}

}  // namespace

Buffer::Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use)
    : device_(context.device()), size_(size) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    FH_VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &buffer_));

    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device_, buffer_, &req);
    uint32_t type = UINT32_MAX;
    constexpr VkMemoryPropertyFlags host_flags =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if (use == MemoryUse::host) {
        type = find_memory_type(context, req.memoryTypeBits, host_flags | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        if (type == UINT32_MAX) type = find_memory_type(context, req.memoryTypeBits, host_flags);
    } else {
        type = find_memory_type(context, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    }
    if (type == UINT32_MAX) {
        release();
        throw std::runtime_error("no suitable Vulkan memory type for a buffer of " + std::to_string(size) + " bytes");
    }
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = type;
    VkResult result = vkAllocateMemory(device_, &alloc, nullptr, &memory_);
    if (result != VK_SUCCESS) {
        release();
        throw_vk_error(result, "vkAllocateMemory", __FILE__, __LINE__);
    }
    allocated_ = req.size;
    live_bytes += allocated_;
    ++live_allocations;
    FH_VK_CHECK(vkBindBufferMemory(device_, buffer_, memory_, 0));

    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(context.physical_device(), &props);
    if (props.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
        FH_VK_CHECK(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
    if (this != &other) {
        release();
        device_ = std::exchange(other.device_, VK_NULL_HANDLE);
        buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
        size_ = std::exchange(other.size_, 0);
        allocated_ = std::exchange(other.allocated_, 0);
        mapped_ = std::exchange(other.mapped_, nullptr);
    }
    return *this;
}

void Buffer::release() {
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) {
        vkFreeMemory(device_, memory_, nullptr);
        live_bytes -= allocated_;
        --live_allocations;
    }
    allocated_ = 0;
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
}

DeviceMemoryInUse device_memory_in_use() { return {live_bytes.load(), live_allocations.load()}; }

void upload_to_buffer(const Context& context, Buffer& target, const void* data, size_t size, size_t offset) {
    if (size == 0) return;
    if (target.mapped()) {
        std::memcpy(static_cast<char*>(target.mapped()) + offset, data, size);
        return;
    }
    Buffer staging(context, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::host);
    std::memcpy(staging.mapped(), data, size);
    CommandRecorder recorder(context);
    recorder.begin();
    recorder.copy_buffer(staging, 0, target, offset, size);
    recorder.submit_and_wait();
}

void download_from_buffer(const Context& context, const Buffer& source, void* data, size_t size, size_t offset) {
    if (size == 0) return;
    if (source.mapped()) {
        std::memcpy(data, static_cast<const char*>(source.mapped()) + offset, size);
        return;
    }
    Buffer staging(context, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::host);
    CommandRecorder recorder(context);
    recorder.begin();
    recorder.copy_buffer(source, offset, staging, 0, size);
    recorder.submit_and_wait();
    std::memcpy(data, staging.mapped(), size);
}

}  // namespace fh::vk
