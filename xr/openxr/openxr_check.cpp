// SPDX-License-Identifier: MIT
/// @brief Names of XrResult values from the OpenXR reflection header, and failure messages.
#include "xr/openxr/openxr_check.h"

#include <openxr/openxr_reflection.h>

namespace telesphere::xr::openxr {

std::string xrResultName(XrResult result) {
  switch (result) {
#define TELESPHERE_XR_RESULT_CASE(name, value) \
  case name:                                   \
    return #name;
    XR_LIST_ENUM_XrResult(TELESPHERE_XR_RESULT_CASE)
#undef TELESPHERE_XR_RESULT_CASE
    default:
      break;
  }
  return "XrResult(" + std::to_string(static_cast<long long>(result)) + ")";
}

std::string describeXrFailure(XrResult result, const char* call, const char* file, int line) {
  std::string text(call ? call : "<OpenXR call>");
  text.append(" failed: ");
  text.append(xrResultName(result));
  text.append(" (");
  text.append(std::to_string(static_cast<long long>(result)));
  text.append(") [");
  text.append(file ? file : "?");
  text.append(":");
  text.append(std::to_string(line));
  text.append("]");
  return text;
}

bool checkXr(XrResult result, const char* call, const char* file, int line,
             std::string* out_error, XrResult* out_result) {
  if (out_result) *out_result = result;
  if (XR_SUCCEEDED(result)) return true;
  if (out_error) *out_error = describeXrFailure(result, call, file, line);
  return false;
}

}  // namespace telesphere::xr::openxr
