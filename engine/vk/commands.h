// Records one command buffer of compute dispatches, with a GPU timestamp after each, and submits it.
#pragma once
#include <string>
#include <utility>
#include <vector>
#include <vulkan/vulkan.h>

namespace fh::vk {

class Buffer;
class BindingTable;
class ComputePipeline;
class Context;

class CommandRecorder {
public:
    // max_dispatches bounds the timestamps one submission can record (0: no timing).
    explicit CommandRecorder(const Context& context, uint32_t max_dispatches = 0);
    ~CommandRecorder();
    CommandRecorder(const CommandRecorder&) = delete;
    CommandRecorder& operator=(const CommandRecorder&) = delete;

    void begin();
    void bind_table(const BindingTable& table);
    void push_constants(const void* data, uint32_t size);
    void dispatch(const ComputePipeline& pipeline, uint32_t group_count);
    void dispatch_indirect(const ComputePipeline& pipeline, const Buffer& args, VkDeviceSize offset);
    // Makes every earlier shader write visible to later shader reads and indirect-argument reads.
    void barrier_compute();
    void copy_buffer(const Buffer& source, VkDeviceSize source_offset, const Buffer& target,
                     VkDeviceSize target_offset, VkDeviceSize size);
    void fill_buffer(const Buffer& target, uint32_t value);
    void fill_buffer(const Buffer& target, uint32_t value, VkDeviceSize size);  // its first `size` bytes (a multiple of 4)
    // Ends recording (making writes visible to the host), submits, waits, and reads the timestamps.
    void submit_and_wait();

    // Seconds spent in each dispatch of the last submission, by pipeline name, in order.
    const std::vector<std::pair<std::string, double>>& dispatch_seconds() const { return dispatch_seconds_; }

private:
    void write_timestamp(const std::string& name);

    const Context& context_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkQueryPool queries_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    uint32_t max_queries_ = 0;
    std::vector<std::string> query_names_;
    std::vector<std::pair<std::string, double>> dispatch_seconds_;
};

}  // namespace fh::vk
