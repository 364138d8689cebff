// Creates the instance (optionally with validation), picks a device with a compute queue, creates it.
#include "vk/context.h"

#include "vk/pipeline.h"

#include <cstdio>
#include <cstring>

#include "vk/check.h"

namespace fh::vk {
namespace {

constexpr const char* VALIDATION_LAYER = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                     void* user) {
    static_cast<std::atomic<uint32_t>*>(user)->fetch_add(1);
    std::fprintf(stderr, "vulkan validation: %s\n", data->pMessage);
    return VK_FALSE;
}

bool has_layer(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const auto& layer : layers)
        if (std::strcmp(layer.layerName, name) == 0) return true;
    return false;
}

// The stages' queues append with ballots and subgroup sums (shaders/lib/core/queue.glsl) and traversal votes
// (traverse.glsl); Vulkan 1.1 only guarantees basic subgroup operations.
bool has_stage_subgroup_operations(VkPhysicalDevice device) {
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props.pNext = &subgroup;
    vkGetPhysicalDeviceProperties2(device, &props);
    const VkSubgroupFeatureFlags needed = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT |
                                          VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
    return (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0 &&
           (subgroup.supportedOperations & needed) == needed;
}

}  // namespace

Context::Context(const ContextOptions& options) {
    try {
        create_instance(options);
        pick_physical_device(options);
        create_device(options);
        pipeline_store_ = std::make_unique<PipelineStore>(device_);
    } catch (...) {
        this->~Context();
        throw;
    }
}

Context::~Context() {
    pipeline_store_.reset();  // its pipelines before the device
    if (device_) vkDestroyDevice(device_, nullptr);
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
    device_ = VK_NULL_HANDLE;
    messenger_ = VK_NULL_HANDLE;
    instance_ = VK_NULL_HANDLE;
}

void Context::create_instance(const ContextOptions& options) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "fredholm";
    app.pEngineName = "fredholm";
    app.apiVersion = VK_API_VERSION_1_1;

    std::vector<const char*> extensions = options.instance_extensions;
    std::vector<const char*> layers;
    if (options.validation) {
        if (!has_layer(VALIDATION_LAYER))
            throw std::runtime_error(
                "validation requested but VK_LAYER_KHRONOS_validation is not installed (Debian package "
                "vulkan-validationlayers)");
        layers.push_back(VALIDATION_LAYER);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = static_cast<uint32_t>(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VkResult result = vkCreateInstance(&info, nullptr, &instance_);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw VulkanError("no Vulkan driver found (install mesa-vulkan-drivers for the lavapipe CPU driver)", result);
    FH_VK_CHECK(result);

    if (options.validation) {
        VkDebugUtilsMessengerCreateInfoEXT messenger{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        messenger.pfnUserCallback = on_validation_message;
        messenger.pUserData = &validation_messages_;
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
        FH_VK_CHECK(create(instance_, &messenger, nullptr, &messenger_));
    }
}

void Context::pick_physical_device(const ContextOptions& options) {
    uint32_t count = 0;
    FH_VK_CHECK(vkEnumeratePhysicalDevices(instance_, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    FH_VK_CHECK(vkEnumeratePhysicalDevices(instance_, &count, devices.data()));

    // Prefer a discrete GPU, then integrated, then anything (lavapipe is a CPU device).
    int best_score = -1;
    for (VkPhysicalDevice device : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(device, &props);
        if (!options.device_filter.empty() && !std::strstr(props.deviceName, options.device_filter.c_str()))
            continue;
        uint32_t family_count = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(device, &family_count, nullptr);
        std::vector<VkQueueFamilyProperties> families(family_count);
        vkGetPhysicalDeviceQueueFamilyProperties(device, &family_count, families.data());
        if (!has_stage_subgroup_operations(device)) continue;
        for (uint32_t i = 0; i < family_count; ++i) {
            if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
            int score = props.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU     ? 3
                        : props.deviceType == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU ? 2
                                                                                     : 1;
            if (score > best_score) {
                best_score = score;
                physical_device_ = device;
                queue_family_ = i;
                properties_ = props;
                timestamp_bits_ = families[i].timestampValidBits;
            }
            break;
        }
    }
    if (!physical_device_)
        throw std::runtime_error(options.device_filter.empty()
                                     ? "no Vulkan device with a compute queue and the subgroup operations the stages "
                                       "use in compute shaders (basic, vote, ballot, arithmetic)"
                                     : "no Vulkan device whose name contains '" + options.device_filter + "'");
    device_name_ = properties_.deviceName;
}

void Context::create_device(const ContextOptions& options) {
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue_info.queueFamilyIndex = queue_family_;
    queue_info.queueCount = 1;
    queue_info.pQueuePriorities = &priority;

    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue_info;
    info.enabledExtensionCount = static_cast<uint32_t>(options.device_extensions.size());
    info.ppEnabledExtensionNames = options.device_extensions.data();
    VkPhysicalDeviceFeatures features{};
    info.pEnabledFeatures = &features;
    FH_VK_CHECK(vkCreateDevice(physical_device_, &info, nullptr, &device_));
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
}

}  // namespace fh::vk
