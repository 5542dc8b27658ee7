// Vulkan backend: instance, physical/logical device, queue, memory, staging, submission and
// the createVkDevice factory.
#include "rhi/vulkan/vk_device.h"

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>

#include "rhi/backends.h"

namespace parity::rhi {

std::unique_ptr<Device> createVkDevice(const DeviceDesc& desc, std::string* whyNot) {
  auto device = std::make_unique<vulkan::VulkanDevice>();
  std::string reason;
  if (!device->init(desc, &reason)) {
    if (whyNot) *whyNot = reason;
    return nullptr;
  }
  return device;
}

std::vector<std::string> vkAdapterNames() {
  std::vector<std::string> names;
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  VkInstance instance = VK_NULL_HANDLE;
  if (vkCreateInstance(&ci, nullptr, &instance) != VK_SUCCESS) return names;
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &families, nullptr);
    std::vector<VkQueueFamilyProperties> props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &families, props.data());
    const bool queue = std::any_of(props.begin(), props.end(), [](const VkQueueFamilyProperties& f) {
      return (f.queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) == (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT);
    });
    if (p.apiVersion >= VK_API_VERSION_1_3 && queue) names.push_back(p.deviceName);
  }
  vkDestroyInstance(instance, nullptr);
  return names;
}

}  // namespace parity::rhi

namespace parity::rhi::vulkan {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr VkDeviceSize kStagingChunkSize = 4u << 20;

VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT types,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT || !data) return VK_FALSE;
  // The loader reports on its own search for drivers and layers (ICDs that find no hardware,
  // environment overrides); those are not about the application's use of Vulkan.
  if (data->pMessageIdName && std::strcmp(data->pMessageIdName, "Loader Message") == 0) return VK_FALSE;
  // Performance warnings are about choices this backend makes on purpose: images stay in
  // VK_IMAGE_LAYOUT_GENERAL (see vk_device.h), which the layer flags at every copy.
  const bool error = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  if (!error && types == VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT) return VK_FALSE;
  std::string text = error ? "Vulkan error: " : "Vulkan warning: ";
  text += data->pMessage ? data->pMessage : "(no message)";
  static_cast<VulkanDevice*>(user)->debugMessage(text);
  return VK_FALSE;
}

std::string versionString(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

}  // namespace

const char* resultName(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_FRAGMENTED_POOL: return "VK_ERROR_FRAGMENTED_POOL";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    default: return "VkResult error";
  }
}

void VulkanDevice::debugMessage(const std::string& message) {
  if (log_)
    log_(message);
  else
    std::fprintf(stderr, "parity: %s\n", message.c_str());
}

// ---------------------------------------------------------------------------------------------
// Creation
// ---------------------------------------------------------------------------------------------
bool VulkanDevice::init(const DeviceDesc& desc, std::string* whyNot) {
  log_ = desc.log;
  adapter_ = desc.adapter;
  if (!createInstance(desc, whyNot) || !pickPhysicalDevice(whyNot) || !createLogicalDevice(whyNot)) return false;
  beginRecording();
  return true;
}

bool VulkanDevice::createInstance(const DeviceDesc& desc, std::string* whyNot) {
  uint32_t loaderVersion = VK_API_VERSION_1_0;
  if (vkEnumerateInstanceVersion(&loaderVersion) != VK_SUCCESS || loaderVersion < VK_API_VERSION_1_3) {
    *whyNot = "the Vulkan loader supports only Vulkan " + versionString(loaderVersion) + " (1.3 needed)";
    return false;
  }

  std::vector<const char*> layers, extensions;
  bool debugUtils = false;
  if (desc.debug) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> available(count);
    vkEnumerateInstanceLayerProperties(&count, available.data());
    for (const VkLayerProperties& l : available)
      if (std::strcmp(l.layerName, kValidationLayer) == 0) layers.push_back(kValidationLayer);
    // debug utils comes from the loader or from the validation layer.
    std::vector<const char*> sources{nullptr};
    if (!layers.empty()) sources.push_back(kValidationLayer);
    for (const char* source : sources) {
      vkEnumerateInstanceExtensionProperties(source, &count, nullptr);
      std::vector<VkExtensionProperties> exts(count);
      vkEnumerateInstanceExtensionProperties(source, &count, exts.data());
      for (const VkExtensionProperties& e : exts)
        if (std::strcmp(e.extensionName, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) == 0) debugUtils = true;
    }
    if (debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "parity";
  app.pEngineName = "parity";
  app.apiVersion = VK_API_VERSION_1_3;

  VkDebugUtilsMessengerCreateInfoEXT messengerInfo{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messengerInfo.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messengerInfo.pfnUserCallback = onDebugMessage;
  messengerInfo.pUserData = this;

  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  ci.enabledLayerCount = static_cast<uint32_t>(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  ci.ppEnabledExtensionNames = extensions.data();
  if (debugUtils) ci.pNext = &messengerInfo;  // also covers vkCreateInstance/vkDestroyInstance
  VkResult r = vkCreateInstance(&ci, nullptr, &instance_);
  if (r != VK_SUCCESS) {
    instance_ = VK_NULL_HANDLE;
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
      *whyNot = std::string("no Vulkan ICD found (vkCreateInstance: ") + resultName(r) + ")";
    else
      *whyNot = std::string("vkCreateInstance failed: ") + resultName(r);
    return false;
  }
  if (debugUtils) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (create) create(instance_, &messengerInfo, nullptr, &messenger_);
  }
  return true;
}

bool VulkanDevice::pickPhysicalDevice(std::string* whyNot) {
  uint32_t count = 0;
  VkResult r = vkEnumeratePhysicalDevices(instance_, &count, nullptr);
  if (r != VK_SUCCESS || count == 0) {
    *whyNot = "no physical device";
    return false;
  }
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance_, &count, devices.data());

  const char* wanted = adapter_.empty() ? std::getenv("PARITY_VK_DEVICE") : adapter_.c_str();
  if (wanted && !*wanted) wanted = nullptr;
  std::string names;
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    names += (names.empty() ? "" : ", ") + std::string(p.deviceName);
    if (wanted && !std::strstr(p.deviceName, wanted)) continue;
    if (p.apiVersion < VK_API_VERSION_1_3) continue;
    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &familyCount, families.data());
    for (uint32_t i = 0; i < familyCount; ++i) {
      VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
      if ((families[i].queueFlags & need) == need) {
        physical_ = d;
        props_ = p;
        queueFamily_ = i;
        timestampValidBits_ = families[i].timestampValidBits;
        vkGetPhysicalDeviceMemoryProperties(d, &memProps_);
        return true;
      }
    }
  }
  if (wanted)
    *whyNot = "no Vulkan 1.3 physical device matching PARITY_VK_DEVICE='" + std::string(wanted) +
              "' (found: " + names + ")";
  else
    *whyNot = "no Vulkan 1.3 physical device with a graphics and compute queue (found: " + names + ")";
  return false;
}

namespace {

// The VkBool32 members of the feature structures, in declaration order (vulkan_core.h).
constexpr const char* kFeatures10[] = {
    "robustBufferAccess", "fullDrawIndexUint32", "imageCubeArray", "independentBlend", "geometryShader",
    "tessellationShader", "sampleRateShading", "dualSrcBlend", "logicOp", "multiDrawIndirect",
    "drawIndirectFirstInstance", "depthClamp", "depthBiasClamp", "fillModeNonSolid", "depthBounds", "wideLines",
    "largePoints", "alphaToOne", "multiViewport", "samplerAnisotropy", "textureCompressionETC2",
    "textureCompressionASTC_LDR", "textureCompressionBC", "occlusionQueryPrecise", "pipelineStatisticsQuery",
    "vertexPipelineStoresAndAtomics", "fragmentStoresAndAtomics", "shaderTessellationAndGeometryPointSize",
    "shaderImageGatherExtended", "shaderStorageImageExtendedFormats", "shaderStorageImageMultisample",
    "shaderStorageImageReadWithoutFormat", "shaderStorageImageWriteWithoutFormat",
    "shaderUniformBufferArrayDynamicIndexing", "shaderSampledImageArrayDynamicIndexing",
    "shaderStorageBufferArrayDynamicIndexing", "shaderStorageImageArrayDynamicIndexing", "shaderClipDistance",
    "shaderCullDistance", "shaderFloat64", "shaderInt64", "shaderInt16", "shaderResourceResidency",
    "shaderResourceMinLod", "sparseBinding", "sparseResidencyBuffer", "sparseResidencyImage2D",
    "sparseResidencyImage3D", "sparseResidency2Samples", "sparseResidency4Samples", "sparseResidency8Samples",
    "sparseResidency16Samples", "sparseResidencyAliased", "variableMultisampleRate", "inheritedQueries"};
constexpr const char* kFeatures11[] = {
    "storageBuffer16BitAccess", "uniformAndStorageBuffer16BitAccess", "storagePushConstant16", "storageInputOutput16",
    "multiview", "multiviewGeometryShader", "multiviewTessellationShader", "variablePointersStorageBuffer",
    "variablePointers", "protectedMemory", "samplerYcbcrConversion", "shaderDrawParameters"};
constexpr const char* kFeatures12[] = {
    "samplerMirrorClampToEdge", "drawIndirectCount", "storageBuffer8BitAccess", "uniformAndStorageBuffer8BitAccess",
    "storagePushConstant8", "shaderBufferInt64Atomics", "shaderSharedInt64Atomics", "shaderFloat16", "shaderInt8",
    "descriptorIndexing", "shaderInputAttachmentArrayDynamicIndexing", "shaderUniformTexelBufferArrayDynamicIndexing",
    "shaderStorageTexelBufferArrayDynamicIndexing", "shaderUniformBufferArrayNonUniformIndexing",
    "shaderSampledImageArrayNonUniformIndexing", "shaderStorageBufferArrayNonUniformIndexing",
    "shaderStorageImageArrayNonUniformIndexing", "shaderInputAttachmentArrayNonUniformIndexing",
    "shaderUniformTexelBufferArrayNonUniformIndexing", "shaderStorageTexelBufferArrayNonUniformIndexing",
    "descriptorBindingUniformBufferUpdateAfterBind", "descriptorBindingSampledImageUpdateAfterBind",
    "descriptorBindingStorageImageUpdateAfterBind", "descriptorBindingStorageBufferUpdateAfterBind",
    "descriptorBindingUniformTexelBufferUpdateAfterBind", "descriptorBindingStorageTexelBufferUpdateAfterBind",
    "descriptorBindingUpdateUnusedWhilePending", "descriptorBindingPartiallyBound",
    "descriptorBindingVariableDescriptorCount", "runtimeDescriptorArray", "samplerFilterMinmax", "scalarBlockLayout",
    "imagelessFramebuffer", "uniformBufferStandardLayout", "shaderSubgroupExtendedTypes", "separateDepthStencilLayouts",
    "hostQueryReset", "timelineSemaphore", "bufferDeviceAddress", "bufferDeviceAddressCaptureReplay",
    "bufferDeviceAddressMultiDevice", "vulkanMemoryModel", "vulkanMemoryModelDeviceScope",
    "vulkanMemoryModelAvailabilityVisibilityChains", "shaderOutputViewportIndex", "shaderOutputLayer",
    "subgroupBroadcastDynamicId"};
constexpr const char* kFeatures13[] = {
    "robustImageAccess", "inlineUniformBlock", "descriptorBindingInlineUniformBlockUpdateAfterBind",
    "pipelineCreationCacheControl", "privateData", "shaderDemoteToHelperInvocation", "shaderTerminateInvocation",
    "subgroupSizeControl", "computeFullSubgroups", "synchronization2", "textureCompressionASTC_HDR",
    "shaderZeroInitializeWorkgroupMemory", "dynamicRendering", "shaderIntegerDotProduct", "maintenance4"};
// The names index the structures' VkBool32 members from the first: they must be contiguous.
static_assert(sizeof(VkPhysicalDeviceFeatures) == std::size(kFeatures10) * sizeof(VkBool32));
static_assert(offsetof(VkPhysicalDeviceVulkan11Features, shaderDrawParameters) ==
              offsetof(VkPhysicalDeviceVulkan11Features, storageBuffer16BitAccess) + (std::size(kFeatures11) - 1) * sizeof(VkBool32));
static_assert(offsetof(VkPhysicalDeviceVulkan12Features, subgroupBroadcastDynamicId) ==
              offsetof(VkPhysicalDeviceVulkan12Features, samplerMirrorClampToEdge) + (std::size(kFeatures12) - 1) * sizeof(VkBool32));
static_assert(offsetof(VkPhysicalDeviceVulkan13Features, maintenance4) ==
              offsetof(VkPhysicalDeviceVulkan13Features, robustImageAccess) + (std::size(kFeatures13) - 1) * sizeof(VkBool32));

bool hasExtension(VkPhysicalDevice physical, const char* name) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(), [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

template <size_t N>
void appendEnabled(const VkBool32* first, const char* const (&names)[N], std::vector<std::string>* out) {
  for (size_t i = 0; i < N; ++i)
    if (first[i]) out->push_back(names[i]);
}

}  // namespace

void VulkanDevice::recordFeatures(const VkPhysicalDeviceFeatures& f10, const VkPhysicalDeviceVulkan11Features& f11,
                                  const VkPhysicalDeviceVulkan12Features& f12, const VkPhysicalDeviceVulkan13Features& f13) {
  info_.features.clear();
  appendEnabled(&f10.robustBufferAccess, kFeatures10, &info_.features);
  appendEnabled(&f11.storageBuffer16BitAccess, kFeatures11, &info_.features);
  appendEnabled(&f12.samplerMirrorClampToEdge, kFeatures12, &info_.features);
  appendEnabled(&f13.robustImageAccess, kFeatures13, &info_.features);
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &count, extensions.data());
  info_.extensions.clear();
  for (const VkExtensionProperties& e : extensions) info_.extensions.push_back(e.extensionName);
}

bool VulkanDevice::createLogicalDevice(std::string* whyNot) {
  VkPhysicalDeviceVulkan13Features have13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceVulkan12Features have12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan11Features have11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
  VkPhysicalDeviceFeatures2 have{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  have.pNext = &have11;
  have11.pNext = &have12;
  have12.pNext = &have13;
  // OpenGL's provoking vertex (RasterState::provokingVertex), where the device has the extension.
  VkPhysicalDeviceProvokingVertexFeaturesEXT haveProvoking{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROVOKING_VERTEX_FEATURES_EXT};
  if (hasExtension(physical_, VK_EXT_PROVOKING_VERTEX_EXTENSION_NAME)) have13.pNext = &haveProvoking;
  vkGetPhysicalDeviceFeatures2(physical_, &have);
  if (!have13.dynamicRendering || !have13.synchronization2 || !have13.maintenance4) {
    *whyNot = std::string(props_.deviceName) + " lacks dynamicRendering, synchronization2 or maintenance4";
    return false;
  }

  // Every feature the device offers is enabled (shader tests bring shaders that use 16- and
  // 64-bit types, subgroup size control, ...), except those that change what a valid program
  // computes or need what this device does not create (robust access, protected memory,
  // address capture). maintenance4 is required: glslang emits SPIR-V 1.6 LocalSizeId for 1.3.
  VkPhysicalDeviceVulkan13Features use13 = have13;
  use13.pNext = nullptr;
  use13.robustImageAccess = VK_FALSE;
  VkPhysicalDeviceVulkan12Features use12 = have12;
  use12.pNext = &use13;
  use12.bufferDeviceAddressCaptureReplay = VK_FALSE;
  use12.bufferDeviceAddressMultiDevice = VK_FALSE;
  VkPhysicalDeviceVulkan11Features use11 = have11;
  use11.pNext = &use12;
  use11.protectedMemory = VK_FALSE;
  VkPhysicalDeviceFeatures2 use{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  use.pNext = &use11;
  use.features = have.features;
  use.features.robustBufferAccess = VK_FALSE;
  recordFeatures(use.features, use11, use12, use13);
  VkPhysicalDeviceProvokingVertexFeaturesEXT useProvoking{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROVOKING_VERTEX_FEATURES_EXT};
  std::vector<const char*> extensions;
  if (haveProvoking.provokingVertexLast) {
    useProvoking.provokingVertexLast = VK_TRUE;
    use13.pNext = &useProvoking;
    extensions.push_back(VK_EXT_PROVOKING_VERTEX_EXTENSION_NAME);
    info_.features.push_back("provokingVertexLast");
  }

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = queueFamily_;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  VkDeviceCreateInfo ci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  ci.pNext = &use;
  ci.queueCreateInfoCount = 1;
  ci.pQueueCreateInfos = &queueInfo;
  ci.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  ci.ppEnabledExtensionNames = extensions.data();
  VkResult r = vkCreateDevice(physical_, &ci, nullptr, &device_);
  if (r != VK_SUCCESS) {
    device_ = VK_NULL_HANDLE;
    *whyNot = std::string("vkCreateDevice failed: ") + resultName(r);
    return false;
  }
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.queueFamilyIndex = queueFamily_;
  VkCommandBufferAllocateInfo allocInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocInfo.commandBufferCount = 2;
  VkCommandBuffer cbs[2];
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  if (vkCreateCommandPool(device_, &poolInfo, nullptr, &commandPool_) != VK_SUCCESS ||
      (allocInfo.commandPool = commandPool_, vkAllocateCommandBuffers(device_, &allocInfo, cbs)) != VK_SUCCESS ||
      vkCreateFence(device_, &fenceInfo, nullptr, &fence_) != VK_SUCCESS) {
    *whyNot = "cannot create a command pool, command buffers or a fence";
    return false;
  }
  mainCmd_ = cbs[0];
  initCmd_ = cbs[1];

  bool timestamps = timestampValidBits_ > 0 && props_.limits.timestampComputeAndGraphics;
  if (timestamps) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = kMaxTimestamps;
    if (vkCreateQueryPool(device_, &qi, nullptr, &queryPool_) != VK_SUCCESS) queryPool_ = VK_NULL_HANDLE;
    timestampResetPending_ = queryPool_ != VK_NULL_HANDLE;
  }

  // --- info ---
  VkPhysicalDeviceDriverProperties driverProps{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceVulkan12Properties props12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_PROPERTIES};
  VkPhysicalDeviceVulkan13Properties props13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_PROPERTIES};
  driverProps.pNext = &props12;
  props12.pNext = &props13;
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props2.pNext = &driverProps;
  vkGetPhysicalDeviceProperties2(physical_, &props2);
  const std::pair<VkBool32, const char*> floatControls[] = {
      {props12.shaderSignedZeroInfNanPreserveFloat16, "shaderSignedZeroInfNanPreserveFloat16"},
      {props12.shaderSignedZeroInfNanPreserveFloat32, "shaderSignedZeroInfNanPreserveFloat32"},
      {props12.shaderSignedZeroInfNanPreserveFloat64, "shaderSignedZeroInfNanPreserveFloat64"},
      {props12.shaderDenormPreserveFloat16, "shaderDenormPreserveFloat16"},
      {props12.shaderDenormPreserveFloat32, "shaderDenormPreserveFloat32"},
      {props12.shaderDenormPreserveFloat64, "shaderDenormPreserveFloat64"},
      {props12.shaderDenormFlushToZeroFloat16, "shaderDenormFlushToZeroFloat16"},
      {props12.shaderDenormFlushToZeroFloat32, "shaderDenormFlushToZeroFloat32"},
      {props12.shaderDenormFlushToZeroFloat64, "shaderDenormFlushToZeroFloat64"},
      {props12.shaderRoundingModeRTEFloat16, "shaderRoundingModeRTEFloat16"},
      {props12.shaderRoundingModeRTEFloat32, "shaderRoundingModeRTEFloat32"},
      {props12.shaderRoundingModeRTEFloat64, "shaderRoundingModeRTEFloat64"},
      {props12.shaderRoundingModeRTZFloat16, "shaderRoundingModeRTZFloat16"},
      {props12.shaderRoundingModeRTZFloat32, "shaderRoundingModeRTZFloat32"},
      {props12.shaderRoundingModeRTZFloat64, "shaderRoundingModeRTZFloat64"}};
  info_.properties.clear();
  for (const auto& [holds, name] : floatControls)
    if (holds) info_.properties.push_back(name);
  info_.backend = "vk";
  info_.api = "Vulkan " + versionString(props_.apiVersion);
  info_.renderer = props_.deviceName;
  info_.driver = std::string(driverProps.driverName) + " " + driverProps.driverInfo;
  for (const char* var : {"VK_DRIVER_FILES", "VK_ICD_FILENAMES"}) {
    const char* value = std::getenv(var);
    if (value && *value) {
      info_.contextProvider = value;
      break;
    }
  }
  const VkPhysicalDeviceLimits& l = props_.limits;
  VkSampleCountFlags counts = l.framebufferColorSampleCounts & l.framebufferDepthSampleCounts &
                              l.framebufferStencilSampleCounts & l.sampledImageColorSampleCounts;
  info_.caps.maxSamples = (counts & VK_SAMPLE_COUNT_4_BIT) ? 4 : 1;
  info_.caps.textureViews = true;
  info_.caps.compute = true;
  info_.caps.timestamps = queryPool_ != VK_NULL_HANDLE;
  info_.caps.independentBlend = have.features.independentBlend;
  const VkPhysicalDeviceLimits& limits = props_.limits;
  info_.caps.maxOutputLocations[size_t(ShaderStage::Vertex)] = limits.maxVertexOutputComponents / 4;
  info_.caps.maxOutputLocations[size_t(ShaderStage::Geometry)] = limits.maxGeometryOutputComponents / 4;
  info_.caps.maxOutputLocations[size_t(ShaderStage::TessControl)] = limits.maxTessellationControlPerVertexOutputComponents / 4;
  info_.caps.maxOutputLocations[size_t(ShaderStage::TessEvaluation)] = limits.maxTessellationEvaluationOutputComponents / 4;
  info_.caps.storageMultisample =
      have.features.shaderStorageImageMultisample && (l.storageImageSampleCounts & VK_SAMPLE_COUNT_4_BIT);
  // Where the R64* formats are missing, the attributes are fed as 32-bit words (below).
  info_.caps.doubleVertexFormats = have.features.shaderFloat64;
  info_.caps.subgroupSizeControl = have13.subgroupSizeControl && have13.computeFullSubgroups &&
                                   (props13.requiredSubgroupSizeStages & VK_SHADER_STAGE_COMPUTE_BIT);
  info_.caps.minSubgroupSize = props13.minSubgroupSize;
  info_.caps.maxSubgroupSize = props13.maxSubgroupSize;
  info_.caps.viewports = have.features.multiViewport ? std::clamp<uint32_t>(limits.maxViewports, 1, kMaxViewports) : 1;
  info_.caps.maxSamplerLodBias = limits.maxSamplerLodBias;
  for (VkFormat f : {VK_FORMAT_R64_SFLOAT, VK_FORMAT_R64G64_SFLOAT, VK_FORMAT_R64G64B64_SFLOAT, VK_FORMAT_R64G64B64A64_SFLOAT}) {
    VkFormatProperties props{};
    vkGetPhysicalDeviceFormatProperties(physical_, f, &props);
    if (!(props.bufferFeatures & VK_FORMAT_FEATURE_VERTEX_BUFFER_BIT)) nativeDoubleVertexFormats_ = false;
  }
  return true;
}

VulkanDevice::~VulkanDevice() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    for (auto& release : deferred_) release();
    deferred_.clear();
    buffers_.forEach([&](BufferObject& b) {
      for (auto& [key, view] : b.views) vkDestroyBufferView(device_, view, nullptr);
      vkDestroyBuffer(device_, b.buffer, nullptr);
      vkFreeMemory(device_, b.memory, nullptr);
    });
    textures_.forEach([&](TextureObject& t) {
      for (auto& [key, view] : t.views) vkDestroyImageView(device_, view, nullptr);
      if (!t.isView) {
        vkDestroyImage(device_, t.image, nullptr);
        vkFreeMemory(device_, t.memory, nullptr);
      }
    });
    samplers_.forEach([&](SamplerObject& s) { vkDestroySampler(device_, s.sampler, nullptr); });
    shaders_.forEach([&](ShaderObject& s) { vkDestroyShaderModule(device_, s.module, nullptr); });
    pipelines_.forEach([&](PipelineObject& p) {
      vkDestroyPipeline(device_, p.pipeline, nullptr);
      destroyLayout(p.layout);
    });
    computePipelines_.forEach([&](ComputePipelineObject& p) {
      vkDestroyPipeline(device_, p.pipeline, nullptr);
      destroyLayout(p.layout);
    });
    vkDestroySampler(device_, defaultSampler_, nullptr);
    vkDestroySampler(device_, defaultCompareSampler_, nullptr);
    for (StagingChunk& c : staging_) {
      vkDestroyBuffer(device_, c.buffer, nullptr);
      vkFreeMemory(device_, c.memory, nullptr);
    }
    for (VkDescriptorPool p : descriptorPools_) vkDestroyDescriptorPool(device_, p, nullptr);
    vkDestroyQueryPool(device_, queryPool_, nullptr);
    vkDestroyFence(device_, fence_, nullptr);
    vkDestroyCommandPool(device_, commandPool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroyMessenger) destroyMessenger(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

// ---------------------------------------------------------------------------------------------
// Memory and staging
// ---------------------------------------------------------------------------------------------
bool VulkanDevice::allocateMemory(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                                  VkMemoryPropertyFlags preferred, VkDeviceMemory* out) {
  int best = -1;
  for (uint32_t i = 0; i < memProps_.memoryTypeCount; ++i) {
    if (!(req.memoryTypeBits & (1u << i))) continue;
    VkMemoryPropertyFlags flags = memProps_.memoryTypes[i].propertyFlags;
    if ((flags & required) != required) continue;
    if ((flags & preferred) == preferred) {
      best = static_cast<int>(i);
      break;
    }
    if (best < 0) best = static_cast<int>(i);
  }
  if (best < 0) return false;
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = static_cast<uint32_t>(best);
  return vkAllocateMemory(device_, &ai, nullptr, out) == VK_SUCCESS;
}

bool VulkanDevice::createHostBuffer(VkDeviceSize size, VkBufferUsageFlags usage, VkBuffer* buffer,
                                    VkDeviceMemory* memory, void** mapped) {
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = size;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  if (vkCreateBuffer(device_, &bi, nullptr, buffer) != VK_SUCCESS) return false;
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, *buffer, &req);
  // Cached memory makes readback fast; coherent memory needs no flush/invalidate calls.
  if (!allocateMemory(req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                      VK_MEMORY_PROPERTY_HOST_CACHED_BIT, memory)) {
    vkDestroyBuffer(device_, *buffer, nullptr);
    return false;
  }
  vkBindBufferMemory(device_, *buffer, *memory, 0);
  vkMapMemory(device_, *memory, 0, VK_WHOLE_SIZE, 0, mapped);
  return true;
}

VulkanDevice::StagingSlice VulkanDevice::stagingAlloc(VkDeviceSize size) {
  constexpr VkDeviceSize kAlign = 16;  // a multiple of every texel size and of 4 (depth copies)
  for (StagingChunk& c : staging_) {
    VkDeviceSize offset = (c.used + kAlign - 1) & ~(kAlign - 1);
    if (offset + size <= c.size) {
      c.used = offset + size;
      return {c.buffer, offset, c.mapped + offset};
    }
  }
  StagingChunk c;
  c.size = std::max(size, kStagingChunkSize);
  void* mapped = nullptr;
  if (!createHostBuffer(c.size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, &c.buffer, &c.memory, &mapped)) return {};
  c.mapped = static_cast<uint8_t*>(mapped);
  c.used = size;
  staging_.push_back(c);
  return {c.buffer, 0, c.mapped};
}

VkFormatFeatureFlags VulkanDevice::formatFeatures(VkFormat f) const {
  VkFormatProperties p{};
  vkGetPhysicalDeviceFormatProperties(physical_, f, &p);
  return p.optimalTilingFeatures;
}

// ---------------------------------------------------------------------------------------------
// Recording and submission
// ---------------------------------------------------------------------------------------------
void VulkanDevice::beginRecording() {
  vkResetCommandPool(device_, commandPool_, 0);
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkBeginCommandBuffer(initCmd_, &bi);
  vkBeginCommandBuffer(mainCmd_, &bi);
  initUsed_ = false;
  if (timestampResetPending_) recordPendingTimestampReset();
}

VkCommandBuffer VulkanDevice::initCmd() {
  initUsed_ = true;
  return initCmd_;
}

void VulkanDevice::globalBarrier(VkCommandBuffer cb, bool toHost) {
  VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  mb.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  mb.srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT;
  mb.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  mb.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
  if (toHost) {
    mb.dstStageMask |= VK_PIPELINE_STAGE_2_HOST_BIT;
    mb.dstAccessMask |= VK_ACCESS_2_HOST_READ_BIT;
  }
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &mb;
  vkCmdPipelineBarrier2(cb, &dep);
}

void VulkanDevice::defer(std::function<void()> release) { deferred_.push_back(std::move(release)); }

void VulkanDevice::flushAndWait() {
  if (inPass_) {  // submit() inside a pass breaks the RHI's rules; keep Vulkan valid anyway
    vkCmdEndRendering(mainCmd_);
    inPass_ = false;
  }
  vkEndCommandBuffer(initCmd_);
  vkEndCommandBuffer(mainCmd_);
  VkCommandBuffer cbs[2] = {initCmd_, mainCmd_};
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = initUsed_ ? 2 : 1;
  si.pCommandBuffers = initUsed_ ? cbs : cbs + 1;
  VkResult r = vkQueueSubmit(queue_, 1, &si, fence_);
  if (r == VK_SUCCESS) r = vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX);
  if (r != VK_SUCCESS) {
    debugMessage(std::string("Vulkan error: queue submission failed: ") + resultName(r));
    vkDeviceWaitIdle(device_);
  }
  vkResetFences(device_, 1, &fence_);
  timestampsSubmitted_ = timestampCount_;

  for (auto& release : deferred_) release();
  deferred_.clear();
  for (VkDescriptorPool p : descriptorPools_) vkResetDescriptorPool(device_, p, 0);
  currentPool_ = 0;
  // Keep one ordinary staging chunk for the next uploads; give back the rest.
  size_t kept = 0;
  for (StagingChunk& c : staging_) {
    if (kept == 0 && c.size == kStagingChunkSize) {
      c.used = 0;
      staging_[kept++] = c;
    } else {
      vkDestroyBuffer(device_, c.buffer, nullptr);
      vkFreeMemory(device_, c.memory, nullptr);
    }
  }
  staging_.resize(kept);
  beginRecording();
}

void VulkanDevice::submit() { flushAndWait(); }

}  // namespace parity::rhi::vulkan
