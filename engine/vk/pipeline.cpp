// Descriptor set, pipeline layout and compute pipeline creation.
#include "vk/pipeline.h"

#include <vector>

#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"

namespace fh::vk {

BindingTable::BindingTable(const Context& context, uint32_t binding_count, uint32_t push_constant_size)
    : device_(context.device()), push_constant_size_(push_constant_size) {
    std::vector<VkDescriptorSetLayoutBinding> bindings(binding_count);
    for (uint32_t i = 0; i < binding_count; ++i) {
        bindings[i].binding = i;
        bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        bindings[i].descriptorCount = 1;
        bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layout_info.bindingCount = binding_count;
    layout_info.pBindings = bindings.data();
    FH_VK_CHECK(vkCreateDescriptorSetLayout(device_, &layout_info, nullptr, &set_layout_));

    VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, binding_count};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &pool_size;
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
    vkDestroyPipelineLayout(device_, pipeline_layout_, nullptr);
    vkDestroyDescriptorPool(device_, pool_, nullptr);
    vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
}

void BindingTable::bind_buffer(uint32_t binding, const Buffer& buffer) {
    VkDescriptorBufferInfo info{buffer.handle(), 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set_;
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    write.pBufferInfo = &info;
    vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
}

ComputePipeline::ComputePipeline(const Context& context, const BindingTable& table, std::string name,
                                 std::span<const uint32_t> spirv)
    : device_(context.device()), name_(std::move(name)) {
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
    info.layout = table.pipeline_layout();
    VkResult result = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
    vkDestroyShaderModule(device_, module, nullptr);
    FH_VK_CHECK(result);
}

ComputePipeline::~ComputePipeline() { vkDestroyPipeline(device_, pipeline_, nullptr); }

}  // namespace fh::vk
