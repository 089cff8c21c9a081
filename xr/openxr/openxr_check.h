// SPDX-License-Identifier: MIT
/// @brief Checked OpenXR calls (STYLE.md §13): every call's result is tested where it is made,
///        and a failure is described with the call's source text, the XrResult's name and the
///        place: `xrBeginSession(session_, &begin) failed: XR_ERROR_SESSION_NOT_READY (-28)
///        [xr/openxr/openxr_session.cpp:123]`.
#pragma once

#include <openxr/openxr.h>

#include <string>

namespace telesphere::xr::openxr {

/// The XrResult's enumerant name ("XR_ERROR_SESSION_LOST"), or "XrResult(<value>)" for values
/// this header version does not know (runtimes may return newer codes).
std::string xrResultName(XrResult result);

/// Describes a failed call: "<call> failed: <name> (<value>) [<file>:<line>]".
std::string describeXrFailure(XrResult result, const char* call, const char* file, int line);

/// True when `result` succeeded (XR_SUCCEEDED: XR_SUCCESS or a qualified success such as
/// XR_SESSION_LOSS_PENDING). Otherwise false with describeXrFailure(...) in *out_error (when not
/// null) and *out_result (when not null) set to the result.
bool checkXr(XrResult result, const char* call, const char* file, int line,
             std::string* out_error, XrResult* out_result = nullptr);

}  // namespace telesphere::xr::openxr

/// Evaluates the OpenXR call `call` and checks it with its own source text; an expression of
/// type bool. Example: `if (!TELESPHERE_CHECK_XR(xrEndSession(session), &error)) return false;`
#define TELESPHERE_CHECK_XR(call, out_error) \
  ::telesphere::xr::openxr::checkXr((call), #call, __FILE__, __LINE__, (out_error))

/// The same, also storing the XrResult in *out_result (to react to XR_ERROR_SESSION_LOST etc.).
#define TELESPHERE_CHECK_XR_RESULT(call, out_error, out_result) \
  ::telesphere::xr::openxr::checkXr((call), #call, __FILE__, __LINE__, (out_error), (out_result))
