// The viewer's GLFW window (no client API: Vulkan presents into it) and the input gathered between frames.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>
#include <vulkan/vulkan.h>

struct GLFWwindow;

namespace fh {

// Thrown when no window can be opened (no display, no Vulkan support in GLFW); main prints it as one line.
struct DisplayUnavailable : std::runtime_error {
    using runtime_error::runtime_error;
};

// Input since the last take_input(): mouse drags by button, wheel steps, and keys pressed (GLFW key codes).
struct WindowInput {
    double orbit_dx = 0, orbit_dy = 0;  // left drag
    double pan_dx = 0, pan_dy = 0;      // middle or right drag, or shift + left drag
    double wheel = 0;
    std::vector<int> pressed;           // key presses (repeats included), in order
    bool clicked = false;               // a left click without a drag (focus there)
    double click_x = 0, click_y = 0;    // where, in framebuffer pixels from the top left
    bool shift = false;
};

class ViewerWindow {
public:
    // Initialises GLFW and opens a window of width x height. Throws DisplayUnavailable.
    ViewerWindow(uint32_t width, uint32_t height, const std::string& title);
    ~ViewerWindow();
    ViewerWindow(const ViewerWindow&) = delete;
    ViewerWindow& operator=(const ViewerWindow&) = delete;

    // The instance extensions GLFW needs for a window surface.
    static std::vector<const char*> required_instance_extensions();
    VkSurfaceKHR create_surface(VkInstance instance);

    void poll();
    // Sleeps until an input event arrives or `seconds` pass (when there is nothing to render).
    void wait_events(double seconds);
    bool should_close() const;
    void request_close();
    VkExtent2D framebuffer_size() const;
    void set_size(uint32_t width, uint32_t height);
    void set_title(const std::string& title);
    // True while a fly key (W, A, S, D, Q, E) is held.
    bool key_down(int key) const;
    WindowInput take_input();

private:
    static void on_cursor(GLFWwindow* window, double x, double y);
    static void on_scroll(GLFWwindow* window, double dx, double dy);
    static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void on_button(GLFWwindow* window, int button, int action, int mods);

    GLFWwindow* window_ = nullptr;
    WindowInput input_;
    double last_x_ = 0, last_y_ = 0;
    bool have_cursor_ = false;
    double dragged_ = 0;  // cursor travel since the left button went down, window pixels
};

}  // namespace fh
