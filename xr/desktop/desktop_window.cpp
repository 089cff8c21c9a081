// SPDX-License-Identifier: MIT
/// @brief DesktopWindow: GLFW window with an EGL-created GL 4.5 core context, side-by-side
///        presentation by framebuffer blits, keyboard and mouse input.
#include "xr/desktop/desktop_window.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <utility>

#include "shaders/egl_context.h"
#include "shaders/framebuffer_readback.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GLFW_EXPOSE_NATIVE_EGL
#include <GLFW/glfw3native.h>

namespace telesphere::xr::desktop {
namespace {

// GLFW reports errors through one process-wide callback, on the thread that made the call.
thread_local std::string g_desktop_glfw_error;
std::mutex g_desktop_glfw_mutex;
int g_desktop_glfw_users = 0;  // windows alive; guarded by g_desktop_glfw_mutex

void desktopGlfwErrorCallback(int code, const char* description) {
  char code_text[32];
  std::snprintf(code_text, sizeof code_text, " (GLFW error 0x%05X)", code);
  if (!g_desktop_glfw_error.empty()) g_desktop_glfw_error += "; ";
  g_desktop_glfw_error += (description != nullptr ? description : "no description");
  g_desktop_glfw_error += code_text;
}

/// The GLFW error text since the last call (then cleared).
std::string takeDesktopGlfwError() {
  std::string text = std::exchange(g_desktop_glfw_error, {});
  return text.empty() ? "GLFW gave no error text" : text;
}

/// glfwInit() for the first window of the process.
bool acquireDesktopGlfw(std::string* error) {
  const std::lock_guard<std::mutex> lock(g_desktop_glfw_mutex);
  if (g_desktop_glfw_users == 0) {
    // glfwTerminate() after the last window unloads Mesa's driver while some of its allocations
    // are referenced only from its globals (LeakSanitizer then reports them from an "<unknown
    // module>"), and the next window loads it again. The process's surfaceless EGL display stays
    // initialised until exit (gl::EglContext) and keeps the driver loaded.
    static const bool driver_kept = gl::EglContext::createSurfaceless(nullptr) != nullptr;
    (void)driver_kept;
    glfwSetErrorCallback(desktopGlfwErrorCallback);
    g_desktop_glfw_error.clear();
    if (glfwInit() != GLFW_TRUE) {
      if (error != nullptr) *error = "glfwInit failed: " + takeDesktopGlfwError();
      return false;
    }
  }
  ++g_desktop_glfw_users;
  return true;
}

/// glfwTerminate() after the last window of the process.
void releaseDesktopGlfw() {
  const std::lock_guard<std::mutex> lock(g_desktop_glfw_mutex);
  if (--g_desktop_glfw_users == 0) glfwTerminate();
}

void setDesktopError(std::string* error, std::string text) {
  if (error != nullptr) *error = std::move(text);
}

std::string desktopHex(unsigned value) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%04X", value);
  return text;
}

bool checkDesktopEyeFramebuffer(GLuint framebuffer, const char* eye, std::string* error) {
  if (framebuffer == 0) {
    setDesktopError(error, std::string(eye) + " eye framebuffer is 0 (the window itself)");
    return false;
  }
  if (glIsFramebuffer(framebuffer) != GL_TRUE) {
    setDesktopError(error, std::string(eye) + " eye framebuffer " + std::to_string(framebuffer) +
                               " is not a framebuffer object");
    return false;
  }
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_READ_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    setDesktopError(error, std::string(eye) + " eye framebuffer " + std::to_string(framebuffer) +
                               " is incomplete (status " + desktopHex(status) + ")");
    return false;
  }
  return true;
}

}  // namespace

std::unique_ptr<DesktopWindow> DesktopWindow::create(int width, int height,
                                                     const std::string& title,
                                                     std::string* error, DesktopContextApi api) {
  if (width <= 0 || height <= 0) {
    setDesktopError(error, "desktop window size must be positive, got " + std::to_string(width) +
                               "x" + std::to_string(height));
    return nullptr;
  }
  const char* display = std::getenv("DISPLAY");
  if (display == nullptr || display[0] == '\0') {
    setDesktopError(error,
                    "no X display (DISPLAY unset): run under Xvfb or use `telesphere-xr offscreen`");
    return nullptr;
  }
  std::string init_error;
  if (!acquireDesktopGlfw(&init_error)) {
    setDesktopError(error, "cannot open the X display \"" + std::string(display) + "\" (" +
                               init_error + "): is an X server running there?");
    return nullptr;
  }
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
  glfwWindowHint(GLFW_CONTEXT_CREATION_API,
                 api == DesktopContextApi::kEgl ? GLFW_EGL_CONTEXT_API : GLFW_NATIVE_CONTEXT_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  // The window only receives blits: no depth or stencil buffer.
  glfwWindowHint(GLFW_DEPTH_BITS, 0);
  glfwWindowHint(GLFW_STENCIL_BITS, 0);
  g_desktop_glfw_error.clear();
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (window == nullptr) {
    setDesktopError(error, std::string("cannot create a window with an OpenGL 4.5 core context through ") +
                               (api == DesktopContextApi::kEgl ? "EGL" : "GLX") + " on display \"" +
                               std::string(display) + "\": " +
                               takeDesktopGlfwError());
    releaseDesktopGlfw();
    return nullptr;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(0);
  return std::unique_ptr<DesktopWindow>(new DesktopWindow(window, api));
}

DesktopWindow::DesktopWindow(GLFWwindow* window, DesktopContextApi api) : window_(window), api_(api) {
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, &DesktopWindow::onKey);
  glfwSetMouseButtonCallback(window_, &DesktopWindow::onMouseButton);
  glfwSetCursorPosCallback(window_, &DesktopWindow::onCursorPos);
  glfwGetCursorPos(window_, &cursor_x_, &cursor_y_);
}

DesktopWindow::~DesktopWindow() {
  glfwDestroyWindow(window_);  // also releases the context if it is current here
  releaseDesktopGlfw();
}

void DesktopWindow::makeCurrent() const { glfwMakeContextCurrent(window_); }

EGLDisplay DesktopWindow::eglDisplay() const {
  return api_ == DesktopContextApi::kEgl ? glfwGetEGLDisplay() : EGL_NO_DISPLAY;
}

EGLContext DesktopWindow::eglContext() const {
  return api_ == DesktopContextApi::kEgl ? glfwGetEGLContext(window_) : EGL_NO_CONTEXT;
}

bool DesktopWindow::isCurrent() const {
  // Asked of EGL, not GLFW: other code may switch contexts with eglMakeCurrent directly.
  if (api_ == DesktopContextApi::kEgl) return eglGetCurrentContext() == glfwGetEGLContext(window_);
  return glfwGetCurrentContext() == window_;
}

bool DesktopWindow::setSwapInterval(int interval) {
  if (!isCurrent()) return false;
  glfwSwapInterval(interval);
  return true;
}

bool DesktopWindow::shouldClose() const { return glfwWindowShouldClose(window_) == GLFW_TRUE; }

void DesktopWindow::pollEvents() { glfwPollEvents(); }

VirtualHeadInput DesktopWindow::headInput() {
  const auto held = [this](int key) { return glfwGetKey(window_, key) == GLFW_PRESS; };
  VirtualHeadInput input;
  input.forward = held(GLFW_KEY_W);
  input.back = held(GLFW_KEY_S);
  input.left = held(GLFW_KEY_A);
  input.right = held(GLFW_KEY_D);
  input.up = held(GLFW_KEY_R) || held(GLFW_KEY_SPACE);
  input.down = held(GLFW_KEY_F) || held(GLFW_KEY_LEFT_SHIFT);
  input.turn_left = held(GLFW_KEY_LEFT);
  input.turn_right = held(GLFW_KEY_RIGHT);
  input.look_up = held(GLFW_KEY_UP);
  input.look_down = held(GLFW_KEY_DOWN);
  input.mouse_dx_px = std::exchange(drag_dx_px_, 0.0);
  input.mouse_dy_px = std::exchange(drag_dy_px_, 0.0);
  // The deltas gather only while the button is held; a drag that began and ended since the last
  // frame (a slow frame) has released the button by now and must still turn the head.
  input.look = dragging_ || input.mouse_dx_px != 0.0 || input.mouse_dy_px != 0.0;
  return input;
}

DesktopCommands DesktopWindow::takeCommands() { return std::exchange(commands_, {}); }

void DesktopWindow::onKey(GLFWwindow* window, int key, int /*scancode*/, int action,
                          int /*mods*/) {
  if (action != GLFW_PRESS) return;  // held keys are polled; repeats are not commands
  auto* self = static_cast<DesktopWindow*>(glfwGetWindowUserPointer(window));
  DesktopCommands& commands = self->commands_;
  switch (key) {
    case GLFW_KEY_N: commands.capture_nominal = true; break;
    case GLFW_KEY_M: commands.cycle_mode = true; break;
    case GLFW_KEY_P: commands.cycle_depth_proxy = true; break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: commands.radius_up = true; break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: commands.radius_down = true; break;
    case GLFW_KEY_HOME:
    case GLFW_KEY_0: commands.reset_head = true; break;
    case GLFW_KEY_ESCAPE:
      commands.quit = true;
      glfwSetWindowShouldClose(window, GLFW_TRUE);
      break;
    default: break;
  }
}

void DesktopWindow::onMouseButton(GLFWwindow* window, int button, int action, int /*mods*/) {
  if (button != GLFW_MOUSE_BUTTON_LEFT) return;
  auto* self = static_cast<DesktopWindow*>(glfwGetWindowUserPointer(window));
  // cursor_x_/cursor_y_ already hold the position as of this event (onCursorPos); asking the
  // server (glfwGetCursorPos) would give where the pointer is now, after motion not yet seen.
  self->dragging_ = action == GLFW_PRESS;
}

void DesktopWindow::onCursorPos(GLFWwindow* window, double x, double y) {
  auto* self = static_cast<DesktopWindow*>(glfwGetWindowUserPointer(window));
  if (self->dragging_) {
    self->drag_dx_px_ += x - self->cursor_x_;
    self->drag_dy_px_ += y - self->cursor_y_;
  }
  self->cursor_x_ = x;
  self->cursor_y_ = y;
}

bool DesktopWindow::present(GLuint left_framebuffer, GLuint right_framebuffer, int eye_width,
                            int eye_height, std::string* error) {
  if (!compose(left_framebuffer, right_framebuffer, eye_width, eye_height, error)) return false;
  swapBuffers();
  return true;
}

bool DesktopWindow::compose(GLuint left_framebuffer, GLuint right_framebuffer, int eye_width,
                            int eye_height, std::string* error) {
  if (!isCurrent()) {
    setDesktopError(error, "the desktop window's context is not current on this thread");
    return false;
  }
  if (eye_width <= 0 || eye_height <= 0) {
    setDesktopError(error, "eye image size must be positive, got " + std::to_string(eye_width) +
                               "x" + std::to_string(eye_height));
    return false;
  }
  if (!checkDesktopEyeFramebuffer(left_framebuffer, "left", error) ||
      !checkDesktopEyeFramebuffer(right_framebuffer, "right", error))
    return false;
  const int window_w = framebufferWidth(), window_h = framebufferHeight();
  if (window_w <= 0 || window_h <= 0) return true;  // minimised

  // Fit 2·eye_width × eye_height into the window, centred: scale = min(W / 2w, H / h).
  const double scale = std::min(window_w / (2.0 * eye_width), window_h / double(eye_height));
  const int dst_eye_w = std::min(int(std::lround(eye_width * scale)), window_w / 2);
  const int dst_eye_h = std::min(int(std::lround(eye_height * scale)), window_h);
  const int x0 = (window_w - 2 * dst_eye_w) / 2;
  const int y0 = (window_h - dst_eye_h) / 2;

  // State the blit and clear depend on: saved, set, restored.
  const GLboolean was_srgb = glIsEnabled(GL_FRAMEBUFFER_SRGB);
  const GLboolean was_scissor = glIsEnabled(GL_SCISSOR_TEST);
  GLboolean colour_mask[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
  glGetBooleanv(GL_COLOR_WRITEMASK, colour_mask);
  glDisable(GL_FRAMEBUFFER_SRGB);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);

  glNamedFramebufferDrawBuffer(0, GL_BACK);
  const GLfloat black[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  glClearNamedFramebufferfv(0, GL_COLOR, 0, black);
  if (dst_eye_w > 0 && dst_eye_h > 0) {
    const GLuint sources[2] = {left_framebuffer, right_framebuffer};
    for (int eye = 0; eye < 2; ++eye) {
      glNamedFramebufferReadBuffer(sources[eye], GL_COLOR_ATTACHMENT0);
      const int x = x0 + eye * dst_eye_w;
      glBlitNamedFramebuffer(sources[eye], 0, 0, 0, eye_width, eye_height, x, y0, x + dst_eye_w,
                             y0 + dst_eye_h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    }
  }

  glColorMask(colour_mask[0], colour_mask[1], colour_mask[2], colour_mask[3]);
  if (was_scissor == GL_TRUE) glEnable(GL_SCISSOR_TEST);
  if (was_srgb == GL_TRUE) glEnable(GL_FRAMEBUFFER_SRGB);
  const GLenum gl_error = glGetError();
  if (gl_error != GL_NO_ERROR) {
    setDesktopError(error, "GL error " + desktopHex(gl_error) +
                               " while drawing the eyes into the desktop window (are the eye "
                               "framebuffers single-sampled?)");
    return false;
  }
  return true;
}

void DesktopWindow::swapBuffers() { glfwSwapBuffers(window_); }

std::vector<std::uint8_t> DesktopWindow::readBackBufferRgba() const {
  return gl::readFramebufferRgba8(0, GL_BACK, framebufferWidth(), framebufferHeight());
}

int DesktopWindow::framebufferWidth() const {
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  return width;
}

int DesktopWindow::framebufferHeight() const {
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  return height;
}

void DesktopWindow::setTitle(const std::string& title) {
  glfwSetWindowTitle(window_, title.c_str());
}

}  // namespace telesphere::xr::desktop
