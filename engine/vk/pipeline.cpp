// Descriptor set, pipeline layout and compute pipeline creation.
#include "vk/pipeline.h"

#include <algorithm>
#include <cassert>
#include <vector>

#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "vk/spirv_specialise.h"

namespace fh::vk {

BindingTable::BindingTable(const Context& context, std::span<const VkDescriptorType> types,
                           uint32_t push_constant_size)
    : device_(context.device()),
      types_(types.begin(), types.end()),
      max_uniform_range_(context.properties().limits.maxUniformBufferRange),
      max_texel_elements_(context.properties().limits.maxTexelBufferElements),
      views_(types.size(), VK_NULL_HANDLE),
      push_constant_size_(push_constant_size) {
    const uint32_t binding_count = uint32_t(types_.size());
    std::vector<VkDescriptorSetLayoutBinding> bindings(binding_count);
    std::vector<VkDescriptorPoolSize> pool_sizes;
    for (uint32_t i = 0; i < binding_count; ++i) {
        bindings[i].binding = i;
        bindings[i].descriptorType = types_[i];
        bindings[i].descriptorCount = 1;
        bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layout_info.bindingCount = binding_count;
    layout_info.pBindings = bindings.data();
    FH_VK_CHECK(vkCreateDescriptorSetLayout(device_, &layout_info, nullptr, &set_layout_));

    for (VkDescriptorType type : types_) {
        auto same = [type](const VkDescriptorPoolSize& p) { return p.type == type; };
        auto it = std::find_if(pool_sizes.begin(), pool_sizes.end(), same);
        if (it == pool_sizes.end()) pool_sizes.push_back({type, 1});
        else ++it->descriptorCount;
    }
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = uint32_t(pool_sizes.size());
    pool_info.pPoolSizes = pool_sizes.data();
    FH_VK_CHECK(vkCreateDescriptorPool(device_, &pool_info, nullptr, &pool_));

    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool_;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout_;
    FH_VK_CHECK(vkAllocateDescriptorSets(device_, &alloc, &set_));

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_size};
    VkPipelineLayoutCreateInfo pipeline_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pipeline_info.setLayoutCount = 1;
    pipeline_info.pSetLayouts = &set_layout_;
    pipeline_info.pushConstantRangeCount = push_constant_size ? 1 : 0;
    pipeline_info.pPushConstantRanges = &range;
    FH_VK_CHECK(vkCreatePipelineLayout(device_, &pipeline_info, nullptr, &pipeline_layout_));
}

BindingTable::~BindingTable() {
    for (VkBufferView view : views_) vkDestroyBufferView(device_, view, nullptr);
    vkDestroyPipelineLayout(device_, pipeline_layout_, nullptr);
    vkDestroyDescriptorPool(device_, pool_, nullptr);
    vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
}

void BindingTable::bind_buffer(uint32_t binding, const Buffer& buffer) {
    assert(binding < types_.size());
    const VkDescriptorType type = types_[binding];
    if (type == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER) {
        VkBufferViewCreateInfo view_info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
        view_info.buffer = buffer.handle();
        view_info.format = VK_FORMAT_R32G32B32A32_UINT;
        view_info.offset = 0;
        view_info.range = std::max<VkDeviceSize>(std::min(buffer.size() / 16, max_texel_elements_), 1) * 16;
        VkBufferView view;
        FH_VK_CHECK(vkCreateBufferView(device_, &view_info, nullptr, &view));
        if (views_[binding] != VK_NULL_HANDLE) vkDestroyBufferView(device_, views_[binding], nullptr);
        views_[binding] = view;
        VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        write.dstSet = set_;
        write.dstBinding = binding;
        write.descriptorCount = 1;
        write.descriptorType = type;
        write.pTexelBufferView = &views_[binding];
        vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
        return;
    }
    const bool uniform = type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    VkDescriptorBufferInfo info{buffer.handle(), 0,
                                uniform ? std::min(buffer.size(), max_uniform_range_) : VK_WHOLE_SIZE};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set_;
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = type;
    write.pBufferInfo = &info;
    vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
}

ComputePipeline::ComputePipeline(const Context& context, const BindingTable& table, std::string name,
                                 std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants)
    : device_(context.device()), name_(std::move(name)) {
    // The driver gets the module specialised on the host when it can be (spirv_specialise.h says why), else the
    // whole module and the constants.
    std::vector<uint32_t> specialised;
    if (!spec_constants.empty()) specialised = specialise_spirv(spirv, spec_constants);
    if (!specialised.empty()) {
        spirv = specialised;
        spec_constants = {};
    }
    VkShaderModuleCreateInfo module_info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    module_info.codeSize = spirv.size_bytes();
    module_info.pCode = spirv.data();
    VkShaderModule module;
    FH_VK_CHECK(vkCreateShaderModule(device_, &module_info, nullptr, &module));

    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module;
    info.stage.pName = "main";
    std::vector<VkSpecializationMapEntry> entries(spec_constants.size());
    for (uint32_t i = 0; i < entries.size(); ++i) entries[i] = {i, i * uint32_t(sizeof(uint32_t)), sizeof(uint32_t)};
    VkSpecializationInfo specialization{uint32_t(entries.size()), entries.data(), spec_constants.size_bytes(),
                                        spec_constants.data()};
    if (!spec_constants.empty()) info.stage.pSpecializationInfo = &specialization;
    info.layout = table.pipeline_layout();
    VkResult result = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
    vkDestroyShaderModule(device_, module, nullptr);
    FH_VK_CHECK(result);
}

ComputePipeline::~ComputePipeline() { vkDestroyPipeline(device_, pipeline_, nullptr); }

}  // namespace fh::vk
