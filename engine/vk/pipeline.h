// Descriptor sets of storage and uniform buffers and compute pipelines built from embedded SPIR-V.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>
#include <vulkan/vulkan.h>

namespace fh::vk {

class Buffer;
class Context;

// One descriptor set whose binding i is a buffer of descriptor type types[i] (storage, uniform, or uniform texel
// buffer of 32-bit RGBA texels), plus the pipeline layout every compute pipeline using it shares (that set + one
// push-constant block).
class BindingTable {
public:
    BindingTable(const Context& context, std::span<const VkDescriptorType> types, uint32_t push_constant_size);
    ~BindingTable();
    BindingTable(const BindingTable&) = delete;
    BindingTable& operator=(const BindingTable&) = delete;

    // Uniform-buffer bindings see at most the device's maxUniformBufferRange bytes from the buffer's start; texel
    // buffers (VK_FORMAT_R32G32B32A32_UINT: 16 bytes a texel) the whole 16-byte texels, at most maxTexelBufferElements.
    void bind_buffer(uint32_t binding, const Buffer& buffer);
    VkDescriptorSet set() const { return set_; }
    VkPipelineLayout pipeline_layout() const { return pipeline_layout_; }
    uint32_t push_constant_size() const { return push_constant_size_; }

private:
    VkDevice device_;
    std::vector<VkDescriptorType> types_;
    VkDeviceSize max_uniform_range_;
    VkDeviceSize max_texel_elements_;
    std::vector<VkBufferView> views_;  // per binding (texel buffers), VK_NULL_HANDLE elsewhere
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
    uint32_t push_constant_size_;
};

class ComputePipeline {
public:
    // spec_constants[i] becomes specialization constant constant_id = i (32 bits each; a bool is 0 or 1).
    ComputePipeline(const Context& context, const BindingTable& table, std::string name,
                    std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants = {});
    ~ComputePipeline();
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;

    VkPipeline handle() const { return pipeline_; }
    const std::string& name() const { return name_; }

private:
    VkDevice device_;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    std::string name_;
};

}  // namespace fh::vk
