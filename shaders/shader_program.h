// SPDX-License-Identifier: MIT
/// @brief GLSL programs loaded from files at run time. A file may pull in others with
///        `#include "name.glsl"` on a line of its own (resolved beside it, once per program);
///        `#define`s given by the caller go right after `#version`. Compile and link errors name
///        the file and line ("shaders/sphere_exact.frag:42:7: error: ..."), not GLSL string
///        numbers.
///
/// Where files are found: a relative name is looked up in shaderDirectory(), which is
/// $TELESPHERE_SHADER_DIR when set (installed or relocated shaders) and otherwise this source
/// folder (compiled in, so build trees work without installing).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "shaders/gl_objects.h"

namespace telesphere::gl {

/// The folder GLSL files are read from (see the file comment).
std::string shaderDirectory();

/// Compiles and links a program from a vertex and a fragment shader file. `defines` are lines
/// such as "TS_MODEL 0". Nothing on failure, with the reason (file:line for compile errors, the
/// file that could not be read, or the link log) in out_error.
std::optional<GlProgram> loadProgram(const std::string& vertex_file,
                                     const std::string& fragment_file,
                                     const std::vector<std::string>& defines = {},
                                     std::string* out_error = nullptr);

/// As loadProgram, for a compute shader on its own (GL 4.3+).
std::optional<GlProgram> loadComputeProgram(const std::string& compute_file, const std::vector<std::string>& defines = {},
                                            std::string* out_error = nullptr);

}  // namespace telesphere::gl
