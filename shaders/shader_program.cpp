// SPDX-License-Identifier: MIT
/// @brief Shader loading: #include expansion with #line markers, and logs mapped to file:line.
#include "shaders/shader_program.h"

#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <fstream>
#include <sstream>

namespace telesphere::gl {
namespace {

namespace fs = std::filesystem;

struct Assembled {
  std::string text;
  std::vector<std::string> files;  ///< #line source-string number → file path
  std::string error;
};

bool readFile(const fs::path& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream os;
  os << in.rdbuf();
  out = os.str();
  return true;
}

/// `line` is a preprocessor directive `#<name> rest`; returns rest (nothing otherwise).
std::optional<std::string> directive(const std::string& line, const std::string& name) {
  std::size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos || line[i] != '#') return std::nullopt;
  i = line.find_first_not_of(" \t", i + 1);
  if (i == std::string::npos || line.compare(i, name.size(), name) != 0) return std::nullopt;
  const std::size_t end = i + name.size();
  if (end < line.size() && line[end] != ' ' && line[end] != '\t') return std::nullopt;
  return line.substr(end);
}

/// The file name of `#include "name"`, or nothing when `line` is not such a directive.
std::optional<std::string> includeName(const std::string& line) {
  const auto rest = directive(line, "include");
  if (!rest) return std::nullopt;
  const std::size_t open = rest->find('"');
  const std::size_t close = open == std::string::npos ? open : rest->find('"', open + 1);
  if (close == std::string::npos) return std::nullopt;
  if (rest->find_first_not_of(" \t\r", close + 1) != std::string::npos) return std::nullopt;
  if (rest->find_first_not_of(" \t", 0) != open) return std::nullopt;
  return rest->substr(open + 1, close - open - 1);
}

fs::path resolve(const std::string& name) {
  const fs::path p(name);
  return p.is_absolute() ? p : fs::path(shaderDirectory()) / p;
}

/// Appends `path` with its includes expanded; `#version` is left to the caller.
bool expand(const fs::path& path, Assembled& out, bool is_main, std::string* version_line) {
  std::string text;
  if (!readFile(path, text)) {
    out.error = path.string() + ": cannot read shader file";
    return false;
  }
  for (const auto& f : out.files)
    if (f == path.string() && !is_main) return true;  // included once per program
  const int index = static_cast<int>(out.files.size());
  out.files.push_back(path.string());
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  out.text += "#line 1 " + std::to_string(index) + "\n";
  while (std::getline(lines, line)) {
    ++number;
    if (directive(line, "version")) {
      if (is_main && version_line && version_line->empty()) *version_line = line;
      out.text += "\n";
    } else if (const auto include = includeName(line)) {
      if (!expand(path.parent_path() / *include, out, false, nullptr)) {
        out.error = path.string() + ":" + std::to_string(number) + ": " + out.error;
        return false;
      }
      out.text += "#line " + std::to_string(number + 1) + " " + std::to_string(index) + "\n";
    } else {
      out.text += line + "\n";
    }
  }
  return true;
}

/// Digits at `i` (advancing it), or nothing.
std::optional<std::string> digits(const std::string& text, std::size_t& i) {
  const std::size_t start = i;
  while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
  if (i == start) return std::nullopt;
  return text.substr(start, i - start);
}

/// `literal` at `i` (advancing past it)?
bool skip(const std::string& text, std::size_t& i, const std::string& literal) {
  if (text.compare(i, literal.size(), literal) != 0) return false;
  i += literal.size();
  return true;
}

/// Rewrites the first "N:L(C):" (Mesa) or "N(L) :" (NVIDIA) in a log line into "file:L:C:" or
/// "file:L:", N being the #line source-string number of `files`.
std::string mapLine(const std::string& line, const std::vector<std::string>& files) {
  const auto name = [&](const std::string& index) {
    const auto k = static_cast<std::size_t>(std::stoul(index));
    return k < files.size() ? files[k] : "<string " + index + ">";
  };
  for (std::size_t start = 0; start < line.size(); ++start) {
    if (start > 0 && line[start - 1] >= '0' && line[start - 1] <= '9') continue;
    std::size_t i = start;
    const auto file = digits(line, i);
    if (!file) continue;
    std::size_t j = i;
    if (skip(line, j, ":")) {
      const auto row = digits(line, j);
      std::size_t k = j;
      if (row && skip(line, k, "(")) {
        const auto col = digits(line, k);
        if (col && skip(line, k, "):"))
          return line.substr(0, start) + name(*file) + ":" + *row + ":" + *col + ":" + line.substr(k);
      }
    }
    j = i;
    if (skip(line, j, "(")) {
      const auto row = digits(line, j);
      if (row && skip(line, j, ") :"))
        return line.substr(0, start) + name(*file) + ":" + *row + ":" + line.substr(j);
    }
  }
  return line;
}

std::string mapLog(const std::string& log, const std::vector<std::string>& files) {
  std::string out;
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) out += mapLine(line, files) + "\n";
  return out;
}

std::optional<GlShader> compile(GLenum stage, const std::string& file,
                                const std::vector<std::string>& defines, std::string* out_error) {
  Assembled assembled;
  std::string version;
  if (!expand(resolve(file), assembled, true, &version)) {
    if (out_error) *out_error = assembled.error;
    return std::nullopt;
  }
  if (version.empty()) version = "#version 450 core";
  std::string source = version + "\n";
  for (const auto& d : defines) source += "#define " + d + "\n";
  source += assembled.text;

  GlShader shader(glCreateShader(stage));
  const char* text = source.c_str();
  glShaderSource(shader.id(), 1, &text, nullptr);
  glCompileShader(shader.id());
  GLint ok = GL_FALSE;
  glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint length = 0;
    glGetShaderiv(shader.id(), GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader.id(), length, nullptr, log.data());
    if (out_error) *out_error = mapLog(log.c_str(), assembled.files);
    return std::nullopt;
  }
  return shader;
}

/// A program of `shaders`; nothing, with "linking NAME: log", when it does not link.
std::optional<GlProgram> link(std::initializer_list<const GlShader*> shaders, const std::string& name, std::string* out_error) {
  GlProgram program(glCreateProgram());
  for (const GlShader* shader : shaders) glAttachShader(program.id(), shader->id());
  glLinkProgram(program.id());
  for (const GlShader* shader : shaders) glDetachShader(program.id(), shader->id());
  GLint ok = GL_FALSE;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint length = 0;
    glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program.id(), length, nullptr, log.data());
    if (out_error) *out_error = "linking " + name + ": " + log.c_str();
    return std::nullopt;
  }
  return program;
}

}  // namespace

std::string shaderDirectory() {
  if (const char* dir = std::getenv("TELESPHERE_SHADER_DIR"); dir && *dir) return dir;
  return TELESPHERE_SHADER_SOURCE_DIR;
}

std::optional<GlProgram> loadProgram(const std::string& vertex_file,
                                     const std::string& fragment_file,
                                     const std::vector<std::string>& defines,
                                     std::string* out_error) {
  auto vs = compile(GL_VERTEX_SHADER, vertex_file, defines, out_error);
  if (!vs) return std::nullopt;
  auto fs = compile(GL_FRAGMENT_SHADER, fragment_file, defines, out_error);
  if (!fs) return std::nullopt;
  return link({&*vs, &*fs}, vertex_file + " + " + fragment_file, out_error);
}

std::optional<GlProgram> loadComputeProgram(const std::string& compute_file, const std::vector<std::string>& defines,
                                            std::string* out_error) {
  auto cs = compile(GL_COMPUTE_SHADER, compute_file, defines, out_error);
  if (!cs) return std::nullopt;
  return link({&*cs}, compute_file, out_error);
}

}  // namespace telesphere::gl
