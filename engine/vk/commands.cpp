// Command buffer recording, barriers, per-dispatch timestamps and synchronous submission.
#include "vk/commands.h"

#include <stdexcept>

#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "vk/pipeline.h"

namespace fh::vk {

CommandRecorder::CommandRecorder(const Context& context, uint32_t max_dispatches) : context_(context) {
    VkDevice device = context.device();
    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool_info.queueFamilyIndex = context.queue_family();
    FH_VK_CHECK(vkCreateCommandPool(device, &pool_info, nullptr, &pool_));

    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    FH_VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &cmd_));

    VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    FH_VK_CHECK(vkCreateFence(device, &fence_info, nullptr, &fence_));

    if (max_dispatches > 0 && context.has_timestamps()) {
        max_queries_ = max_dispatches + 1;
        VkQueryPoolCreateInfo query_info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        query_info.queryCount = max_queries_;
        FH_VK_CHECK(vkCreateQueryPool(device, &query_info, nullptr, &queries_));
    }
}

CommandRecorder::~CommandRecorder() {
    VkDevice device = context_.device();
    if (queries_) vkDestroyQueryPool(device, queries_, nullptr);
    vkDestroyFence(device, fence_, nullptr);
    vkDestroyCommandPool(device, pool_, nullptr);
}

void CommandRecorder::begin() {
    FH_VK_CHECK(vkResetCommandBuffer(cmd_, 0));
    VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    FH_VK_CHECK(vkBeginCommandBuffer(cmd_, &info));
    query_names_.clear();
    if (queries_) {
        vkCmdResetQueryPool(cmd_, queries_, 0, max_queries_);
        write_timestamp("");
    }
}

void CommandRecorder::bind_table(const BindingTable& table) {
    layout_ = table.pipeline_layout();
    VkDescriptorSet set = table.set();
    vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set, 0, nullptr);
}

void CommandRecorder::push_constants(const void* data, uint32_t size) {
    vkCmdPushConstants(cmd_, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, size, data);
}

void CommandRecorder::dispatch(const ComputePipeline& pipeline, uint32_t group_count) {
    vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdDispatch(cmd_, group_count, 1, 1);
    write_timestamp(pipeline.name());
}

void CommandRecorder::dispatch_indirect(const ComputePipeline& pipeline, const Buffer& args, VkDeviceSize offset) {
    vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdDispatchIndirect(cmd_, args.handle(), offset);
    write_timestamp(pipeline.name());
}

void CommandRecorder::write_timestamp(const std::string& name) {
    if (!queries_) return;
    if (query_names_.size() >= max_queries_)
        throw std::logic_error("CommandRecorder: more dispatches than timestamp queries");
    vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_,
                        static_cast<uint32_t>(query_names_.size()));
    query_names_.push_back(name);
}

void CommandRecorder::barrier_compute() {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_UNIFORM_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                            VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
}

void CommandRecorder::copy_buffer(const Buffer& source, VkDeviceSize source_offset, const Buffer& target,
                                  VkDeviceSize target_offset, VkDeviceSize size) {
    VkBufferCopy region{source_offset, target_offset, size};
    vkCmdCopyBuffer(cmd_, source.handle(), target.handle(), 1, &region);
}

void CommandRecorder::fill_buffer(const Buffer& target, uint32_t value) {
    vkCmdFillBuffer(cmd_, target.handle(), 0, VK_WHOLE_SIZE, value);
}

void CommandRecorder::fill_buffer(const Buffer& target, uint32_t value, VkDeviceSize size) {
    vkCmdFillBuffer(cmd_, target.handle(), 0, size, value);
}

void CommandRecorder::submit_and_wait() {
    VkMemoryBarrier to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    to_host.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, nullptr, 0, nullptr);
    FH_VK_CHECK(vkEndCommandBuffer(cmd_));

    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_;
    FH_VK_CHECK(vkResetFences(context_.device(), 1, &fence_));
    FH_VK_CHECK(vkQueueSubmit(context_.queue(), 1, &submit, fence_));
    FH_VK_CHECK(vkWaitForFences(context_.device(), 1, &fence_, VK_TRUE, UINT64_MAX));

    dispatch_seconds_.clear();
    if (!queries_ || query_names_.size() < 2) return;
    std::vector<uint64_t> ticks(query_names_.size());
    FH_VK_CHECK(vkGetQueryPoolResults(context_.device(), queries_, 0, static_cast<uint32_t>(ticks.size()),
                                      ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                      VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    const double seconds_per_tick = context_.properties().limits.timestampPeriod * 1e-9;
    for (size_t i = 1; i < ticks.size(); ++i)
        dispatch_seconds_.emplace_back(query_names_[i], double(ticks[i] - ticks[i - 1]) * seconds_per_tick);
}

}  // namespace fh::vk
