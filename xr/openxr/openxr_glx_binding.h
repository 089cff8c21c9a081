// SPDX-License-Identifier: MIT
/// @brief The OpenXR graphics binding for a GLX context (XR_KHR_opengl_enable on Xlib: what
///        SteamVR and most desktop runtimes offer). Kept in its own translation unit because GLX's
///        header pulls in GL/gl.h, which must not meet the core-profile header of shaders/gl_api.h.
#pragma once

#include <memory>
#include <string>

namespace telesphere::xr::openxr {

/// A GLX context is current on the calling thread.
bool glxContextCurrent();

/// An XrGraphicsBindingOpenGLXlibKHR for the current GLX context (display, its FB config and
/// visual, drawable, context), ready to chain into XrSessionCreateInfo::next; null with the
/// reason when no GLX context is current or its FB config cannot be found.
std::shared_ptr<const void> makeGlxSessionBinding(std::string* error);

/// Makes the binding's context current again (a runtime's client may switch contexts while it
/// creates the session).
void restoreGlxContext(const std::shared_ptr<const void>& binding);

}  // namespace telesphere::xr::openxr
