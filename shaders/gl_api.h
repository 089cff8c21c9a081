// SPDX-License-Identifier: MIT
/// @brief The one place that includes the OpenGL 4.5 core API (glcorearb.h with prototypes; the
///        entry points come from glvnd's libOpenGL) and EGL.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>
