#include "viewer/viewer.h"

#include <volk.h>
// GLFW after volk: it declares its Vulkan functions when VK_VERSION_1_0 is defined.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include "core/log.h"
#include "core/memory.h"
#include "core/strings.h"
#include "core/timer.h"
#include "image/camera.h"
#include "image/image_io.h"
#include "image/renderer.h"
#include "image/texture_detail.h"
#include "spectral/color.h"
#include "viewer/build_status.h"
#include "viewer/detail_textures.h"
#include "viewer/display_values.h"
#include "viewer/material_edit.h"
#include "viewer/patch_pipeline.h"
#include "viewer/solve_worker.h"
#include "viewer/swapchain.h"
#include "viewer/ui.h"
#include "viewer/view_camera.h"
#include "vulkan/vk_check.h"

namespace daisy::viewer {
namespace {

constexpr int kFramesInFlight = 2;
// The automatic exposure is measured on a ray-cast image this many times smaller per axis than
// the window (the test mode's last frame: full size, as `daisy render`), at most this often.
constexpr int kExposureDownscale = 4;
constexpr double kExposureIntervalSeconds = 0.25;
// A changed measurement is approached exponentially with this time constant, so the picture's
// brightness glides (an edit's converged solve would otherwise jump it: 186 -> 229 on a wall).
constexpr double kExposureEaseSeconds = 0.3;
// While the solver runs, frames are at least this far apart, so a CPU Vulkan driver (lavapipe)
// leaves the cores to the solve; the picture still updates at every published iterate.
constexpr double kSolvingFrameSeconds = 1.0 / 30;

struct Frame {
    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    VkSemaphore imageAvailable = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
};

// What the GLFW callbacks saw since the loop last looked (Dear ImGui's back-end chains to them).
struct InputEvents {
    double scroll = 0;
    bool activity = false;  // any input or window event: the picture may change
    // Left clicks (press and release within kClickPixels, window coordinates), recorded by the
    // mouse-button callback, so a click shorter than a frame is never lost.
    std::array<double, 2> pressAt{-1e9, -1e9};
    std::vector<std::array<double, 2>> clicks;
};

// A press and release this close (window pixels) is a click, not a drag.
constexpr double kClickPixels = 3;

// The automatic exposure of the view (image/exposure.h autoExposureScale, as `daisy render`
// applies it) measured on a ray-cast image of the snapshot's smooth corner values, with `detail`
// (texture detail, and the face of a double-sided surface the camera sees, as daisy render).
double measureExposure(const PatchMesh& mesh, const Camera& camera, const DisplaySnapshot& snapshot,
                       const SurfaceDetail& detail, int width, int height) {
    const ChannelLayout& layout = snapshot.layout;
    const std::size_t channels = std::size_t(layout.count());
    const std::size_t corners = snapshot.corners.size() / channels;
    std::vector<float> xyz(corners * 4);  // X Y Z coverage
    for (std::size_t c = 0; c < corners; ++c) {
        const float* v = snapshot.corners.data() + c * channels;
        for (int k = 0; k < 4; ++k)
            xyz[c * 4 + std::size_t(k)] = v[layout.x() + k];
    }
    RenderSettings settings;
    settings.width = std::max(width, 1);
    settings.height = std::max(height, 1);
    const float miss[4] = {0, 0, 0, 0};
    const float backFace[4] = {0, 0, 0, 1};  // black and covered, as daisy render
    Camera imageCamera = camera;
    imageCamera.aspectRatio = 0;
    auto image = renderCornerValues(mesh, imageCamera, settings, xyz, 4, miss, &detail, backFace);
    return image ? autoExposureScale(*image) : 1.0;
}

// The rows of display RGB from XYZ times `scale` (spectral/color.h, IEC 61966-2-1).
void colourRows(double scale, float rows[9]) {
    for (int row = 0; row < 3; ++row) {
        for (int column = 0; column < 3; ++column) {
            Xyz unit{0, 0, 0};
            unit[std::size_t(column)] = 1;
            const Rgb rgb = xyzToLinearSrgb(unit);
            rows[row * 3 + column] = static_cast<float>(rgb[std::size_t(row)] * scale);
        }
    }
}

class Viewer {
public:
    Viewer(Session session, const ViewerOptions& options)
        : options_(options),
          worker_(std::move(session), true),
          surfaceDetail_(worker_.initialScene(), worker_.patches(), worker_.initialAppearance(),
                         0) {}
    ~Viewer();

    // 0, or the exit status of a failure (message logged).
    int open();
    int run();

private:
    // The render pass, pipeline, buffers, frames and swapchain on the open device.
    Expected<void> createDeviceResources();
    Expected<void> initImgui();
    // False when the window is minimised (nothing made).
    Expected<bool> recreateSwapchain();
    void handleInput(double dt);
    bool heldKey() const;  // a movement key is down (fly keys move every frame)
    void applyCameraRequest();
    void updateValues(int frame, const DisplaySnapshot& snapshot);
    void updateExposure(const DisplaySnapshot& snapshot, bool exact);
    // Draws one frame; `capture` copies its pixels into the read-back buffer. False when the
    // frame was skipped (swapchain out of date, minimised); an Error when a device call failed.
    Expected<bool> drawFrame(bool capture);
    Expected<void> writeCapture(const std::string& path);
    void exerciseWindow(int frame);
    // After a scripted edit: when the first frame showing an updated iterate, and the first
    // showing the converged solution, were submitted (seconds after the edit was posted).
    void trackEdit();
    // Logs the first frame, and the first showing a converged solution, with their time since
    // the command started and what they showed.
    void logOpening(bool drawn);

    ViewerOptions options_;
    SolveWorker worker_;
    SurfaceDetail surfaceDetail_;  // the exposure measurement's (image/texture_detail.h)
    Scene scene_;  // the scene as loaded: cameras and names (materials live in the worker)
    GLFWwindow* window_ = nullptr;
    VulkanContext context_;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    SurfaceFormats formats_;
    VkRenderPass renderPass_ = VK_NULL_HANDLE;
    Swapchain swapchain_;
    PatchPipeline pipeline_;
    PatchBuffers buffers_;
    DetailTextures detail_;  // texture detail; empty (no sets) when nothing varies
    Frame frames_[kFramesInFlight];
    HostBuffer readback_;
    VkDescriptorPool imguiPool_ = VK_NULL_HANDLE;
    bool showPanel_ = true;
    // The part of the window the picture fills: right of the docked panel while it is shown.
    VkRect2D sceneArea() const;
    bool imgui_ = false;
    bool resized_ = false;
    int frame_ = 0;
    uint64_t framesDrawn_ = 0;

    std::optional<ViewCamera> camera_;
    Camera startCamera_;
    double sceneSize_ = 1;  // bounding-box diagonal, scene units
    Vec3d sceneLow_{0, 0, 0}, sceneHigh_{0, 0, 0};  // bounding box of the patches
    int cameraIndex_ = -1;
    UiState ui_;
    DisplaySettings valueSettings_[kFramesInFlight];
    std::vector<float> values_;
    std::vector<std::string> pendingEdits_;
    double editPostedAt_ = -1;
    uint64_t editVersion_ = 0;
    double firstImageSeconds_ = -1, convergedSeconds_ = -1;
    // The first updated frame finished (its fence), and the process CPU from the edit to then.
    double firstImageDoneSeconds_ = -1, firstImageCpuSeconds_ = -1;
    double editPostedCpu_ = 0;
    uint64_t shownVersion_ = 0;  // the snapshot the last frame drew
    uint64_t shownProgress_ = 0;  // the BuildProgress version the last frame drew
    bool firstFrameLogged_ = false, convergedFrameLogged_ = false;
    bool shownSolving_ = false;
    double shownSinceEdit_ = -1;  // the shown snapshot's age of the edit when published
    double firstPublishedSeconds_ = -1, convergedPublishedSeconds_ = -1;

    double exposureScale_ = 1;  // applied to the picture
    double exposureTarget_ = 1;  // the last measurement, which exposureScale_ eases towards
    double exposureEasedAt_ = -1;
    bool exposureExact_ = false;
    uint64_t exposureVersion_ = 0;
    std::optional<Camera> exposureCamera_;
    double exposureAt_ = -1;
    bool exposurePending_ = false;
    Timer clock_;

    double lastMouseX_ = 0, lastMouseY_ = 0;
    bool dragging_ = false;
    InputEvents events_;
    int settleFrames_ = 0;  // frames still to draw after the last input (Dear ImGui's hover)
    bool f12Down_ = false, rDown_ = false, homeDown_ = false, zDown_ = false, yDown_ = false,
         cDown_ = false, fDown_ = false, tabDown_ = false;
};

InputEvents& eventsOf(GLFWwindow* window) {
    return *static_cast<InputEvents*>(glfwGetWindowUserPointer(window));
}

void installEventCallbacks(GLFWwindow* window) {
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double y) {
        eventsOf(w).scroll += y;
        eventsOf(w).activity = true;
    });
    glfwSetCursorPosCallback(window,
                             [](GLFWwindow* w, double, double) { eventsOf(w).activity = true; });
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
        InputEvents& events = eventsOf(w);
        events.activity = true;
        if (button != GLFW_MOUSE_BUTTON_LEFT) return;
        double x = 0, y = 0;
        glfwGetCursorPos(w, &x, &y);
        if (action == GLFW_PRESS) {
            events.pressAt = {x, y};
        } else if (action == GLFW_RELEASE && std::abs(x - events.pressAt[0]) < kClickPixels &&
                   std::abs(y - events.pressAt[1]) < kClickPixels) {
            events.clicks.push_back({x, y});
        }
    });
    glfwSetKeyCallback(window,
                       [](GLFWwindow* w, int, int, int, int) { eventsOf(w).activity = true; });
    glfwSetCharCallback(window, [](GLFWwindow* w, unsigned int) { eventsOf(w).activity = true; });
    glfwSetWindowFocusCallback(window, [](GLFWwindow* w, int) { eventsOf(w).activity = true; });
    glfwSetWindowRefreshCallback(window, [](GLFWwindow* w) { eventsOf(w).activity = true; });
}

Viewer::~Viewer() {
    if (context_.device) {
        vkDeviceWaitIdle(context_.device);
        if (imgui_) {
            ImGui_ImplVulkan_Shutdown();
            ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext();
        }
        if (imguiPool_) vkDestroyDescriptorPool(context_.device, imguiPool_, nullptr);
        for (Frame& frame : frames_) {
            if (frame.fence) vkDestroyFence(context_.device, frame.fence, nullptr);
            if (frame.imageAvailable)
                vkDestroySemaphore(context_.device, frame.imageAvailable, nullptr);
        }
        destroyHostBuffer(context_, readback_);
        destroyPatchBuffers(context_, buffers_);
        destroyDetailTextures(context_, detail_);
        destroyPatchPipeline(context_, pipeline_);
        destroySwapchain(context_, swapchain_);
        if (renderPass_) vkDestroyRenderPass(context_.device, renderPass_, nullptr);
    }
    if (surface_) vkDestroySurfaceKHR(context_.instance, surface_, nullptr);
    destroyContext(context_);
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

int Viewer::open() {
    scene_ = worker_.initialScene();
    // Fail fast on the options before the window opens.
    const double aspect = double(options_.width) / double(options_.height);
    auto chosen = chooseCamera(scene_, options_.camera, aspect);
    if (!chosen) {
        logError(concat("--camera: ", chosen.error().message));
        return 2;
    }
    for (const std::string& text : options_.edits) {
        auto edit = parseMaterialEdit(text);
        if (!edit) {
            logError(edit.error().message);
            return 2;
        }
        auto targets = editTargets(scene_, *edit);
        if (!targets) {
            logError(targets.error().message);
            return 2;
        }
    }
    if (!options_.display.empty()) {
        auto display = parseDisplay(options_.display);
        if (!display) {
            logError(display.error().message);
            return 2;
        }
        ui_.display = display->settings;
        ui_.wireframe = display->wireframe;
        if (display->wavelengthNm) {
            const std::vector<double>& samples = worker_.latest()->wavelengthsNm;
            ui_.display.wavelengthIndex = nearestSample(samples, *display->wavelengthNm);
            logInfo(concat("view: false colour of the radiance at the sample ",
                           formatNumber(samples[ui_.display.wavelengthIndex], 4), " nm"));
        }
    }
    pendingEdits_ = options_.edits;
    startCamera_ = *chosen;
    startCamera_.aspectRatio = 0;
    Vec3d lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const Vec3d& p : worker_.patches().positions) {
        for (int axis = 0; axis < 3; ++axis) {
            lo[axis] = std::min(lo[axis], p[axis]);
            hi[axis] = std::max(hi[axis], p[axis]);
        }
    }
    if (worker_.patches().positions.empty()) lo = hi = Vec3d{0, 0, 0};
    sceneLow_ = lo;
    sceneHigh_ = hi;
    sceneSize_ = std::max(length(hi - lo), 1e-6);
    double orbitDistance = defaultOrbitDistance(startCamera_, lo, hi);
    if (options_.camera.empty() && scene_.cameras.empty()) {
        // No camera in the file: start outside the geometry, looking at all of it (the automatic
        // framing's direction), rather than inside a room next to whatever stands there.
        const bool panel = options_.frames == 0 || options_.panel;
        const double pictureWidth =
            options_.width - (panel ? std::min(double(kPanelWidth), options_.width / 2.0) : 0.0);
        const Framing framing = frameAll(startCamera_, lo, hi, pictureWidth / options_.height);
        startCamera_ = framing.camera;
        orbitDistance = framing.orbitDistance;
    }
    camera_.emplace(startCamera_, orbitDistance);
    showPanel_ = options_.frames == 0;

    if (!glfwInit()) {
        logError(
            "daisy view: cannot open a window (no display: set DISPLAY, or run under xvfb-run)");
        return 1;
    }
    if (!glfwVulkanSupported()) {
        logError("daisy view: GLFW finds no Vulkan loader (install a Vulkan driver)");
        return 1;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window_ = glfwCreateWindow(options_.width, options_.height, "daisy view", nullptr, nullptr);
    if (!window_) {
        logError("daisy view: cannot create a window");
        return 1;
    }
    glfwSetWindowUserPointer(window_, &events_);
    installEventCallbacks(window_);

    uint32_t extensionCount = 0;
    const char** extensions = glfwGetRequiredInstanceExtensions(&extensionCount);
    auto instance = createInstance(std::span<const char* const>(extensions, extensionCount));
    if (!instance) {
        logError(concat("daisy view: ", instance.error().message));
        return 1;
    }
    context_.instance = *instance;
    const VkResult surfaceResult =
        glfwCreateWindowSurface(context_.instance, window_, nullptr, &surface_);
    if (surfaceResult != VK_SUCCESS) {
        logError(concat("daisy view: cannot create a Vulkan surface for the window (",
                        vkResultName(surfaceResult), ")"));
        return 1;
    }
    DeviceRequirements requirements;
    requirements.compute = false;
    requirements.graphics = true;
    requirements.presentSurface = surface_;
    auto physicalDevice = pickPhysicalDevice(context_.instance, options_.device, requirements);
    if (!physicalDevice) {
        logError(concat("daisy view: ", physicalDevice.error().message));
        return options_.device.empty() ? 1 : 2;
    }
    const VkInstance ownedInstance = context_.instance;
    context_.instance = VK_NULL_HANDLE;  // createDevice owns it from here, also on failure
    auto context = createDevice(ownedInstance, *physicalDevice, requirements);
    if (!context) {
        vkDestroySurfaceKHR(ownedInstance, surface_, nullptr);
        surface_ = VK_NULL_HANDLE;
        logError(concat("daisy view: ", context.error().message));
        return 1;
    }
    context_ = *context;
    logInfo(concat("view: device '", context_.properties.deviceName, "' (",
                   deviceTypeName(context_.properties.deviceType), ")"));

    if (auto made = createDeviceResources(); !made) {
        logError(concat("daisy view: ", made.error().message));
        return 2;
    }
    logVerbose(concat("view: window, device and pipeline ready ",
                      formatNumber(secondsSince(options_.startedAt) * 1e3, 3),
                      " ms after the start"));
    const std::string materialsPath = !options_.saveMaterialsPath.empty()
        ? options_.saveMaterialsPath
        : std::filesystem::path(scene_.path).stem().string() + ".materials.json";
    initUi(ui_, scene_, options_.wavelengthsText, materialsPath);
    ui_.autoExposure = options_.exposure.automatic;
    ui_.ev = static_cast<float>(options_.exposure.ev);
    if (showPanel_ || options_.panel) {
        if (auto made = initImgui(); !made) {
            logError(concat("daisy view: ", made.error().message));
            return 2;
        }
    }
    showPanel_ = showPanel_ || options_.panel;
    return 0;
}

// What it made stays in the members for the destructor when it fails.
Expected<void> Viewer::createDeviceResources() {
    formats_ = chooseSurfaceFormats(context_, surface_);
    auto renderPass = createRenderPass(context_, formats_);
    if (!renderPass) return renderPass.error();
    renderPass_ = *renderPass;
    // Texture detail where a material's colour varies; the plain pipeline otherwise.
    const DetailVertices detail =
        detailVertices(worker_.initialScene(), worker_.patches(), worker_.initialAppearance());
    if (!detail.empty()) {
        auto textures = createDetailTextures(context_, worker_.initialScene(), detail);
        if (!textures) return textures.error();
        detail_ = std::move(*textures);
        logVerbose(concat("view: texture detail: ", detail.textures.size() - 1, " textures, ",
                          detail.runs.size(), " draws"));
    }
    auto pipeline = createPatchPipeline(context_, renderPass_, detail_.setLayout);
    if (!pipeline) return pipeline.error();
    pipeline_ = *pipeline;
    auto buffers = createPatchBuffers(context_, worker_.patches(), kFramesInFlight);
    if (!buffers) return buffers.error();
    buffers_ = std::move(*buffers);
    for (Frame& frame : frames_) {
        VkCommandBufferAllocateInfo allocateInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        allocateInfo.commandPool = context_.commandPool;
        allocateInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        allocateInfo.commandBufferCount = 1;
        VK_CHECK(vkAllocateCommandBuffers(context_.device, &allocateInfo, &frame.commandBuffer));
        VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VK_CHECK(
            vkCreateSemaphore(context_.device, &semaphoreInfo, nullptr, &frame.imageAvailable));
        VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;
        VK_CHECK(vkCreateFence(context_.device, &fenceInfo, nullptr, &frame.fence));
    }
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    auto created = createSwapchain(context_, surface_, formats_, renderPass_, uint32_t(width),
                                   uint32_t(height), swapchain_);
    if (!created) return created.error();
    return {};
}

Expected<void> Viewer::initImgui() {
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    poolInfo.maxSets = 16;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    VK_CHECK(vkCreateDescriptorPool(context_.device, &poolInfo, nullptr, &imguiPool_));
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsDark();
    // Chains to the scroll callback installed above.
    ImGui_ImplGlfw_InitForVulkan(window_, true);
    // The prebuilt Dear ImGui would call the vk* prototypes volk replaces: load through volk.
    ImGui_ImplVulkan_LoadFunctions(
        [](const char* name, void* instance) {
            return vkGetInstanceProcAddr(static_cast<VkInstance>(instance), name);
        },
        context_.instance);
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = context_.instance;
    info.PhysicalDevice = context_.physicalDevice;
    info.Device = context_.device;
    info.QueueFamily = context_.queueFamily;
    info.Queue = context_.queue;
    info.DescriptorPool = imguiPool_;
    info.Subpass = 0;
    info.MinImageCount = std::max(swapchain_.minImageCount, 2u);
    info.ImageCount = std::max<uint32_t>(uint32_t(swapchain_.images.size()), info.MinImageCount);
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    ImGui_ImplVulkan_Init(&info, renderPass_);
    imgui_ = true;  // the destructor shuts Dear ImGui down from here on
    auto fonts = submitAndWait(context_, [](VkCommandBuffer commandBuffer) {
        ImGui_ImplVulkan_CreateFontsTexture(commandBuffer);
    });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
    return fonts;
}

Expected<bool> Viewer::recreateSwapchain() {
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    if (width == 0 || height == 0) return false;
    VK_CHECK(vkDeviceWaitIdle(context_.device));
    auto created = createSwapchain(context_, surface_, formats_, renderPass_, uint32_t(width),
                                   uint32_t(height), swapchain_);
    if (!created || !*created) return created;
    if (imgui_) ImGui_ImplVulkan_SetMinImageCount(std::max(swapchain_.minImageCount, 2u));
    resized_ = false;
    return true;
}

void Viewer::applyCameraRequest() {
    if (ui_.frameAllRequest) {
        ui_.frameAllRequest = false;
        const VkExtent2D area = sceneArea().extent;
        const Framing framing = frameAll(camera_->camera(), sceneLow_, sceneHigh_,
                                         double(area.width) / std::max(double(area.height), 1.0));
        camera_.emplace(framing.camera, framing.orbitDistance);
        cameraIndex_ = -1;
    }
    if (ui_.cameraRequest == -1) return;
    const double distance = camera_->orbitDistance();
    if (ui_.cameraRequest == -2) {
        camera_.emplace(startCamera_, distance);
        cameraIndex_ = -1;
    } else if (ui_.cameraRequest >= 0 && std::size_t(ui_.cameraRequest) < scene_.cameras.size()) {
        Camera camera = scene_.cameras[std::size_t(ui_.cameraRequest)];
        camera.aspectRatio = 0;
        camera_.emplace(camera, distance);
        cameraIndex_ = ui_.cameraRequest;
    }
    ui_.cameraRequest = -1;
}

// Edge-triggered key press.
bool pressed(GLFWwindow* window, int key, bool& down) {
    const bool now = glfwGetKey(window, key) == GLFW_PRESS;
    const bool edge = now && !down;
    down = now;
    return edge;
}

bool Viewer::heldKey() const {
    for (int key : {GLFW_KEY_W, GLFW_KEY_A, GLFW_KEY_S, GLFW_KEY_D, GLFW_KEY_Q, GLFW_KEY_E}) {
        if (glfwGetKey(window_, key) == GLFW_PRESS) return true;
    }
    return false;
}

void Viewer::handleInput(double dt) {
    const bool mouseTaken = imgui_ && showPanel_ && ImGui::GetIO().WantCaptureMouse;
    const bool keysTaken = imgui_ && showPanel_ && ImGui::GetIO().WantCaptureKeyboard;
    double x = 0, y = 0;
    glfwGetCursorPos(window_, &x, &y);
    const double dx = x - lastMouseX_, dy = y - lastMouseY_;
    lastMouseX_ = x;
    lastMouseY_ = y;
    int windowWidth = 1, windowHeight = 1;
    glfwGetWindowSize(window_, &windowWidth, &windowHeight);
    const bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    const bool right = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
        glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
    if (!mouseTaken) {
        if (left && !dragging_) dragging_ = true;
        if (left && (dx != 0 || dy != 0)) {
            const double radiansPerPixel = 0.005;
            if (ui_.fly) {
                camera_->look(-dx * radiansPerPixel, -dy * radiansPerPixel);
            } else {
                camera_->orbit(-dx * radiansPerPixel, -dy * radiansPerPixel);
            }
        }
        if (right && (dx != 0 || dy != 0)) {
            const double perPixel = 2 * camera_->orbitDistance() *
                std::tan(0.5 * camera_->camera().yFovRad) / std::max(windowHeight, 1);
            camera_->pan(-dx * perPixel, dy * perPixel);
        }
        if (events_.scroll != 0) camera_->dolly(0.1 * events_.scroll);
    }
    events_.scroll = 0;
    if (!left) dragging_ = false;
    for (const auto& [clickX, clickY] : events_.clicks) {
        if (mouseTaken) continue;
        int width = 1, height = 1;
        glfwGetFramebufferSize(window_, &width, &height);
        const double sx = double(width) / std::max(windowWidth, 1);
        const double sy = double(height) / std::max(windowHeight, 1);
        const VkRect2D area = sceneArea();
        ui_.picked = pickPatch(worker_.patches(), camera_->camera(), int(area.extent.width),
                               int(area.extent.height), clickX * sx - area.offset.x,
                               clickY * sy - area.offset.y);
    }
    events_.clicks.clear();
    if (keysTaken) return;
    const double speed = 0.3 * sceneSize_ * dt;
    const auto key = [&](int k) { return glfwGetKey(window_, k) == GLFW_PRESS ? 1.0 : 0.0; };
    const double forward = key(GLFW_KEY_W) - key(GLFW_KEY_S);
    const double sideways = key(GLFW_KEY_D) - key(GLFW_KEY_A);
    const double up = key(GLFW_KEY_E) - key(GLFW_KEY_Q);
    if (forward != 0 || sideways != 0 || up != 0)
        camera_->fly(forward * speed, sideways * speed, up * speed);
    if (pressed(window_, GLFW_KEY_R, rDown_)) ui_.cameraRequest = -2;
    if (pressed(window_, GLFW_KEY_HOME, homeDown_)) ui_.frameAllRequest = true;
    const bool control = glfwGetKey(window_, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS ||
        glfwGetKey(window_, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS;
    const bool shift = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
        glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    if (pressed(window_, GLFW_KEY_Z, zDown_) && control)
        (shift ? ui_.redoRequest : ui_.undoRequest) = true;
    if (pressed(window_, GLFW_KEY_Y, yDown_) && control) ui_.redoRequest = true;
    if (pressed(window_, GLFW_KEY_C, cDown_) && !scene_.cameras.empty())
        ui_.cameraRequest = (cameraIndex_ + 1) % int(scene_.cameras.size());
    if (pressed(window_, GLFW_KEY_F, fDown_)) ui_.fly = !ui_.fly;
    if (pressed(window_, GLFW_KEY_TAB, tabDown_) && imgui_) showPanel_ = !showPanel_;
    if (pressed(window_, GLFW_KEY_F12, f12Down_)) ui_.screenshotRequest = true;
}

void Viewer::updateValues(int frame, const DisplaySnapshot& snapshot) {
    if (buffers_.valueVersions[std::size_t(frame)] == snapshot.version &&
        valueSettings_[frame] == ui_.display)
        return;
    ui_.range = displayValues(snapshot, ui_.display, values_);
    std::memcpy(buffers_.values[std::size_t(frame)].mapped, values_.data(),
                std::min<std::size_t>(values_.size() * sizeof(float),
                                      buffers_.values[std::size_t(frame)].bytes));
    buffers_.valueVersions[std::size_t(frame)] = snapshot.version;
    valueSettings_[frame] = ui_.display;
}

bool sameCamera(const Camera& a, const Camera& b) {
    return a.position == b.position && a.forward == b.forward && a.up == b.up &&
        a.yFovRad == b.yFovRad;
}

void Viewer::updateExposure(const DisplaySnapshot& snapshot, bool exact) {
    const double now = clock_.seconds();
    const double dt = exposureEasedAt_ < 0 ? 0 : now - exposureEasedAt_;
    exposureEasedAt_ = now;
    if (!ui_.autoExposure) {
        exposureScale_ = std::exp2(double(ui_.ev));
        exposureTarget_ = exposureScale_;
        exposureCamera_.reset();
        exposurePending_ = false;
        ui_.appliedEv = ui_.ev;
        return;
    }
    const bool sameView = exposureCamera_ && sameCamera(*exposureCamera_, camera_->camera());
    // While a solve converges the exposure stays (no flicker, and no ray cast between an edit
    // and its first image); it is measured again when the solve ends or the view moves.
    const bool current = sameView &&
        ((exposureVersion_ == snapshot.version && (exposureExact_ || !exact)) ||
         (snapshot.solving && !exact));
    exposurePending_ = false;
    if (!current) {
        if (!exact && exposureAt_ >= 0 && now - exposureAt_ < kExposureIntervalSeconds) {
            exposurePending_ = true;  // measured at a later frame: keep drawing until then
        } else {
            const int divisor = exact ? 1 : kExposureDownscale;
            const bool first = exposureAt_ < 0;
            const VkExtent2D area = sceneArea().extent;
            exposureTarget_ =
                measureExposure(worker_.patches(), camera_->camera(), snapshot, surfaceDetail_,
                                int(area.width) / divisor, int(area.height) / divisor);
            if (first) exposureScale_ = exposureTarget_;
            exposureVersion_ = snapshot.version;
            exposureCamera_ = camera_->camera();
            exposureExact_ = exact;
            exposureAt_ = clock_.seconds();
        }
    }
    // A new measurement eases in (in stops, time constant kExposureEaseSeconds) instead of
    // jumping; the exact measurement of a screenshot applies at once.
    const double target = std::log2(exposureTarget_), shown = std::log2(exposureScale_);
    if (exact || std::abs(target - shown) < 0.01) {
        exposureScale_ = exposureTarget_;
    } else {
        const double step = 1 - std::exp(-dt / kExposureEaseSeconds);
        exposureScale_ = std::exp2(shown + (target - shown) * step);
        exposurePending_ = true;  // keep drawing until it arrives
    }
    ui_.appliedEv = std::log2(exposureScale_);
}

VkRect2D Viewer::sceneArea() const {
    const VkExtent2D full = swapchain_.extent;
    const uint32_t panel = imgui_ && showPanel_ && !ui_.panelCollapsed
        ? std::min(uint32_t(kPanelWidth), full.width / 2)
        : 0;
    return {{int32_t(panel), 0}, {full.width - panel, full.height}};
}

Expected<bool> Viewer::drawFrame(bool capture) {
    if (resized_ || !swapchain_.swapchain) {
        auto recreated = recreateSwapchain();
        if (!recreated || !*recreated) return recreated;
    }
    Frame& frame = frames_[frame_];
    VK_CHECK(vkWaitForFences(context_.device, 1, &frame.fence, VK_TRUE, UINT64_MAX));
    uint32_t imageIndex = 0;
    const VkResult acquired =
        vkAcquireNextImageKHR(context_.device, swapchain_.swapchain, UINT64_MAX,
                              frame.imageAvailable, VK_NULL_HANDLE, &imageIndex);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
        auto recreated = recreateSwapchain();
        if (!recreated) return recreated.error();
        return false;
    }
    if (acquired != VK_SUBOPTIMAL_KHR) VK_CHECK(acquired);
    shownProgress_ = worker_.buildProgress().version;
    const std::shared_ptr<const DisplaySnapshot> snapshot = worker_.latest();
    updateValues(frame_, *snapshot);
    shownVersion_ = snapshot->version;
    shownSolving_ = snapshot->solving;
    shownSinceEdit_ = snapshot->secondsSinceEdit;
    updateExposure(*snapshot, capture && options_.frames > 0);

    if (imgui_) {
        ImGui_ImplVulkan_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        if (showPanel_) drawPanel(ui_, *snapshot, worker_, scene_);
        drawBuildStatus(worker_.buildProgress(), *snapshot);
        ImGui::Render();
    }

    shared::ViewerPush push{};
    const VkRect2D area = sceneArea();
    const std::array<float, 16> viewProj =
        viewProjection(camera_->camera(), double(area.extent.width) / double(area.extent.height));
    std::copy(viewProj.begin(), viewProj.end(), push.viewProj);
    colourRows(exposureScale_, push.colourRows);
    push.mode = ui_.display.quantity == DisplayQuantity::Colour ? DAISY_VIEWER_MODE_COLOUR
                                                                : DAISY_VIEWER_MODE_FALSE;
    push.flags = (formats_.encodeSrgb ? DAISY_VIEWER_FLAG_ENCODE_SRGB : 0u) |
        (ui_.wireframe ? DAISY_VIEWER_FLAG_WIREFRAME : 0u);
    push.picked = ui_.picked ? *ui_.picked + 1 : 0;
    push.falseLo = static_cast<float>(ui_.range.lo);
    push.falseHi = static_cast<float>(ui_.range.hi);

    VkCommandBuffer commandBuffer = frame.commandBuffer;
    VK_CHECK(vkResetCommandBuffer(commandBuffer, 0));
    VkCommandBufferBeginInfo beginInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    beginInfo.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(commandBuffer, &beginInfo));
    VkClearValue clears[2]{};
    clears[0].color = {{0, 0, 0, 1}};
    clears[1].depthStencil = {0.0f, 0};
    VkRenderPassBeginInfo passInfo{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    passInfo.renderPass = renderPass_;
    passInfo.framebuffer = swapchain_.framebuffers[imageIndex];
    passInfo.renderArea = {{0, 0}, swapchain_.extent};
    passInfo.clearValueCount = 2;
    passInfo.pClearValues = clears;
    vkCmdBeginRenderPass(commandBuffer, &passInfo, VK_SUBPASS_CONTENTS_INLINE);
    recordPatches(commandBuffer, pipeline_, buffers_, frame_, push, area,
                  detail_.sets.empty() ? nullptr : &detail_);
    if (imgui_) ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), commandBuffer);
    vkCmdEndRenderPass(commandBuffer);

    const bool copy = capture && swapchain_.transferSource;
    if (copy) {
        const VkDeviceSize bytes =
            VkDeviceSize(swapchain_.extent.width) * swapchain_.extent.height * 4;
        if (readback_.bytes < bytes) {
            destroyHostBuffer(context_, readback_);
            auto readback = createHostBuffer(context_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
            if (!readback) return readback.error();
            readback_ = *readback;
        }
        VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        barrier.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        barrier.oldLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
        barrier.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        barrier.image = swapchain_.images[imageIndex];
        barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1,
                             &barrier);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {swapchain_.extent.width, swapchain_.extent.height, 1};
        vkCmdCopyImageToBuffer(commandBuffer, swapchain_.images[imageIndex],
                               VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.buffer, 1, &region);
        barrier.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        barrier.dstAccessMask = 0;
        barrier.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        barrier.newLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
        vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, nullptr, 0, nullptr, 1,
                             &barrier);
        VkBufferMemoryBarrier hostRead{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
        hostRead.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        hostRead.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        hostRead.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        hostRead.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        hostRead.buffer = readback_.buffer;
        hostRead.size = VK_WHOLE_SIZE;
        vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &hostRead, 0, nullptr);
    }
    VK_CHECK(vkEndCommandBuffer(commandBuffer));

    VK_CHECK(vkResetFences(context_.device, 1, &frame.fence));
    const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.waitSemaphoreCount = 1;
    submit.pWaitSemaphores = &frame.imageAvailable;
    submit.pWaitDstStageMask = &waitStage;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commandBuffer;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &swapchain_.renderFinished[imageIndex];
    VK_CHECK(vkQueueSubmit(context_.queue, 1, &submit, frame.fence));
    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &swapchain_.renderFinished[imageIndex];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_.swapchain;
    present.pImageIndices = &imageIndex;
    const VkResult presented = vkQueuePresentKHR(context_.queue, &present);
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) {
        resized_ = true;
    } else {
        VK_CHECK(presented);
    }
    if (copy) VK_CHECK(vkWaitForFences(context_.device, 1, &frame.fence, VK_TRUE, UINT64_MAX));
    frame_ = (frame_ + 1) % kFramesInFlight;
    ++framesDrawn_;
    return true;
}

Expected<void> Viewer::writeCapture(const std::string& path) {
    const uint32_t width = swapchain_.extent.width, height = swapchain_.extent.height;
    std::vector<uint8_t> rgb(std::size_t(width) * height * 3);
    const auto* pixels = static_cast<const uint8_t*>(readback_.mapped);
    for (std::size_t p = 0; p < std::size_t(width) * height; ++p) {
        rgb[p * 3 + 0] = pixels[p * 4 + (formats_.bgr ? 2 : 0)];
        rgb[p * 3 + 1] = pixels[p * 4 + 1];
        rgb[p * 3 + 2] = pixels[p * 4 + (formats_.bgr ? 0 : 2)];
    }
    return writePng(path, int(width), int(height), rgb);
}

void Viewer::exerciseWindow(int frame) {
    // Smaller, minimised, restored, larger, then the size asked for: each makes the swapchain
    // out of date or zero-sized.
    switch (frame) {
        case 2:
            glfwSetWindowSize(window_, std::max(options_.width / 2, 1),
                              std::max(options_.height / 3, 1));
            break;
        case 4:
            glfwIconifyWindow(window_);
            break;
        case 6:
            glfwRestoreWindow(window_);
            break;
        case 8:
            glfwSetWindowSize(window_, options_.width + 64, options_.height + 48);
            break;
        case 10:
            glfwSetWindowSize(window_, options_.width, options_.height);
            break;
        default:
            break;
    }
}

void Viewer::logOpening(bool drawn) {
    if (!drawn || (firstFrameLogged_ && convergedFrameLogged_)) return;
    const double ms = secondsSince(options_.startedAt) * 1e3;
    const auto snapshot = worker_.latest();
    if (!firstFrameLogged_) {
        firstFrameLogged_ = true;
        const std::string status = buildStatusLine(worker_.buildProgress(), *snapshot);
        logInfo(concat("view: first frame ", formatNumber(ms, 3), " ms after the start, showing ",
                       snapshot->fromCache         ? "the converged solution from the cache"
                           : snapshot->converged   ? "the converged solution"
                           : snapshot->directLight ? "the emitters' direct light"
                                                   : "the emission",
                       snapshot->building ? " while the view factors are made" : "",
                       status.empty() ? "" : concat(" (", status, ")")));
    }
    if (!convergedFrameLogged_ && snapshot->converged && !snapshot->solving &&
        shownVersion_ == snapshot->version) {
        convergedFrameLogged_ = true;
        logInfo(concat("view: first converged frame ", formatNumber(ms, 3), " ms after the start",
                       snapshot->fromCache ? " (the solution from the cache)" : ""));
    }
}

void Viewer::trackEdit() {
    if (editPostedAt_ < 0 || shownVersion_ <= editVersion_) return;
    const double since = clock_.seconds() - editPostedAt_;
    if (firstImageSeconds_ < 0) {
        firstImageSeconds_ = since;
        firstPublishedSeconds_ = shownSinceEdit_;
        // The frame just submitted: wait until it is drawn (on a CPU driver its rasterisation
        // is CPU work of this process) to time and charge it whole.
        const Frame& submitted = frames_[(frame_ + kFramesInFlight - 1) % kFramesInFlight];
        vkWaitForFences(context_.device, 1, &submitted.fence, VK_TRUE, UINT64_MAX);
        firstImageDoneSeconds_ = clock_.seconds() - editPostedAt_;
        firstImageCpuSeconds_ = processCpuSeconds() - editPostedCpu_;
    }
    if (convergedSeconds_ < 0 && !shownSolving_ && worker_.idle()) {
        convergedSeconds_ = since;
        convergedPublishedSeconds_ = shownSinceEdit_;
    }
}

int Viewer::run() {
    double last = clock_.seconds();
    double smoothedFrame = 0;
    double lastFrameSeconds = 0, titleFrameSeconds = -1;
    double titleAt = -1;
    const auto setTitle = [&](double frameSeconds) {
        // While F is being made (or when it failed) the title says so, for the --frames mode
        // and a hidden panel too.
        const std::string status = buildStatusLine(worker_.buildProgress(), *worker_.latest());
        glfwSetWindowTitle(
            window_,
            concat("daisy view - ", scene_.path, " - ", formatNumber(frameSeconds * 1e3, 3), " ms",
                   status.empty() ? "" : " - " + status)
                .c_str());
    };
    bool minimisedLogged = false;
    int frameNumber = 0;
    bool editsPosted = false;
    while (!glfwWindowShouldClose(window_)) {
        glfwPollEvents();
        int width = 0, height = 0;
        glfwGetFramebufferSize(window_, &width, &height);
        if (width == 0 || height == 0) {
            // Minimised: nothing to draw into; wait for the window to come back.
            if (!minimisedLogged) logVerbose("view: minimised (framebuffer 0 x 0)");
            minimisedLogged = true;
            glfwWaitEventsTimeout(0.05);
            if (options_.frames > 0) {
                ++frameNumber;
                if (options_.exerciseWindow) exerciseWindow(frameNumber);
            }
            continue;
        }
        if (swapchain_.extent.width != uint32_t(width) ||
            swapchain_.extent.height != uint32_t(height))
            resized_ = true;
        // Draw only when the picture can change: input, a new iterate, a resize, or the test
        // mode counting its frames. Otherwise wait for an event (or the next iterate), leaving
        // the cores to the solver and to other programs.
        const bool held = dragging_ || heldKey();
        const bool active = events_.activity || held;
        events_.activity = false;
        settleFrames_ = active ? 3 : std::max(settleFrames_ - 1, 0);
        const bool fresh = worker_.latest()->version != shownVersion_ ||
            worker_.buildProgress().version != shownProgress_;
        const bool counting = options_.frames > 0 && worker_.idle();
        if (settleFrames_ <= 0 && !fresh && !resized_ && !counting && !ui_.screenshotRequest &&
            !exposurePending_ && frameNumber > 0) {
            // Idle: the title keeps the last frame's real time (a title set a moment before
            // that frame would otherwise stay, e.g. the first frame's set-up time).
            if (titleFrameSeconds != lastFrameSeconds) {
                titleFrameSeconds = lastFrameSeconds;
                setTitle(lastFrameSeconds);
            }
            glfwWaitEventsTimeout(worker_.idle() ? 0.25 : kSolvingFrameSeconds);
            continue;
        }
        if (!worker_.idle()) {
            const double wait = kSolvingFrameSeconds - (clock_.seconds() - last);
            if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
        }
        const double now = clock_.seconds();
        const double dt = std::min(now - last, 0.1);  // movement per frame, bounded after waits
        last = now;
        handleInput(dt);
        applyCameraRequest();
        if (options_.pick && frameNumber == 0) {
            const VkRect2D area = sceneArea();
            ui_.picked =
                pickPatch(worker_.patches(), camera_->camera(), int(area.extent.width),
                          int(area.extent.height), (*options_.pick)[0] + 0.5 - area.offset.x,
                          (*options_.pick)[1] + 0.5 - area.offset.y);
            const std::size_t material =
                ui_.picked ? worker_.patches().materials[*ui_.picked] : scene_.materials.size();
            logInfo(ui_.picked ? concat("view: picked patch ", *ui_.picked, " (material '",
                                        scene_.materials[material].name, "')")
                               : std::string("view: picked nothing"));
        }
        // Scripted edits go in after the first frame, once F is in hand and the first solve done
        // (the worker idle), as a user's would: their timings are then the edit's own, not the
        // rest of F's build or cache read.
        if (!editsPosted && frameNumber >= 1 && worker_.idle()) {
            editsPosted = true;
            editPostedCpu_ = processCpuSeconds();
            for (const std::string& text : pendingEdits_) {
                auto edit = parseMaterialEdit(text);
                auto targets = editTargets(scene_, *edit);
                const auto snapshot = worker_.latest();
                for (std::size_t index : *targets)
                    worker_.setMaterial(index, applyEdit(snapshot->materials[index], *edit));
            }
            if (!pendingEdits_.empty()) {
                editPostedAt_ = clock_.seconds();
                editVersion_ = worker_.latest()->version;
            }
        }
        const bool testMode = options_.frames > 0;
        const bool sizeSettled = !options_.exerciseWindow ||
            (width == options_.width && height == options_.height && frameNumber > 10);
        const bool finalFrame = testMode && frameNumber + 1 >= options_.frames && editsPosted &&
            worker_.idle() && sizeSettled;
        const bool capture =
            ui_.screenshotRequest || (finalFrame && !options_.screenshotPath.empty());
        auto frameDrawn = drawFrame(capture);
        if (!frameDrawn) {
            // A device error (out of memory, device or surface lost) ends the viewer with it.
            logError(concat("daisy view: ", frameDrawn.error().message));
            vkDeviceWaitIdle(context_.device);
            return 2;
        }
        const bool drawn = *frameDrawn;
        if (drawn) worker_.shown(shownVersion_);
        logOpening(drawn);
        // The frame's own time (record, submit, the wait for the frame before last): the frame
        // period when drawing continuously.
        const double work = clock_.seconds() - now;
        // The first frame also creates pipelines and uploads: it does not seed the average.
        if (frameNumber > 0) {
            smoothedFrame = smoothedFrame == 0 ? work : 0.9 * smoothedFrame + 0.1 * work;
        }
        lastFrameSeconds = work;
        ui_.frameSeconds = smoothedFrame;
        ++frameNumber;
        if (options_.exerciseWindow) exerciseWindow(frameNumber);
        if (now - titleAt >= 0.25 || worker_.buildProgress().active) {
            titleAt = now;
            titleFrameSeconds = lastFrameSeconds;
            setTitle(smoothedFrame > 0 ? smoothedFrame : work);
        }
        if (capture && drawn) {
            // F12 in the interactive mode writes to --screenshot when given.
            const bool named = finalFrame || (!testMode && !options_.screenshotPath.empty());
            const std::string path =
                named ? options_.screenshotPath : concat("daisy_view_", framesDrawn_, ".png");
            if (!swapchain_.transferSource) {
                logError(
                    "daisy view: this swapchain's images cannot be read back (no "
                    "VK_IMAGE_USAGE_TRANSFER_SRC_BIT); no screenshot");
                if (finalFrame) return 1;
            } else if (auto written = writeCapture(path); !written) {
                logError(written.error().message);
                if (finalFrame) return 1;
            } else {
                logInfo(concat("view: wrote ", path, " (", swapchain_.extent.width, " x ",
                               swapchain_.extent.height, ", exposure ",
                               formatNumber(ui_.appliedEv, 3), " EV)"));
            }
            ui_.screenshotRequest = false;
        }
        trackEdit();
        if (finalFrame && (drawn || options_.screenshotPath.empty())) {
            const auto snapshot = worker_.latest();
            logInfo(concat("view: ", frameNumber, " frames, mean frame time ",
                           formatNumber(smoothedFrame * 1e3, 3), " ms at ", swapchain_.extent.width,
                           " x ", swapchain_.extent.height, "; peak memory ",
                           formatBytes(double(peakResidentBytes()))));
            if (!options_.edits.empty()) {
                logInfo(concat(
                    "view: edit -> first updated frame ", formatNumber(firstImageSeconds_ * 1e3, 3),
                    " ms (its iterate ready at ", formatNumber(firstPublishedSeconds_ * 1e3, 3),
                    " ms, the frame drawn at ", formatNumber(firstImageDoneSeconds_ * 1e3, 3),
                    " ms with ", formatNumber(firstImageCpuSeconds_ * 1e3, 3),
                    " ms of process CPU since the edit), converged frame ",
                    formatNumber(convergedSeconds_ * 1e3, 3), " ms (solution ready at ",
                    formatNumber(convergedPublishedSeconds_ * 1e3, 3), " ms; ", snapshot->iteration,
                    " iterations, residual ", formatNumber(snapshot->residual, 3), ")",
                    snapshot->message.empty() ? "" : concat("; ", snapshot->message)));
            }
            if (!snapshot->error.empty()) {
                logError(concat("daisy view: no view factors: ", snapshot->error));
                vkDeviceWaitIdle(context_.device);
                return 2;
            }
            if (!options_.saveMaterialsPath.empty()) {
                auto saved =
                    saveEditedMaterials(options_.saveMaterialsPath, scene_, snapshot->materials);
                if (!saved) {
                    logError(saved.error().message);
                    vkDeviceWaitIdle(context_.device);
                    return 2;
                }
                logInfo(concat("view: wrote ", options_.saveMaterialsPath));
            }
            if (snapshot->refusedEdits > 0) {
                logError(concat("daisy view: ", snapshot->message,
                                snapshot->refusedEdits > 1
                                    ? concat(" (", snapshot->refusedEdits, " edits refused)")
                                    : std::string()));
                vkDeviceWaitIdle(context_.device);
                return 2;
            }
            break;
        }
    }
    vkDeviceWaitIdle(context_.device);
    return 0;
}

}  // namespace

ViewerUnavailable viewerUnavailable(const std::string& device) {
    if (!glfwInit()) {
        return {"daisy view: cannot open a window (no display: set DISPLAY, or run under xvfb-run)",
                1};
    }
    ViewerUnavailable result;
    if (!glfwVulkanSupported()) {
        result = {"daisy view: GLFW finds no Vulkan loader (install a Vulkan driver)", 1};
    } else {
        uint32_t extensionCount = 0;
        const char** extensions = glfwGetRequiredInstanceExtensions(&extensionCount);
        auto instance = createInstance(std::span<const char* const>(extensions, extensionCount));
        if (!instance) {
            result = {concat("daisy view: ", instance.error().message), 1};
        } else {
            DeviceRequirements requirements;
            requirements.compute = false;
            requirements.graphics = true;
            if (auto picked = pickPhysicalDevice(*instance, device, requirements); !picked) {
                result = {concat("daisy view: ", picked.error().message), device.empty() ? 1 : 2};
            }
            vkDestroyInstance(*instance, nullptr);
        }
    }
    glfwTerminate();
    return result;
}

int runViewer(Session session, const ViewerOptions& options) {
    Viewer viewer(std::move(session), options);
    if (const int status = viewer.open(); status != 0) return status;
    return viewer.run();
}

}  // namespace daisy::viewer
