// SPDX-License-Identifier: MIT
#include "tests/xr/monado/leak_report.h"

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <map>
#include <optional>
#include <sstream>

namespace telesphere::test {
namespace {

std::string leakTrim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r");
  return s.substr(begin, end - begin + 1);
}

bool isLeakFrameLine(const std::string& trimmed) {
  return trimmed.size() > 1 && trimmed[0] == '#' && trimmed[1] >= '0' && trimmed[1] <= '9';
}

std::string leakRootFolder(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

std::string leakFileName(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// Lines that start a sanitizer report other than a leak block.
bool isOtherSanitizerReport(const std::string& line) {
  if (line.find("ERROR: LeakSanitizer: detected memory leaks") != std::string::npos) return false;
  static const char* const kMarkers[] = {
      "ERROR: AddressSanitizer",       "ERROR: LeakSanitizer",
      "AddressSanitizer:DEADLYSIGNAL", "ERROR: UndefinedBehaviorSanitizer",
      "runtime error:",                "LeakSanitizer has encountered a fatal error",
      "Tracer caught signal",
  };
  for (const char* marker : kMarkers)
    if (line.find(marker) != std::string::npos) return true;
  return false;
}

}  // namespace

std::string LeakBlock::allocatingFrame() const {
  return allocating_frame < frames.size() ? frames[allocating_frame] : std::string();
}

std::string LeakBlock::allocatingModule() const {
  const std::string frame = allocatingFrame();
  if (frame.empty()) return "?";
  // "#1 0x… in f (/path/libx.so+0x1234)" or "#1 0x… (/path/libx.so+0x1234)"
  const auto plus = frame.rfind("+0x");
  const auto open = frame.rfind('(', plus);
  if (plus != std::string::npos && open != std::string::npos) return leakFileName(frame.substr(open + 1, plus - open - 1));
  // "#1 0x… in f /path/file.cpp:12" (symbolized with a source line)
  const auto space = frame.rfind(' ');
  if (space == std::string::npos) return "?";
  std::string location = frame.substr(space + 1);
  if (const auto colon = location.find(':'); colon != std::string::npos) location.resize(colon);
  return leakFileName(location);
}

long long SanitizerFindings::foreignBytes() const {
  long long bytes = 0;
  for (const LeakBlock& b : foreign) bytes += b.bytes;
  return bytes;
}

std::string SanitizerFindings::foreignSummary() const {
  std::map<std::string, int> modules;
  for (const LeakBlock& b : foreign) ++modules[b.allocatingModule()];
  std::ostringstream out;
  out << foreign.size() << " foreign leak block" << (foreign.size() == 1 ? "" : "s") << " (" << foreignBytes()
      << " bytes)";
  if (!modules.empty()) {
    out << " allocated in";
    const char* separator = " ";
    for (const auto& [module, count] : modules) {
      out << separator << module << " ×" << count;
      separator = ", ";
    }
  }
  return out.str();
}

std::string SanitizerFindings::oursText() const {
  std::ostringstream out;
  for (const std::string& report : other_reports) out << report << '\n';
  for (const LeakBlock& b : ours) out << b.text << '\n';
  return out.str();
}

bool isSanitizerRuntimeFrame(const std::string& frame) {
  // GCC's runtime (its sources under libsanitizer/, or the shared libasan without debug info) and
  // LLVM's (compiler-rt sources, or its shared runtime). An unsymbolized frame of a runtime linked
  // statically into our binary is not recognised: the block then counts as ours, the safe side.
  static const char* const kRuntime[] = {"/libsanitizer/", "libasan.so", "compiler-rt/lib/", "libclang_rt.asan"};
  for (const char* marker : kRuntime)
    if (frame.find(marker) != std::string::npos) return true;
  return false;
}

/// Parses "Direct leak of 2352 byte(s) in 49 object(s) allocated from:" (or Indirect), as
/// LeakSanitizer prints it; nullopt for any other line. (Not std::regex: GCC 12 warns inside it.)
static std::optional<LeakBlock> parseLeakHeader(const std::string& line) {
  const std::string trimmed = leakTrim(line);
  LeakBlock block;
  std::size_t pos = std::string::npos;
  for (const bool direct : {true, false}) {
    const char* const phrase = direct ? "Direct leak of " : "Indirect leak of ";
    const std::size_t at = trimmed.find(phrase);
    if (at == std::string::npos) continue;
    block.direct = direct;
    pos = at + std::strlen(phrase);
    break;
  }
  if (pos == std::string::npos) return std::nullopt;
  const auto number = [&](const char* then) -> std::optional<long long> {
    std::size_t end = pos;
    while (end < trimmed.size() && std::isdigit(static_cast<unsigned char>(trimmed[end]))) ++end;
    if (end == pos || trimmed.compare(end, std::strlen(then), then) != 0) return std::nullopt;
    const long long value = std::atoll(trimmed.substr(pos, end - pos).c_str());
    pos = end + std::strlen(then);
    return value;
  };
  const auto bytes = number(" byte(s) in ");
  if (!bytes) return std::nullopt;
  const auto objects = number(" object(s) allocated from:");
  if (!objects || pos != trimmed.size()) return std::nullopt;
  block.bytes = *bytes;
  block.objects = *objects;
  block.text = line;
  return block;
}

SanitizerFindings classifySanitizerOutput(const std::string& output, const std::vector<std::string>& foreign_roots) {
  std::vector<std::string> roots;
  for (const std::string& root : foreign_roots)
    if (!root.empty()) roots.push_back(leakRootFolder(root) + "/");

  SanitizerFindings findings;
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) lines.push_back(line);

  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::optional<LeakBlock> header = parseLeakHeader(lines[i]);
    if (!header) {
      if (isOtherSanitizerReport(lines[i])) findings.other_reports.push_back(leakTrim(lines[i]));
      continue;
    }
    LeakBlock block = std::move(*header);
    while (i + 1 < lines.size() && isLeakFrameLine(leakTrim(lines[i + 1]))) {
      block.frames.push_back(leakTrim(lines[++i]));
      block.text += '\n' + lines[i];
    }
    block.allocating_frame = 0;
    while (block.allocating_frame < block.frames.size() && isSanitizerRuntimeFrame(block.frames[block.allocating_frame]))
      ++block.allocating_frame;
    bool foreign = false;
    const std::string allocating = block.allocatingFrame();
    for (const std::string& root : roots) foreign = foreign || allocating.find(root) != std::string::npos;
    (foreign ? findings.foreign : findings.ours).push_back(std::move(block));
  }
  return findings;
}

}  // namespace telesphere::test
