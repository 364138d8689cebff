// Descriptor sets of storage buffers and compute pipelines built from embedded SPIR-V.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vulkan/vulkan.h>

namespace fh::vk {

class Buffer;
class Context;

// One descriptor set whose bindings 0..count-1 are all storage buffers, plus the pipeline layout every
// compute pipeline using it shares (that set + one push-constant block).
class BindingTable {
public:
    BindingTable(const Context& context, uint32_t binding_count, uint32_t push_constant_size);
    ~BindingTable();
    BindingTable(const BindingTable&) = delete;
    BindingTable& operator=(const BindingTable&) = delete;

    void bind_buffer(uint32_t binding, const Buffer& buffer);
    VkDescriptorSet set() const { return set_; }
    VkPipelineLayout pipeline_layout() const { return pipeline_layout_; }
    uint32_t push_constant_size() const { return push_constant_size_; }

private:
    VkDevice device_;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
    uint32_t push_constant_size_;
};

class ComputePipeline {
public:
    ComputePipeline(const Context& context, const BindingTable& table, std::string name,
                    std::span<const uint32_t> spirv);
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
