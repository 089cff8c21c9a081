// SPDX-License-Identifier: MIT
/// @brief EglContext: a windowless EGL display (Mesa surfaceless, else the first EGL device), GL 4.5 core context.
#include "shaders/egl_context.h"

#include <cstring>
#include <sstream>
#include <vector>

namespace telesphere::gl {
namespace {

bool fail(std::string* out_error, const char* call) {
  if (out_error) {
    std::ostringstream os;
    os << call << " failed with EGL error 0x" << std::hex << eglGetError();
    *out_error = os.str();
  }
  return false;
}

/// Mesa's surfaceless platform (llvmpipe without a GPU, or Mesa's GPU drivers).
EGLDisplay mesaSurfacelessDisplay(PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display) {
  return get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
}

/// The EGL devices (EGL_EXT_device_enumeration; the first 8), none where EGL cannot list them.
std::vector<EGLDeviceEXT> eglDevices() {
  const auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  std::vector<EGLDeviceEXT> devices(8);
  EGLint count = 0;
  if (!query_devices || !query_devices(static_cast<EGLint>(devices.size()), devices.data(), &count)) count = 0;
  devices.resize(static_cast<std::size_t>(count));
  return devices;
}

/// The first EGL device (EGL_EXT_platform_device): NVIDIA's driver offers no Mesa platform, but
/// makes windowless contexts on a device display.
EGLDisplay firstDeviceDisplay(PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display) {
  const std::vector<EGLDeviceEXT> devices = eglDevices();
  return devices.empty() ? EGL_NO_DISPLAY : get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
}

}  // namespace

std::unique_ptr<EglContext> EglContext::createSurfaceless(std::string* out_error) {
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) {
    fail(out_error, "eglGetProcAddress(\"eglGetPlatformDisplayEXT\")");
    return nullptr;
  }
  EGLDisplay display = mesaSurfacelessDisplay(get_platform_display);
  if (display == EGL_NO_DISPLAY) display = firstDeviceDisplay(get_platform_display);
  if (display == EGL_NO_DISPLAY) {
    fail(out_error, "eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, then EGL_PLATFORM_DEVICE_EXT)");
    return nullptr;
  }
  return contextOn(display, out_error);
}

/// A GL 4.5 core context on `display` (initialised here), current on this thread.
std::unique_ptr<EglContext> EglContext::contextOn(EGLDisplay display, std::string* out_error) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    fail(out_error, "eglInitialize");
    return nullptr;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    fail(out_error, "eglBindAPI(EGL_OPENGL_API)");
    return nullptr;
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    fail(out_error, "eglCreateContext(OpenGL 4.5 core, EGL_NO_CONFIG_KHR)");
    return nullptr;
  }
  std::unique_ptr<EglContext> result(new EglContext(display, context));
  if (!result->makeCurrent()) {
    fail(out_error, "eglMakeCurrent(EGL_NO_SURFACE)");
    return nullptr;
  }
  return result;
}

std::unique_ptr<EglContext> EglContext::createOnHardwareDevice(std::string* out_error) {
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  const auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  const auto query_device_string =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (!get_platform_display || !query_devices || !query_device_string) {
    if (out_error) *out_error = "this EGL cannot list devices (EGL_EXT_device_enumeration, EGL_EXT_device_query)";
    return nullptr;
  }
  const std::vector<EGLDeviceEXT> devices = eglDevices();
  const std::size_t count = devices.size();
  std::string why = "no EGL device";
  int software = 0;
  for (const EGLDeviceEXT device : devices) {
    // Mesa lists its software rasterizer (llvmpipe) as a device of its own.
    const char* extensions = query_device_string(device, EGL_EXTENSIONS);
    if (extensions && std::strstr(extensions, "EGL_MESA_device_software")) {
      ++software;
      continue;
    }
    const EGLDisplay display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
    if (display == EGL_NO_DISPLAY) continue;
    if (auto context = contextOn(display, &why)) {
      if (!context->software()) return context;
      ++software;
      why = "no EGL device";
    }
  }
  if (out_error)
    *out_error = why + " with a GPU (" + std::to_string(count) + " EGL device" + (count == 1 ? "" : "s") + ", " +
                 std::to_string(software) + " of them software)";
  return nullptr;
}

EglContext::~EglContext() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  // No eglTerminate: the surfaceless display is one per process, shared by every EglContext
  // (terminating it would destroy the others' contexts), and it stays initialised until exit.
  eglReleaseThread();
}

bool EglContext::makeCurrent() const {
  return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE;
}

std::string EglContext::renderer() const {
  const auto* text = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return text ? text : "";
}

bool EglContext::software() const {
  const std::string name = renderer();
  for (const char* rasterizer : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer"})
    if (name.find(rasterizer) != std::string::npos) return true;
  return false;
}

}  // namespace telesphere::gl
