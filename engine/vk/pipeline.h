// Descriptor sets of storage and uniform buffers and compute pipelines built from embedded SPIR-V.
#pragma once
#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
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
    std::span<const VkDescriptorType> types() const { return types_; }

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

// Every compute pipeline a Context has compiled, kept until the Context ends and found again by what made it (the
// SPIR-V, its specialisation constants, the binding types and push-constant size): a render after another (each frame
// of a sequence, the viewer after a resize) takes its stages from here instead of compiling them again. lavapipe
// (Mesa 22.3) keeps part of every pipeline it compiles after the pipeline is destroyed (tests/soak/README.md), so
// compiling each variant once also keeps a long process's memory flat. A pipeline is built with a layout of the store's
// own, identical to the BindingTable's, so that it outlives the table it was first asked for.
class PipelineStore {
public:
    explicit PipelineStore(VkDevice device) : device_(device) {}
    ~PipelineStore();
    PipelineStore(const PipelineStore&) = delete;
    PipelineStore& operator=(const PipelineStore&) = delete;

    // The pipeline for this module and constants with `table`'s layout; built on the first request (thread-safe).
    VkPipeline get(const BindingTable& table, std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants);
    size_t size() const;  // pipelines held

private:
    struct Layout {
        VkDescriptorSetLayout set = VK_NULL_HANDLE;
        VkPipelineLayout pipeline = VK_NULL_HANDLE;
    };
    VkPipelineLayout layout_for(std::span<const VkDescriptorType> types, uint32_t push_constant_size);
    VkPipeline build(VkPipelineLayout layout, std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants) const;

    VkDevice device_;
    mutable std::mutex mutex_;
    std::map<std::pair<uint64_t, uint64_t>, VkPipeline> pipelines_;  // by hash_spirv_key of what made them
    std::map<std::pair<uint64_t, uint64_t>, Layout> layouts_;        // by the binding types and push size
};

// A stage's pipeline, from the Context's PipelineStore (which owns it).
class ComputePipeline {
public:
    // spec_constants[i] becomes specialization constant constant_id = i (32 bits each; a bool is 0 or 1).
    ComputePipeline(const Context& context, const BindingTable& table, std::string name,
                    std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants = {});

    VkPipeline handle() const { return pipeline_; }
    const std::string& name() const { return name_; }

private:
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    std::string name_;
};

}  // namespace fh::vk
