// GLFW set-up with one-line errors (no display, no Vulkan loader), and callbacks that accumulate input.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "app/view/viewer_window.h"

#include <cmath>

#include "vk/check.h"

namespace fh {
namespace {

std::string last_glfw_error;

void on_glfw_error(int, const char* description) { last_glfw_error = description ? description : "unknown"; }

std::string glfw_error_or(const char* fallback) { return last_glfw_error.empty() ? fallback : last_glfw_error; }

}  // namespace

ViewerWindow::ViewerWindow(uint32_t width, uint32_t height, const std::string& title) {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit())
        throw DisplayUnavailable("cannot open a window (" + glfw_error_or("glfwInit failed") +
                                 "); without a display use `fredholm render`, or run under xvfb-run");
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        throw DisplayUnavailable("GLFW finds no Vulkan loader for window surfaces; use `fredholm render`");
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    window_ = glfwCreateWindow(int(width), int(height), title.c_str(), nullptr, nullptr);
    if (!window_) {
        glfwTerminate();
        throw DisplayUnavailable("cannot create a window (" + glfw_error_or("glfwCreateWindow failed") +
                                 "); use `fredholm render`");
    }
    glfwSetWindowUserPointer(window_, this);
    glfwSetCursorPosCallback(window_, on_cursor);
    glfwSetScrollCallback(window_, on_scroll);
    glfwSetKeyCallback(window_, on_key);
    glfwSetMouseButtonCallback(window_, on_button);
}

ViewerWindow::~ViewerWindow() {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

std::vector<const char*> ViewerWindow::required_instance_extensions() {
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names)
        throw DisplayUnavailable("the Vulkan driver offers no window-system surface extensions; use `fredholm render`");
    return std::vector<const char*>(names, names + count);
}

VkSurfaceKHR ViewerWindow::create_surface(VkInstance instance) {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    VkResult result = glfwCreateWindowSurface(instance, window_, nullptr, &surface);
    if (result != VK_SUCCESS)
        throw DisplayUnavailable(std::string("cannot create a Vulkan surface for the window (") +
                                 vk::result_name(result) + "); use `fredholm render`");
    return surface;
}

void ViewerWindow::poll() { glfwPollEvents(); }
bool ViewerWindow::should_close() const { return glfwWindowShouldClose(window_); }
void ViewerWindow::request_close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

VkExtent2D ViewerWindow::framebuffer_size() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return {uint32_t(w > 0 ? w : 0), uint32_t(h > 0 ? h : 0)};
}

void ViewerWindow::set_size(uint32_t width, uint32_t height) { glfwSetWindowSize(window_, int(width), int(height)); }
void ViewerWindow::wait_events(double seconds) { glfwWaitEventsTimeout(seconds); }

void ViewerWindow::set_title(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }
bool ViewerWindow::key_down(int key) const { return glfwGetKey(window_, key) == GLFW_PRESS; }

WindowInput ViewerWindow::take_input() {
    WindowInput input = std::move(input_);
    input_ = WindowInput{};
    input.shift = key_down(GLFW_KEY_LEFT_SHIFT) || key_down(GLFW_KEY_RIGHT_SHIFT);
    return input;
}

void ViewerWindow::on_cursor(GLFWwindow* window, double x, double y) {
    auto* self = static_cast<ViewerWindow*>(glfwGetWindowUserPointer(window));
    const double dx = self->have_cursor_ ? x - self->last_x_ : 0.0;
    const double dy = self->have_cursor_ ? y - self->last_y_ : 0.0;
    self->last_x_ = x;
    self->last_y_ = y;
    self->have_cursor_ = true;
    const bool left = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (left) self->dragged_ += std::abs(dx) + std::abs(dy);
    const bool shift = glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                       glfwGetKey(window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    const bool pan = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS ||
                     glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS || (left && shift);
    if (pan) {
        self->input_.pan_dx += dx;
        self->input_.pan_dy += dy;
    } else if (left) {
        self->input_.orbit_dx += dx;
        self->input_.orbit_dy += dy;
    }
}

void ViewerWindow::on_button(GLFWwindow* window, int button, int action, int mods) {
    auto* self = static_cast<ViewerWindow*>(glfwGetWindowUserPointer(window));
    if (button != GLFW_MOUSE_BUTTON_LEFT || (mods & GLFW_MOD_SHIFT)) return;
    if (action == GLFW_PRESS) {
        self->dragged_ = 0;
        return;
    }
    if (action != GLFW_RELEASE || self->dragged_ > 3.0) return;  // a drag orbits; only a click focuses
    double x = 0, y = 0;
    int window_w = 0, window_h = 0;
    glfwGetCursorPos(window, &x, &y);
    glfwGetWindowSize(window, &window_w, &window_h);
    const VkExtent2D fb = self->framebuffer_size();
    self->input_.clicked = true;
    self->input_.click_x = window_w > 0 ? x * fb.width / window_w : x;  // framebuffer pixels (HiDPI)
    self->input_.click_y = window_h > 0 ? y * fb.height / window_h : y;
}

void ViewerWindow::on_scroll(GLFWwindow* window, double, double dy) {
    static_cast<ViewerWindow*>(glfwGetWindowUserPointer(window))->input_.wheel += dy;
}

void ViewerWindow::on_key(GLFWwindow* window, int key, int, int action, int) {
    if (action == GLFW_PRESS || action == GLFW_REPEAT)
        static_cast<ViewerWindow*>(glfwGetWindowUserPointer(window))->input_.pressed.push_back(key);
}

}  // namespace fh
