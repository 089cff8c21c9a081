// SPDX-License-Identifier: MIT
/// @brief The desktop window (desktop mode without a headset, and the mirror of a headset
///        session): a GLFW window on X11 whose OpenGL 4.5 core context is made through EGL, so
///        that the rest of the app uses it like its headless EGL context (eglGetCurrentDisplay(),
///        eglGetCurrentContext(), e.g. for OpenXR with XR_MNDX_egl_enable). It shows both eyes
///        side by side and turns keys and mouse into VirtualHeadInput and one-shot commands.
///
/// Threads: GLFW wants its calls on the main thread; use a DesktopWindow there only.
/// GLFW's lifetime: the first window in the process calls glfwInit(), the last one destroyed
/// calls glfwTerminate() (reference counted); GLFW's error callback is set by this file and
/// records the error text (per thread) for the messages below.
///
/// Keys (GLFW key codes, i.e. positions on a US layout):
///   held:      W/S forward/back, A/D left/right, R or Space up, F or Left Shift down,
///              ←/→ turn, ↑/↓ look up/down; left mouse button held + motion: look around
///   one-shot:  N capture nominal, M cycle mode, + (=, keypad +) radius up, − (keypad −)
///              radius down, Home or 0 reset the head, Escape quit (also sets shouldClose())
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "shaders/gl_api.h"
#include "xr/desktop/virtual_head.h"

struct GLFWwindow;

namespace telesphere::xr::desktop {

/// How the window's OpenGL context is made: through EGL (on X11; what the rest of the app and
/// OpenXR's XR_MNDX_egl_enable use) or GLX (the Xlib binding of XR_KHR_opengl_enable, which
/// SteamVR needs).
enum class DesktopContextApi { kEgl, kGlx };

/// Commands pressed since the last takeCommands(), each reported once (key repeat ignored).
struct DesktopCommands {
  bool capture_nominal = false;  ///< N
  bool cycle_mode = false;       ///< M
  bool cycle_depth_proxy = false;  ///< P: fixed → radius → grid (#35)
  bool radius_up = false;        ///< + / = / keypad +
  bool radius_down = false;      ///< − / keypad −
  bool reset_head = false;       ///< Home / 0
  bool quit = false;             ///< Escape
};

class DesktopWindow {
 public:
  /// Opens a width×height (screen coordinates) resizable window titled `title` with a GL 4.5
  /// core context created through EGL, made current on the calling thread, vsync off.
  /// Nothing, with the reason in *error, when DISPLAY is unset or empty ("no X display …"),
  /// when glfwInit fails (e.g. no X server at DISPLAY) or the window/context cannot be made;
  /// GLFW's own error text is included. width and height must be positive.
  static std::unique_ptr<DesktopWindow> create(int width, int height, const std::string& title,
                                               std::string* error,
                                               DesktopContextApi api = DesktopContextApi::kEgl);
  ~DesktopWindow();
  DesktopWindow(const DesktopWindow&) = delete;
  DesktopWindow& operator=(const DesktopWindow&) = delete;

  /// Makes the window's context current on the calling thread.
  void makeCurrent() const;
  /// The window's context is the calling thread's current EGL context.
  bool isCurrent() const;
  /// The EGL display and context GLFW made (equal to eglGetCurrent*() while current); none for
  /// a GLX window.
  EGLDisplay eglDisplay() const;
  EGLContext eglContext() const;

  /// Swap interval: 0 = vsync off (the default), 1 = wait for one vertical blank. Needs the
  /// window's context current; false (nothing changed) otherwise.
  bool setSwapInterval(int interval);

  /// Escape was pressed or the window's close button clicked.
  bool shouldClose() const;
  /// Processes pending window-system events (keys, mouse, resize, close); call once a frame.
  void pollEvents();

  /// Keys held as of the last pollEvents(), and the mouse motion (screen coordinates, pixels on
  /// X11) while the left button was held since the last headInput(); `look` while it is held.
  VirtualHeadInput headInput();
  /// One-shot commands since the last call (then cleared).
  DesktopCommands takeCommands();

  /// compose() then swapBuffers().
  bool present(GLuint left_framebuffer, GLuint right_framebuffer, int eye_width, int eye_height,
               std::string* error);
  /// Draws both eye images side by side into the window's back buffer: colour attachment 0 of
  /// each single-sampled framebuffer object (its read buffer is set to it; the
  /// eye_width×eye_height lower-left region is used), scaled (linear
  /// filter) to fit the window keeping the aspect 2·eye_width : eye_height, centred, the rest
  /// black. The bytes are copied as they are (GL_FRAMEBUFFER_SRGB is off during the blit, then
  /// restored; the scissor test too): the eye images are assumed to hold display-ready,
  /// sRGB-encoded values, whether stored in GL_SRGB8_ALPHA8 (the OpenXR staging textures) or
  /// GL_RGBA8, and the window shows them as sRGB. Needs the window's context current. False,
  /// with the reason, for framebuffer 0, an incomplete framebuffer, non-positive sizes, another
  /// current context or a GL error. A minimised (0×0) window draws nothing and succeeds.
  bool compose(GLuint left_framebuffer, GLuint right_framebuffer, int eye_width, int eye_height,
               std::string* error);
  /// Shows the back buffer (glfwSwapBuffers); its content is undefined afterwards.
  void swapBuffers();
  /// The back buffer as RGBA bytes, framebufferWidth()·framebufferHeight()·4, rows top first:
  /// read it between compose() and swapBuffers() (tests, screenshots). Needs the context current.
  std::vector<std::uint8_t> readBackBufferRgba() const;

  int framebufferWidth() const;   ///< pixels (may differ from screen coordinates on HiDPI)
  int framebufferHeight() const;  ///< pixels
  /// The window title (the app shows fps, mode and radius there).
  void setTitle(const std::string& title);

 private:
  DesktopWindow(GLFWwindow* window, DesktopContextApi api);
  static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
  static void onMouseButton(GLFWwindow* window, int button, int action, int mods);
  static void onCursorPos(GLFWwindow* window, double x, double y);

  GLFWwindow* window_;
  DesktopContextApi api_;
  DesktopCommands commands_;
  bool dragging_ = false;
  double cursor_x_ = 0.0, cursor_y_ = 0.0;  ///< last cursor position, screen coordinates
  double drag_dx_px_ = 0.0, drag_dy_px_ = 0.0;
};

}  // namespace telesphere::xr::desktop
