// Descriptor set, pipeline layout and compute pipeline creation.
#include "vk/pipeline.h"

#include <algorithm>
#include <cassert>
#include <mutex>
#include <vector>

#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "vk/spirv_cache.h"
#include "vk/spirv_specialise.h"

namespace fh::vk {

namespace {

VkDescriptorSetLayout create_set_layout(VkDevice device, std::span<const VkDescriptorType> types) {
    std::vector<VkDescriptorSetLayoutBinding> bindings(types.size());
    for (uint32_t i = 0; i < bindings.size(); ++i) {
        bindings[i].binding = i;
        bindings[i].descriptorType = types[i];
        bindings[i].descriptorCount = 1;
        bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layout_info.bindingCount = uint32_t(bindings.size());
    layout_info.pBindings = bindings.data();
    VkDescriptorSetLayout layout;
    FH_VK_CHECK(vkCreateDescriptorSetLayout(device, &layout_info, nullptr, &layout));
    return layout;
}

VkPipelineLayout create_pipeline_layout(VkDevice device, VkDescriptorSetLayout set_layout, uint32_t push_constant_size) {
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_size};
    VkPipelineLayoutCreateInfo pipeline_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pipeline_info.setLayoutCount = 1;
    pipeline_info.pSetLayouts = &set_layout;
    pipeline_info.pushConstantRangeCount = push_constant_size ? 1 : 0;
    pipeline_info.pPushConstantRanges = &range;
    VkPipelineLayout layout;
    FH_VK_CHECK(vkCreatePipelineLayout(device, &pipeline_info, nullptr, &layout));
    return layout;
}

template <typename T>
std::span<const uint8_t> bytes_of(std::span<const T> items) {
    return {reinterpret_cast<const uint8_t*>(items.data()), items.size_bytes()};
}

}  // namespace

BindingTable::BindingTable(const Context& context, std::span<const VkDescriptorType> types,
                           uint32_t push_constant_size)
    : device_(context.device()),
      types_(types.begin(), types.end()),
      max_uniform_range_(context.properties().limits.maxUniformBufferRange),
      max_texel_elements_(context.properties().limits.maxTexelBufferElements),
      views_(types.size(), VK_NULL_HANDLE),
      push_constant_size_(push_constant_size) {
    set_layout_ = create_set_layout(device_, types_);

    std::vector<VkDescriptorPoolSize> pool_sizes;
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

    pipeline_layout_ = create_pipeline_layout(device_, set_layout_, push_constant_size);
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

PipelineStore::~PipelineStore() {
    for (const auto& [key, pipeline] : pipelines_) vkDestroyPipeline(device_, pipeline, nullptr);
    for (const auto& [key, layout] : layouts_) {
        vkDestroyPipelineLayout(device_, layout.pipeline, nullptr);
        vkDestroyDescriptorSetLayout(device_, layout.set, nullptr);
    }
}

size_t PipelineStore::size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return pipelines_.size();
}

VkPipelineLayout PipelineStore::layout_for(std::span<const VkDescriptorType> types, uint32_t push_constant_size) {
    const uint32_t push[1] = {push_constant_size};
    const SpirvKey key = hash_spirv_key({bytes_of(types), bytes_of(std::span<const uint32_t>(push))});
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = layouts_.find({key.a, key.b});
    if (it == layouts_.end()) {
        Layout layout;
        layout.set = create_set_layout(device_, types);
        layout.pipeline = create_pipeline_layout(device_, layout.set, push_constant_size);
        it = layouts_.emplace(std::make_pair(key.a, key.b), layout).first;
    }
    return it->second.pipeline;
}

VkPipeline PipelineStore::get(const BindingTable& table, std::span<const uint32_t> spirv,
                              std::span<const uint32_t> spec_constants) {
    const uint32_t push[1] = {table.push_constant_size()};
    const SpirvKey key = hash_spirv_key({bytes_of(spirv), bytes_of(spec_constants), bytes_of(table.types()),
                                         bytes_of(std::span<const uint32_t>(push))});
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = pipelines_.find({key.a, key.b});
        if (it != pipelines_.end()) return it->second;
    }
    // Built outside the lock (the stages compile on threads of their own); a pipeline built twice at once keeps one.
    const VkPipeline built = build(layout_for(table.types(), table.push_constant_size()), spirv, spec_constants);
    std::lock_guard<std::mutex> lock(mutex_);
    const auto [it, inserted] = pipelines_.emplace(std::make_pair(key.a, key.b), built);
    if (!inserted) vkDestroyPipeline(device_, built, nullptr);
    return it->second;
}

VkPipeline PipelineStore::build(VkPipelineLayout layout, std::span<const uint32_t> spirv,
                                std::span<const uint32_t> spec_constants) const {
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
    info.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkResult result = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
    vkDestroyShaderModule(device_, module, nullptr);
    FH_VK_CHECK(result);
    return pipeline;
}

ComputePipeline::ComputePipeline(const Context& context, const BindingTable& table, std::string name,
                                 std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants)
    : pipeline_(context.pipeline_store().get(table, spirv, spec_constants)), name_(std::move(name)) {}

}  // namespace fh::vk
