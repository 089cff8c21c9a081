// SPDX-License-Identifier: MIT
/// @brief DesktopWindow on an Xvfb server the test starts itself (Mesa llvmpipe): the clear
///        message without a display, the EGL context it makes current, both eyes side by side
///        with letter- and pillarboxing (RGBA8 and sRGB eye images), refused inputs, and real X
///        input injected with XTest (held keys, one-shot commands, mouse drag, Escape).
///        Skipped, saying why, when Xvfb cannot be started.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "shaders/egl_context.h"
#include "shaders/gl_objects.h"
#include "xr/desktop/desktop_window.h"

// Xlib last: its macros (Success, None, Bool, Status, …) break Eigen and gtest headers.
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/extensions/XTest.h>
#include <X11/keysym.h>

extern char** environ;

namespace telesphere::xr {
namespace {

using Clock = std::chrono::steady_clock;

bool pathExists(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0;
}

/// A display number in 90..99 with no X server socket or lock file, other than `except`.
std::optional<int> freeDisplayNumber(int except = -1) {
  for (int n = 90; n <= 99; ++n) {
    if (n == except) continue;
    const std::string id = std::to_string(n);
    if (!pathExists("/tmp/.X11-unix/X" + id) && !pathExists("/tmp/.X" + id + "-lock")) return n;
  }
  return std::nullopt;
}

/// Sets or unsets an environment variable for the scope, then restores it.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value != nullptr)
      ::setenv(name, value, 1);
    else
      ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_.c_str(), old_->c_str(), 1);
    else
      ::unsetenv(name_.c_str());
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

// --- Without a display (runs first, before any Xvfb exists) ---------------------------------

TEST(DesktopWindowNoDisplay, UnsetOrEmptyDisplayGivesTheClearMessage) {
  for (const char* value : {static_cast<const char*>(nullptr), ""}) {
    const ScopedEnv display("DISPLAY", value);
    std::string error;
    EXPECT_EQ(desktop::DesktopWindow::create(640, 400, "no display", &error), nullptr);
    EXPECT_EQ(error,
              "no X display (DISPLAY unset): run under Xvfb or use `telesphere-xr offscreen`");
  }
}

TEST(DesktopWindowNoDisplay, NoServerAtDisplayGivesGlfwsReason) {
  const std::optional<int> n = freeDisplayNumber();
  ASSERT_TRUE(n) << "no free display number in 90..99";
  const std::string name = ":" + std::to_string(*n);
  const ScopedEnv display("DISPLAY", name.c_str());
  std::string error;
  EXPECT_EQ(desktop::DesktopWindow::create(640, 400, "no server", &error), nullptr);
  EXPECT_NE(error.find("cannot open the X display \"" + name + "\""), std::string::npos) << error;
  EXPECT_NE(error.find("glfwInit failed: X11: Failed to open display"), std::string::npos)
      << error;
}

TEST(DesktopWindowNoDisplay, NonPositiveSizeIsRefused) {
  std::string error;
  EXPECT_EQ(desktop::DesktopWindow::create(0, 400, "zero", &error), nullptr);
  EXPECT_NE(error.find("must be positive, got 0x400"), std::string::npos) << error;
}

// --- On Xvfb --------------------------------------------------------------------------------

class DesktopWindowTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // A few tries: another process may take a free display number between check and start.
    for (int attempt = 0; attempt < 3 && xvfb_pid_ <= 0; ++attempt) {
      const std::optional<int> n = freeDisplayNumber();
      if (!n) {
        skip_reason_ = "no free X display number in 90..99";
        return;
      }
      startXvfb(*n);
      if (!skip_reason_.empty()) return;
    }
    if (xvfb_pid_ <= 0) {
      skip_reason_ = "Xvfb did not come up on any display tried";
      return;
    }
    // Each window's glfwTerminate() unloads Mesa's driver (swrast_dri.so) while allocations are
    // still referenced only from its globals; LeakSanitizer then reports them as leaks from an
    // "<unknown module>" that no suppression can name. A surfaceless EGL display, initialised
    // until exit as in the other GL tests, keeps the driver loaded and those allocations
    // reachable.
    std::string egl_error;
    if (!gl::EglContext::createSurfaceless(&egl_error))
      ADD_FAILURE() << "surfaceless EGL context: " << egl_error;
    ::setenv("DISPLAY", display_name_.c_str(), 1);
    x_display_ = XOpenDisplay(display_name_.c_str());
    int event_base = 0, error_base = 0, major = 0, minor = 0;
    if (x_display_ == nullptr ||
        !XTestQueryExtension(x_display_, &event_base, &error_base, &major, &minor))
      skip_reason_ = "Xvfb on " + display_name_ + " has no XTest extension";
  }

  static void TearDownTestSuite() {
    if (x_display_ != nullptr) XCloseDisplay(x_display_);
    x_display_ = nullptr;
    if (xvfb_pid_ > 0) {
      ::kill(xvfb_pid_, SIGTERM);
      int status = 0;
      ::waitpid(xvfb_pid_, &status, 0);
    }
    xvfb_pid_ = -1;
    ::unsetenv("DISPLAY");
  }

  void SetUp() override {
    if (!skip_reason_.empty()) GTEST_SKIP() << skip_reason_;
  }

  /// Starts `Xvfb :n` and waits (up to 10 s) until a client can connect. Sets skip_reason_
  /// when Xvfb cannot be executed at all.
  static void startXvfb(int n) {
    const std::string name = ":" + std::to_string(n);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    std::vector<std::string> args = {"Xvfb", name, "-screen", "0", "1280x800x24", "-nolisten",
                                     "tcp"};
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    // The server gets this process's environment without LD_PRELOAD (a sanitizer runtime or
    // shim preloaded for the test must not be loaded into Xvfb).
    std::vector<char*> env;
    for (char** e = environ; *e != nullptr; ++e)
      if (std::strncmp(*e, "LD_PRELOAD=", 11) != 0) env.push_back(*e);
    env.push_back(nullptr);
    pid_t pid = -1;
    const int spawn_error = posix_spawnp(&pid, "Xvfb", &actions, nullptr, argv.data(), env.data());
    posix_spawn_file_actions_destroy(&actions);
    if (spawn_error != 0) {
      skip_reason_ = std::string("cannot run Xvfb (is it installed and on PATH?): ") +
                     std::strerror(spawn_error);
      return;
    }
    const auto deadline = Clock::now() + std::chrono::seconds(10);
    while (Clock::now() < deadline) {
      int status = 0;
      if (::waitpid(pid, &status, WNOHANG) == pid) return;  // exited: display taken, try another
      if (pathExists("/tmp/.X11-unix/X" + std::to_string(n))) {
        if (Display* probe = XOpenDisplay(name.c_str())) {
          XCloseDisplay(probe);
          xvfb_pid_ = pid;
          display_name_ = name;
          return;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
  }

  static std::unique_ptr<desktop::DesktopWindow> makeWindow(int width, int height,
                                                   const std::string& title) {
    std::string error;
    auto window = desktop::DesktopWindow::create(width, height, title, &error);
    EXPECT_TRUE(window) << error;
    return window;
  }

  /// The top-level X window titled `title` (no window manager: a direct child of the root).
  static Window findXWindow(const std::string& title) {
    Window root = 0, parent = 0, found = 0;
    Window* children = nullptr;
    unsigned count = 0;
    XQueryTree(x_display_, DefaultRootWindow(x_display_), &root, &parent, &children, &count);
    for (unsigned i = 0; i < count && found == 0; ++i) {
      char* name = nullptr;
      if (XFetchName(x_display_, children[i], &name) != 0 && name != nullptr) {
        if (title == name) found = children[i];
        XFree(name);
      }
    }
    if (children != nullptr) XFree(children);
    return found;
  }

  /// Polls the window's events until `done()` (true) or 5 s pass (false).
  template <typename Done>
  static bool pumpUntil(desktop::DesktopWindow& window, Done done) {
    const auto deadline = Clock::now() + std::chrono::seconds(5);
    while (Clock::now() < deadline) {
      window.pollEvents();
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

  static void pressKey(KeySym key, bool down) {
    XTestFakeKeyEvent(x_display_, XKeysymToKeycode(x_display_, key), down ? True : False, 0);
    XFlush(x_display_);
  }

  static inline pid_t xvfb_pid_ = -1;
  static inline std::string display_name_;
  static inline std::string skip_reason_;
  static inline Display* x_display_ = nullptr;
};

TEST_F(DesktopWindowTest, MakesItsEglContextCurrentWithGl45Core) {
  auto window = makeWindow(640, 400, "telesphere context");
  ASSERT_TRUE(window);
  EXPECT_NE(window->eglContext(), EGL_NO_CONTEXT);
  EXPECT_EQ(eglGetCurrentContext(), window->eglContext());
  EXPECT_EQ(eglGetCurrentDisplay(), window->eglDisplay());
  EXPECT_TRUE(window->isCurrent());
  EGLint client_type = 0;
  ASSERT_TRUE(eglQueryContext(eglGetCurrentDisplay(), eglGetCurrentContext(),
                              EGL_CONTEXT_CLIENT_TYPE, &client_type));
  EXPECT_EQ(client_type, EGL_OPENGL_API);
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_GE(major * 10 + minor, 45) << glGetString(GL_VERSION);
  EXPECT_NE(profile & GL_CONTEXT_CORE_PROFILE_BIT, 0);
  EXPECT_EQ(window->framebufferWidth(), 640);  // no window manager: the size asked for
  EXPECT_EQ(window->framebufferHeight(), 400);
  EXPECT_TRUE(window->setSwapInterval(1));
  EXPECT_TRUE(window->setSwapInterval(0));
  EXPECT_FALSE(window->shouldClose());

  // The title reaches the X server.
  ASSERT_NE(findXWindow("telesphere context"), 0u);
  window->setTitle("telesphere 90 fps full6d r=2.0 m");
  EXPECT_TRUE(pumpUntil(*window, [] { return findXWindow("telesphere 90 fps full6d r=2.0 m"); }));
  EXPECT_EQ(findXWindow("telesphere context"), 0u);
}

/// An eye image: a texture whose top half is one colour and bottom half another.
struct DeskEyeImage {
  gl::GlTexture texture;
  gl::GlFramebuffer framebuffer;
};

struct DeskRgb {
  int r, g, b;
};

DeskEyeImage makeEyeImage(int width, int height, GLenum format, DeskRgb top, DeskRgb bottom) {
  DeskEyeImage eye;
  eye.texture = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(eye.texture.id(), 1, format, width, height);
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height * 4);
  for (int y = 0; y < height; ++y) {  // GL rows: bottom first
    const DeskRgb c = y < height / 2 ? bottom : top;
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = &pixels[(static_cast<std::size_t>(y) * width + x) * 4];
      p[0] = static_cast<std::uint8_t>(c.r);
      p[1] = static_cast<std::uint8_t>(c.g);
      p[2] = static_cast<std::uint8_t>(c.b);
      p[3] = 255;
    }
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(eye.texture.id(), 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE,
                      pixels.data());
  eye.framebuffer = gl::createFramebuffer();
  glNamedFramebufferTexture(eye.framebuffer.id(), GL_COLOR_ATTACHMENT0, eye.texture.id(), 0);
  return eye;
}

TEST_F(DesktopWindowTest, PresentsBothEyesSideBySideKeepingTheAspect) {
  struct Case {
    int window_w, window_h, eye_w, eye_h;
    GLenum format;
    int left, top, eye_w_px, eye_h_px;  // expected content: top-left corner, size of one eye
  };
  const Case cases[] = {
      {1280, 800, 320, 400, GL_RGBA8, 0, 0, 640, 800},            // fills, upscaled 2×
      {1280, 800, 400, 400, GL_SRGB8_ALPHA8, 0, 80, 640, 640},    // letterbox (bars top, bottom)
      {1000, 800, 300, 600, GL_RGBA8, 100, 0, 400, 800},          // pillarbox (bars left, right)
      {640, 400, 1280, 1600, GL_SRGB8_ALPHA8, 0, 0, 320, 400},    // downscaled 4×
  };
  const DeskRgb left_top{200, 30, 40}, left_bottom{20, 180, 60};
  const DeskRgb right_top{30, 60, 220}, right_bottom{230, 220, 10};
  for (const Case& c : cases) {
    SCOPED_TRACE(testing::Message() << "window " << c.window_w << "x" << c.window_h << ", eye "
                                    << c.eye_w << "x" << c.eye_h << ", format 0x" << std::hex
                                    << c.format);
    auto window = makeWindow(c.window_w, c.window_h, "telesphere present");
    ASSERT_TRUE(window);
    ASSERT_EQ(window->framebufferWidth(), c.window_w);
    ASSERT_EQ(window->framebufferHeight(), c.window_h);
    const DeskEyeImage left = makeEyeImage(c.eye_w, c.eye_h, c.format, left_top, left_bottom);
    const DeskEyeImage right = makeEyeImage(c.eye_w, c.eye_h, c.format, right_top, right_bottom);
    // State present() must neither suffer from nor change: sRGB encoding on, a scissor box.
    glEnable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 8, 8);

    std::string error;
    ASSERT_TRUE(window->compose(left.framebuffer.id(), right.framebuffer.id(), c.eye_w, c.eye_h,
                                &error))
        << error;
    EXPECT_TRUE(glIsEnabled(GL_FRAMEBUFFER_SRGB));
    EXPECT_TRUE(glIsEnabled(GL_SCISSOR_TEST));
    glDisable(GL_FRAMEBUFFER_SRGB);
    glDisable(GL_SCISSOR_TEST);
    const std::vector<std::uint8_t> rgba = window->readBackBufferRgba();
    ASSERT_EQ(rgba.size(), static_cast<std::size_t>(c.window_w) * c.window_h * 4);

    // Every 3rd pixel, away (2 px) from the edges between regions, must be exact (±1).
    const int margin = 2;
    int checked = 0, wrong = 0;
    std::ostringstream first_wrong;
    const int right_edge = c.left + 2 * c.eye_w_px, bottom_edge = c.top + c.eye_h_px;
    const int middle_x = c.left + c.eye_w_px, middle_y = c.top + c.eye_h_px / 2;
    for (int y = 0; y < c.window_h; y += 3) {
      for (int x = 0; x < c.window_w; x += 3) {
        const bool inside = x >= c.left && x < right_edge && y >= c.top && y < bottom_edge;
        const auto near = [margin](int v, int edge) { return std::abs(v - edge) < margin; };
        if (near(x, c.left) || near(x, right_edge) || near(y, c.top) || near(y, bottom_edge) ||
            (inside && (near(x, middle_x) || near(y, middle_y))))
          continue;
        DeskRgb expected{0, 0, 0};
        if (inside) {
          const bool is_left = x < middle_x, is_top = y < middle_y;
          expected = is_left ? (is_top ? left_top : left_bottom)
                             : (is_top ? right_top : right_bottom);
        }
        const std::uint8_t* p = &rgba[(static_cast<std::size_t>(y) * c.window_w + x) * 4];
        ++checked;
        if (std::abs(p[0] - expected.r) > 1 || std::abs(p[1] - expected.g) > 1 ||
            std::abs(p[2] - expected.b) > 1) {
          if (wrong++ < 5)
            first_wrong << " (" << x << "," << y << ") = " << int(p[0]) << "," << int(p[1])
                        << "," << int(p[2]) << " expected " << expected.r << "," << expected.g
                        << "," << expected.b << ";";
        }
      }
    }
    EXPECT_GT(checked, c.window_w * c.window_h / 12);
    EXPECT_EQ(wrong, 0) << "of " << checked << " pixels:" << first_wrong.str();
    EXPECT_TRUE(window->present(left.framebuffer.id(), right.framebuffer.id(), c.eye_w, c.eye_h,
                                &error))
        << error;
  }
}

TEST_F(DesktopWindowTest, RefusesBadFramebuffersSizesAndAForeignContext) {
  auto window = makeWindow(320, 200, "telesphere refuse");
  ASSERT_TRUE(window);
  const DeskEyeImage eye = makeEyeImage(16, 16, GL_RGBA8, {255, 0, 0}, {0, 255, 0});
  const gl::GlFramebuffer empty = gl::createFramebuffer();  // no attachment: incomplete
  std::string error;
  EXPECT_FALSE(window->compose(0, eye.framebuffer.id(), 16, 16, &error));
  EXPECT_NE(error.find("left eye framebuffer is 0"), std::string::npos) << error;
  EXPECT_FALSE(window->compose(eye.framebuffer.id(), empty.id(), 16, 16, &error));
  EXPECT_NE(error.find("right eye framebuffer " + std::to_string(empty.id()) + " is incomplete"),
            std::string::npos)
      << error;
  EXPECT_FALSE(window->compose(eye.framebuffer.id(), 987654, 16, 16, &error));
  EXPECT_NE(error.find("is not a framebuffer object"), std::string::npos) << error;
  EXPECT_FALSE(window->present(eye.framebuffer.id(), eye.framebuffer.id(), 16, 0, &error));
  EXPECT_NE(error.find("eye image size must be positive, got 16x0"), std::string::npos) << error;

  // Another context current (here: none, released through EGL behind GLFW's back).
  ASSERT_TRUE(eglMakeCurrent(eglGetCurrentDisplay(), EGL_NO_SURFACE, EGL_NO_SURFACE,
                             EGL_NO_CONTEXT));
  EXPECT_FALSE(window->isCurrent());
  EXPECT_FALSE(window->setSwapInterval(0));
  EXPECT_FALSE(window->compose(eye.framebuffer.id(), eye.framebuffer.id(), 16, 16, &error));
  EXPECT_EQ(error, "the desktop window's context is not current on this thread");
  window->makeCurrent();
  EXPECT_TRUE(window->isCurrent());
  EXPECT_TRUE(window->compose(eye.framebuffer.id(), eye.framebuffer.id(), 16, 16, &error))
      << error;
}

TEST_F(DesktopWindowTest, XInputDrivesTheHeadAndTheCommands) {
  auto window = makeWindow(640, 400, "telesphere input");
  ASSERT_TRUE(window);
  const Window x_window = findXWindow("telesphere input");
  ASSERT_NE(x_window, 0u);
  XWindowAttributes attributes;
  ASSERT_NE(XGetWindowAttributes(x_display_, x_window, &attributes), 0);
  const int cx = attributes.x + 320, cy = attributes.y + 200;  // window centre, root coordinates
  XTestFakeMotionEvent(x_display_, -1, cx, cy, 0);
  XFlush(x_display_);
  ASSERT_TRUE(pumpUntil(*window, [] { return true; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  window->pollEvents();
  (void)window->headInput();
  (void)window->takeCommands();

  // Held W: forward while held, not after.
  pressKey(XK_w, true);
  EXPECT_TRUE(pumpUntil(*window, [&] { return window->headInput().forward; }));
  const desktop::VirtualHeadInput held = window->headInput();
  EXPECT_TRUE(held.forward);
  EXPECT_FALSE(held.back || held.left || held.right || held.up || held.down || held.look);
  pressKey(XK_w, false);
  EXPECT_TRUE(pumpUntil(*window, [&] { return !window->headInput().forward; }));
  pressKey(XK_space, true);
  EXPECT_TRUE(pumpUntil(*window, [&] { return window->headInput().up; }));
  pressKey(XK_space, false);
  EXPECT_TRUE(pumpUntil(*window, [&] { return !window->headInput().up; }));

  // N: capture_nominal exactly once.
  pressKey(XK_n, true);
  pressKey(XK_n, false);
  int captures = 0;
  desktop::DesktopCommands all;
  const auto take = [&] {
    const desktop::DesktopCommands commands = window->takeCommands();
    captures += commands.capture_nominal ? 1 : 0;
    all.cycle_mode |= commands.cycle_mode;
    all.radius_up |= commands.radius_up;
    all.radius_down |= commands.radius_down;
    all.reset_head |= commands.reset_head;
    all.quit |= commands.quit;
    return captures > 0;
  };
  EXPECT_TRUE(pumpUntil(*window, take));
  for (int i = 0; i < 20; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    window->pollEvents();
    take();
  }
  EXPECT_EQ(captures, 1);
  EXPECT_FALSE(all.cycle_mode || all.radius_up || all.radius_down || all.reset_head || all.quit);
  EXPECT_FALSE(window->takeCommands().capture_nominal);

  // Motion without the button: no look. Then a left drag right and down: positive deltas.
  XTestFakeMotionEvent(x_display_, -1, cx - 50, cy - 30, 0);
  XFlush(x_display_);
  double dx = 0, dy = 0;
  const auto accumulate = [&](bool* look = nullptr) {
    const desktop::VirtualHeadInput input = window->headInput();
    dx += input.mouse_dx_px;
    dy += input.mouse_dy_px;
    if (look != nullptr) *look = input.look;
  };
  // 100 ms of events with nothing expected to move the head.
  const auto pumpIdle = [&] {
    for (int i = 0; i < 20; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      window->pollEvents();
      accumulate();
    }
  };
  pumpIdle();
  EXPECT_EQ(dx, 0.0);
  EXPECT_EQ(dy, 0.0);
  XTestFakeButtonEvent(x_display_, 1, True, 0);
  XTestFakeMotionEvent(x_display_, -1, cx - 10, cy - 5, 0);
  XFlush(x_display_);
  bool looking = false;
  EXPECT_TRUE(pumpUntil(*window, [&] {
    accumulate(&looking);
    return dx >= 40.0 && dy >= 25.0;
  }));
  EXPECT_TRUE(looking);
  EXPECT_EQ(dx, 40.0);
  EXPECT_EQ(dy, 25.0);
  XTestFakeButtonEvent(x_display_, 1, False, 0);
  XFlush(x_display_);
  EXPECT_TRUE(pumpUntil(*window, [&] {
    accumulate(&looking);
    return !looking;
  }));
  dx = dy = 0;
  XTestFakeMotionEvent(x_display_, -1, cx + 60, cy + 60, 0);
  XFlush(x_display_);
  pumpIdle();
  EXPECT_EQ(dx, 0.0);
  EXPECT_EQ(dy, 0.0);

  // A whole drag between two frames (a slow frame: press, move and release all in one poll) still
  // turns the head: its deltas come with look set, as the head applies them only then.
  XTestFakeButtonEvent(x_display_, 1, True, 0);
  XTestFakeMotionEvent(x_display_, -1, cx + 90, cy + 80, 0);
  XTestFakeButtonEvent(x_display_, 1, False, 0);
  XSync(x_display_, False);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  double applied_dx = 0, applied_dy = 0;
  for (int i = 0; i < 20; ++i) {
    window->pollEvents();
    const desktop::VirtualHeadInput input = window->headInput();
    if (input.look) {
      applied_dx += input.mouse_dx_px;
      applied_dy += input.mouse_dy_px;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(applied_dx, 30.0) << "a drag that began and ended within one frame was dropped";
  EXPECT_EQ(applied_dy, 20.0);

  // The other commands, then Escape closes.
  for (const KeySym key : {XK_m, XK_equal, XK_KP_Subtract, XK_Home}) {
    pressKey(key, true);
    pressKey(key, false);
  }
  EXPECT_TRUE(pumpUntil(*window, [&] {
    take();
    return all.cycle_mode && all.radius_up && all.radius_down && all.reset_head;
  }));
  EXPECT_FALSE(window->shouldClose());
  pressKey(XK_Escape, true);
  pressKey(XK_Escape, false);
  EXPECT_TRUE(pumpUntil(*window, [&] { return window->shouldClose(); }));
  take();
  EXPECT_TRUE(all.quit);
}

}  // namespace
}  // namespace telesphere::xr
