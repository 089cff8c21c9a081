// SPDX-License-Identifier: MIT
/// @brief makeGlxSessionBinding: the current GLX context as an XrGraphicsBindingOpenGLXlibKHR.
#include "xr/openxr/openxr_glx_binding.h"

#include <X11/Xlib.h>
#include <GL/glx.h>

#define XR_USE_GRAPHICS_API_OPENGL 1
#define XR_USE_PLATFORM_XLIB 1
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

namespace telesphere::xr::openxr {

bool glxContextCurrent() { return glXGetCurrentContext() != nullptr; }

std::shared_ptr<const void> makeGlxSessionBinding(std::string* error) {
  GLXContext context = glXGetCurrentContext();
  Display* display = glXGetCurrentDisplay();
  const GLXDrawable drawable = glXGetCurrentDrawable();
  if (context == nullptr || display == nullptr) {
    *error = "no GLX context is current on this thread";
    return nullptr;
  }
  int fbconfig_id = 0, screen = 0;
  glXQueryContext(display, context, GLX_FBCONFIG_ID, &fbconfig_id);
  glXQueryContext(display, context, GLX_SCREEN, &screen);
  const int attributes[] = {GLX_FBCONFIG_ID, fbconfig_id, None};
  int count = 0;
  GLXFBConfig* configs = glXChooseFBConfig(display, screen, attributes, &count);
  if (configs == nullptr || count < 1) {
    if (configs != nullptr) XFree(configs);
    *error = "the current GLX context's FB config (id " + std::to_string(fbconfig_id) + ") was not found";
    return nullptr;
  }
  auto binding = std::make_shared<XrGraphicsBindingOpenGLXlibKHR>();
  binding->type = XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR;
  binding->next = nullptr;
  binding->xDisplay = display;
  binding->glxFBConfig = configs[0];
  binding->glxDrawable = drawable;
  binding->glxContext = context;
  if (XVisualInfo* visual = glXGetVisualFromFBConfig(display, configs[0])) {
    binding->visualid = static_cast<std::uint32_t>(visual->visualid);
    XFree(visual);
  }
  XFree(configs);
  return binding;
}

void restoreGlxContext(const std::shared_ptr<const void>& binding) {
  const auto* b = static_cast<const XrGraphicsBindingOpenGLXlibKHR*>(binding.get());
  if (b != nullptr && glXGetCurrentContext() != b->glxContext)
    glXMakeCurrent(b->xDisplay, b->glxDrawable, b->glxContext);
}

}  // namespace telesphere::xr::openxr
