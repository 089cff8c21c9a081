// SPDX-License-Identifier: MIT
/// @brief OpenXrSession: instance, EGL or GLX graphics binding, swapchains, actions, events and
///        the frame loop.
#include "xr/openxr/openxr_session.h"

#define XR_USE_GRAPHICS_API_OPENGL 1
#define XR_USE_PLATFORM_EGL 1
#define XR_USE_TIMESPEC 1
#include <time.h>

#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>

#include "robot/link/link_endpoints.h"
#include "shaders/gl_objects.h"
#include "xr/openxr/openxr_check.h"
#include "xr/openxr/openxr_glx_binding.h"
#include "xr/openxr/openxr_pose.h"
#include "xr/openxr/openxr_struct.h"

namespace telesphere::xr::openxr {
namespace {

constexpr XrViewConfigurationType kOpenXrViewConfig = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;

bool openXrHasExtension(const std::vector<XrExtensionProperties>& all, const char* name) {
  return std::any_of(all.begin(), all.end(), [&](const XrExtensionProperties& e) {
    return std::strcmp(e.extensionName, name) == 0;
  });
}

bool openXrIsLoss(XrResult r) {
  return r == XR_ERROR_INSTANCE_LOST || r == XR_ERROR_SESSION_LOST ||
         r == XR_ERROR_RUNTIME_FAILURE || r == XR_ERROR_RUNTIME_UNAVAILABLE;
}

void setFailure(OpenXrFailure* out, OpenXrFailure f) {
  if (out) *out = f;
}

}  // namespace

std::optional<bool> openXrRuntimeOffers(const char* name) {
  std::uint32_t count = 0;
  if (XR_FAILED(xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr))) return std::nullopt;
  std::vector<XrExtensionProperties> extensions(count, xrStruct<XrExtensionProperties>(XR_TYPE_EXTENSION_PROPERTIES));
  if (XR_FAILED(xrEnumerateInstanceExtensionProperties(nullptr, count, &count, extensions.data()))) return std::nullopt;
  extensions.resize(count);
  return openXrHasExtension(extensions, name);
}

std::string noRuntimeHelp() {
  return "no OpenXR runtime is available. To use a headset install and start one: Monado "
         "(https://monado.freedesktop.org; Debian/Ubuntu: apt install monado-service "
         "libopenxr1-monado, then run monado-service) or SteamVR (set it as the OpenXR runtime "
         "in its settings); the loader finds the active runtime through "
         "/etc/xdg/openxr/1/active_runtime.json or $XR_RUNTIME_JSON. Without a headset: "
         "`telesphere-xr desktop` shows the robot's cameras in a window moved by mouse and "
         "keyboard, `telesphere-xr offscreen` runs the loop headless from a trajectory, and "
         "tests/xr/monado/run_with_monado.sh runs any command against a headless simulated "
         "Monado (see xr/README.md, \"OpenXR session\").";
}

struct OpenXrSession::Impl {
  XrInstance instance = XR_NULL_HANDLE;
  XrSystemId system = XR_NULL_SYSTEM_ID;
  XrSession session = XR_NULL_HANDLE;
  XrSpace space = XR_NULL_HANDLE;
  /// XR_KHR_convert_timespec_time: XrTime → CLOCK_MONOTONIC (the link's steady clock).
  PFN_xrConvertTimeToTimespecTimeKHR time_to_timespec = nullptr;
  /// The operator's controller buttons: select (either hand) captures the nominal pose.
  XrActionSet action_set = XR_NULL_HANDLE;
  XrAction capture_nominal = XR_NULL_HANDLE;
  struct Eye {
    XrSwapchain swapchain = XR_NULL_HANDLE;
    std::vector<XrSwapchainImageOpenGLKHR> images;
    gl::GlFramebuffer framebuffer;   // the acquired swapchain image + depth
    gl::GlRenderbuffer depth;
    gl::GlTexture staging;           // linear swapchains: sRGB texture rendered first
    gl::GlFramebuffer staging_framebuffer;
  };
  std::array<Eye, 2> eyes;

  ~Impl() {
    for (Eye& e : eyes)
      if (e.swapchain != XR_NULL_HANDLE) xrDestroySwapchain(e.swapchain);
    if (space != XR_NULL_HANDLE) xrDestroySpace(space);
    if (action_set != XR_NULL_HANDLE) xrDestroyActionSet(action_set);
    if (session != XR_NULL_HANDLE) xrDestroySession(session);
    if (instance != XR_NULL_HANDLE) xrDestroyInstance(instance);
  }
};

OpenXrSession::OpenXrSession(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OpenXrSession::~OpenXrSession() = default;

std::unique_ptr<OpenXrSession> OpenXrSession::create(const OpenXrOptions& options,
                                                     std::string* out_error,
                                                     OpenXrFailure* out_failure) {
  setFailure(out_failure, OpenXrFailure::kFailed);
  std::string local_error;
  std::string* error = out_error ? out_error : &local_error;

  // The binding follows the current context: EGL (XR_MNDX_egl_enable) or GLX (Xlib).
  const EGLDisplay egl_display = eglGetCurrentDisplay();
  const EGLContext egl_context = eglGetCurrentContext();
  const bool use_egl = egl_display != EGL_NO_DISPLAY && egl_context != EGL_NO_CONTEXT;
  if (!use_egl && !glxContextCurrent()) {
    *error = "OpenXrSession::create needs a current EGL or GLX OpenGL context on this thread";
    return nullptr;
  }

  // Extensions: which graphics binding the runtime offers.
  std::uint32_t count = 0;
  XrResult result = xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr);
  if (XR_FAILED(result)) {
    *error = describeXrFailure(result, "xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr)",
                               __FILE__, __LINE__) + ": " + noRuntimeHelp();
    setFailure(out_failure, OpenXrFailure::kNoRuntime);
    return nullptr;
  }
  std::vector<XrExtensionProperties> extensions(count, xrStruct<XrExtensionProperties>(XR_TYPE_EXTENSION_PROPERTIES));
  if (!TELESPHERE_CHECK_XR(xrEnumerateInstanceExtensionProperties(nullptr, count, &count, extensions.data()), error))
    return nullptr;
  extensions.resize(count);
  const bool has_gl = openXrHasExtension(extensions, XR_KHR_OPENGL_ENABLE_EXTENSION_NAME);
  const bool has_egl = openXrHasExtension(extensions, XR_MNDX_EGL_ENABLE_EXTENSION_NAME);
  if (!has_gl || (use_egl && !has_egl)) {
    *error = std::string("the OpenXR runtime offers ") +
             (has_gl ? "XR_KHR_opengl_enable but not XR_MNDX_egl_enable, which an EGL context needs; "
                       "use a GLX context instead (telesphere-xr openxr --binding glx, needs an X display)"
                     : "no OpenGL binding (XR_KHR_opengl_enable); telesphere-xr renders with OpenGL");
    setFailure(out_failure, OpenXrFailure::kNoGraphicsBinding);
    return nullptr;
  }

  auto impl = std::make_unique<Impl>();
  std::vector<const char*> enabled{XR_KHR_OPENGL_ENABLE_EXTENSION_NAME};
  if (use_egl) enabled.push_back(XR_MNDX_EGL_ENABLE_EXTENSION_NAME);
  const bool has_timespec = openXrHasExtension(extensions, XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME);
  if (has_timespec) enabled.push_back(XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME);
  auto instance_info = xrStruct<XrInstanceCreateInfo>(XR_TYPE_INSTANCE_CREATE_INFO);
  std::strncpy(instance_info.applicationInfo.applicationName, options.application_name.c_str(),
               XR_MAX_APPLICATION_NAME_SIZE - 1);
  std::strncpy(instance_info.applicationInfo.engineName, "telesphere", XR_MAX_ENGINE_NAME_SIZE - 1);
  instance_info.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
  instance_info.enabledExtensionCount = std::uint32_t(enabled.size());
  instance_info.enabledExtensionNames = enabled.data();
  result = xrCreateInstance(&instance_info, &impl->instance);
  if (XR_FAILED(result)) {
    *error = describeXrFailure(result, "xrCreateInstance(&instance_info, &impl->instance)", __FILE__, __LINE__);
    if (result == XR_ERROR_RUNTIME_UNAVAILABLE || result == XR_ERROR_RUNTIME_FAILURE ||
        result == XR_ERROR_INSTANCE_LOST) {
      *error += ": " + noRuntimeHelp();
      setFailure(out_failure, OpenXrFailure::kNoRuntime);
    }
    return nullptr;
  }
  if (has_timespec &&
      !TELESPHERE_CHECK_XR(xrGetInstanceProcAddr(impl->instance, "xrConvertTimeToTimespecTimeKHR", reinterpret_cast<PFN_xrVoidFunction*>(&impl->time_to_timespec)), error))
    return nullptr;
  auto instance_props = xrStruct<XrInstanceProperties>(XR_TYPE_INSTANCE_PROPERTIES);
  if (!TELESPHERE_CHECK_XR(xrGetInstanceProperties(impl->instance, &instance_props), error)) return nullptr;

  auto system_info = xrStruct<XrSystemGetInfo>(XR_TYPE_SYSTEM_GET_INFO);
  system_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  result = xrGetSystem(impl->instance, &system_info, &impl->system);
  if (result == XR_ERROR_FORM_FACTOR_UNAVAILABLE) {
    *error = "the OpenXR runtime has no head-mounted display connected "
             "(xrGetSystem: XR_ERROR_FORM_FACTOR_UNAVAILABLE): connect and switch on the headset";
    setFailure(out_failure, OpenXrFailure::kNoHmd);
    return nullptr;
  }
  if (!TELESPHERE_CHECK_XR(result, error)) return nullptr;
  auto system_props = xrStruct<XrSystemProperties>(XR_TYPE_SYSTEM_PROPERTIES);
  if (!TELESPHERE_CHECK_XR(xrGetSystemProperties(impl->instance, impl->system, &system_props), error))
    return nullptr;

  // Stereo views.
  std::uint32_t view_count = 0;
  if (!TELESPHERE_CHECK_XR(xrEnumerateViewConfigurationViews(impl->instance, impl->system, kOpenXrViewConfig, 0, &view_count, nullptr), error))
    return nullptr;
  if (view_count != 2) {
    *error = "the stereo view configuration has " + std::to_string(view_count) + " views, not 2";
    return nullptr;
  }
  std::array<XrViewConfigurationView, 2> config_views{};
  for (auto& v : config_views) v = xrStruct<XrViewConfigurationView>(XR_TYPE_VIEW_CONFIGURATION_VIEW);
  if (!TELESPHERE_CHECK_XR(xrEnumerateViewConfigurationViews(impl->instance, impl->system, kOpenXrViewConfig, 2, &view_count, config_views.data()), error))
    return nullptr;

  // Graphics requirements must be queried before xrCreateSession.
  PFN_xrGetOpenGLGraphicsRequirementsKHR get_requirements = nullptr;
  if (!TELESPHERE_CHECK_XR(xrGetInstanceProcAddr(impl->instance, "xrGetOpenGLGraphicsRequirementsKHR", reinterpret_cast<PFN_xrVoidFunction*>(&get_requirements)), error))
    return nullptr;
  auto requirements = xrStruct<XrGraphicsRequirementsOpenGLKHR>(XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR);
  if (!TELESPHERE_CHECK_XR(get_requirements(impl->instance, impl->system, &requirements), error))
    return nullptr;
  const XrVersion have_gl = XR_MAKE_VERSION(4, 5, 0);
  if (have_gl < requirements.minApiVersionSupported) {
    *error = "the OpenXR runtime needs OpenGL " +
             std::to_string(XR_VERSION_MAJOR(requirements.minApiVersionSupported)) + "." +
             std::to_string(XR_VERSION_MINOR(requirements.minApiVersionSupported)) +
             ", the context is 4.5";
    return nullptr;
  }

  // The session on the current context.
  std::shared_ptr<const void> glx_binding;
  if (!use_egl) {
    glx_binding = makeGlxSessionBinding(error);
    if (!glx_binding) return nullptr;
  }
  EGLint config_id = 0;
  EGLConfig egl_config = EGL_NO_CONFIG_KHR;
  if (use_egl && eglQueryContext(egl_display, egl_context, EGL_CONFIG_ID, &config_id) && config_id != 0) {
    const EGLint attributes[] = {EGL_CONFIG_ID, config_id, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(egl_display, attributes, &egl_config, 1, &n) || n != 1)
      egl_config = EGL_NO_CONFIG_KHR;
  }
  auto binding = xrStruct<XrGraphicsBindingEGLMNDX>(XR_TYPE_GRAPHICS_BINDING_EGL_MNDX);
  binding.getProcAddress = eglGetProcAddress;
  binding.display = egl_display;
  binding.config = egl_config;
  binding.context = egl_context;
  auto session_info = xrStruct<XrSessionCreateInfo>(XR_TYPE_SESSION_CREATE_INFO);
  session_info.next = use_egl ? static_cast<const void*>(&binding) : glx_binding.get();
  session_info.systemId = impl->system;
  if (!TELESPHERE_CHECK_XR(xrCreateSession(impl->instance, &session_info, &impl->session), error))
    return nullptr;
  // Monado's client may leave its own context current: ours is the one we render with.
  if (use_egl && eglGetCurrentContext() != egl_context)
    eglMakeCurrent(egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_context);
  if (!use_egl) restoreGlxContext(glx_binding);

  // Reference space: STAGE where offered, else LOCAL.
  std::uint32_t space_count = 0;
  if (!TELESPHERE_CHECK_XR(xrEnumerateReferenceSpaces(impl->session, 0, &space_count, nullptr), error))
    return nullptr;
  std::vector<XrReferenceSpaceType> spaces(space_count);
  if (!TELESPHERE_CHECK_XR(xrEnumerateReferenceSpaces(impl->session, space_count, &space_count, spaces.data()), error))
    return nullptr;
  const bool has_stage = std::find(spaces.begin(), spaces.end(), XR_REFERENCE_SPACE_TYPE_STAGE) != spaces.end();
  auto space_info = xrStruct<XrReferenceSpaceCreateInfo>(XR_TYPE_REFERENCE_SPACE_CREATE_INFO);
  space_info.referenceSpaceType = has_stage ? XR_REFERENCE_SPACE_TYPE_STAGE : XR_REFERENCE_SPACE_TYPE_LOCAL;
  space_info.poseInReferenceSpace.orientation.w = 1.0f;
  if (!TELESPHERE_CHECK_XR(xrCreateReferenceSpace(impl->session, &space_info, &impl->space), error))
    return nullptr;

  // Actions: "capture nominal pose" on the select button of a simple controller in either hand
  // (runtimes map it to their controllers' trigger or A button).
  auto set_info = xrStruct<XrActionSetCreateInfo>(XR_TYPE_ACTION_SET_CREATE_INFO);
  std::strncpy(set_info.actionSetName, "operator", XR_MAX_ACTION_SET_NAME_SIZE - 1);
  std::strncpy(set_info.localizedActionSetName, "Operator", XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE - 1);
  if (!TELESPHERE_CHECK_XR(xrCreateActionSet(impl->instance, &set_info, &impl->action_set), error)) return nullptr;
  std::array<XrPath, 2> hands{};
  if (!TELESPHERE_CHECK_XR(xrStringToPath(impl->instance, "/user/hand/left", &hands[0]), error) ||
      !TELESPHERE_CHECK_XR(xrStringToPath(impl->instance, "/user/hand/right", &hands[1]), error))
    return nullptr;
  auto action_info = xrStruct<XrActionCreateInfo>(XR_TYPE_ACTION_CREATE_INFO);
  action_info.actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
  std::strncpy(action_info.actionName, "capture_nominal", XR_MAX_ACTION_NAME_SIZE - 1);
  std::strncpy(action_info.localizedActionName, "Capture the nominal pose", XR_MAX_LOCALIZED_ACTION_NAME_SIZE - 1);
  action_info.countSubactionPaths = std::uint32_t(hands.size());
  action_info.subactionPaths = hands.data();
  if (!TELESPHERE_CHECK_XR(xrCreateAction(impl->action_set, &action_info, &impl->capture_nominal), error))
    return nullptr;
  std::array<XrActionSuggestedBinding, 2> bindings{};
  const char* select_paths[2] = {"/user/hand/left/input/select/click", "/user/hand/right/input/select/click"};
  for (std::size_t i = 0; i < 2; ++i) {
    bindings[i].action = impl->capture_nominal;
    if (!TELESPHERE_CHECK_XR(xrStringToPath(impl->instance, select_paths[i], &bindings[i].binding), error))
      return nullptr;
  }
  auto suggested = xrStruct<XrInteractionProfileSuggestedBinding>(XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING);
  if (!TELESPHERE_CHECK_XR(xrStringToPath(impl->instance, "/interaction_profiles/khr/simple_controller", &suggested.interactionProfile), error))
    return nullptr;
  suggested.countSuggestedBindings = std::uint32_t(bindings.size());
  suggested.suggestedBindings = bindings.data();
  if (!TELESPHERE_CHECK_XR(xrSuggestInteractionProfileBindings(impl->instance, &suggested), error)) return nullptr;
  auto attach = xrStruct<XrSessionActionSetsAttachInfo>(XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO);
  attach.countActionSets = 1;
  attach.actionSets = &impl->action_set;
  if (!TELESPHERE_CHECK_XR(xrAttachSessionActionSets(impl->session, &attach), error)) return nullptr;

  // Swapchains.
  std::uint32_t format_count = 0;
  if (!TELESPHERE_CHECK_XR(xrEnumerateSwapchainFormats(impl->session, 0, &format_count, nullptr), error))
    return nullptr;
  std::vector<std::int64_t> formats(format_count);
  if (!TELESPHERE_CHECK_XR(xrEnumerateSwapchainFormats(impl->session, format_count, &format_count, formats.data()), error))
    return nullptr;
  const auto format = chooseSwapchainFormat(formats, options.colour);
  if (!format) {
    *error = "the OpenXR runtime offers no colour swapchain format we render to (want "
             "GL_SRGB8_ALPHA8, GL_SRGB8, GL_RGBA8, GL_RGB10_A2 or GL_RGBA16F)";
    return nullptr;
  }
  const int width = int(config_views[0].recommendedImageRectWidth);
  const int height = int(config_views[0].recommendedImageRectHeight);
  for (int i = 0; i < 2; ++i) {
    Impl::Eye& eye = impl->eyes[std::size_t(i)];
    auto swapchain_info = xrStruct<XrSwapchainCreateInfo>(XR_TYPE_SWAPCHAIN_CREATE_INFO);
    swapchain_info.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_SAMPLED_BIT |
                                XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
    swapchain_info.format = format->format;
    swapchain_info.sampleCount = 1;
    swapchain_info.width = std::uint32_t(width);
    swapchain_info.height = std::uint32_t(height);
    swapchain_info.faceCount = 1;
    swapchain_info.arraySize = 1;
    swapchain_info.mipCount = 1;
    if (!TELESPHERE_CHECK_XR(xrCreateSwapchain(impl->session, &swapchain_info, &eye.swapchain), error))
      return nullptr;
    std::uint32_t image_count = 0;
    if (!TELESPHERE_CHECK_XR(xrEnumerateSwapchainImages(eye.swapchain, 0, &image_count, nullptr), error))
      return nullptr;
    eye.images.assign(image_count, xrStruct<XrSwapchainImageOpenGLKHR>(XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR));
    if (!TELESPHERE_CHECK_XR(xrEnumerateSwapchainImages(eye.swapchain, image_count, &image_count, reinterpret_cast<XrSwapchainImageBaseHeader*>(eye.images.data())), error))
      return nullptr;
    eye.framebuffer = gl::createFramebuffer();
    eye.depth = gl::createRenderbuffer();
    glNamedRenderbufferStorage(eye.depth.id(), GL_DEPTH_COMPONENT32F, width, height);
    if (!format->srgb) {
      eye.staging = gl::createTexture(GL_TEXTURE_2D);
      glTextureStorage2D(eye.staging.id(), 1, GL_SRGB8_ALPHA8, width, height);
      eye.staging_framebuffer = gl::createFramebuffer();
      glNamedFramebufferTexture(eye.staging_framebuffer.id(), GL_COLOR_ATTACHMENT0, eye.staging.id(), 0);
      glNamedFramebufferRenderbuffer(eye.staging_framebuffer.id(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, eye.depth.id());
    } else {
      glNamedFramebufferRenderbuffer(eye.framebuffer.id(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, eye.depth.id());
    }
  }

  std::unique_ptr<OpenXrSession> session(new OpenXrSession(std::move(impl)));
  session->runtime_name_ = std::string(instance_props.runtimeName) + " " +
                           std::to_string(XR_VERSION_MAJOR(instance_props.runtimeVersion)) + "." +
                           std::to_string(XR_VERSION_MINOR(instance_props.runtimeVersion)) + "." +
                           std::to_string(XR_VERSION_PATCH(instance_props.runtimeVersion));
  session->system_name_ = system_props.systemName;
  session->binding_ = use_egl ? XR_MNDX_EGL_ENABLE_EXTENSION_NAME : "XR_KHR_opengl_enable (Xlib/GLX)";
  session->space_name_ = has_stage ? "STAGE" : "LOCAL";
  session->format_ = *format;
  session->width_ = width;
  session->height_ = height;
  setFailure(out_failure, OpenXrFailure::kNone);
  return session;
}

bool OpenXrSession::handleResult(bool ok, int result) {
  if (!ok && openXrIsLoss(XrResult(result))) machine_.onLost();
  return ok;
}

bool OpenXrSession::apply(SessionAction action, std::string* out_error) {
  XrResult result = XR_SUCCESS;
  switch (action) {
    case SessionAction::kBeginSession: {
      auto begin = xrStruct<XrSessionBeginInfo>(XR_TYPE_SESSION_BEGIN_INFO);
      begin.primaryViewConfigurationType = kOpenXrViewConfig;
      const bool ok = TELESPHERE_CHECK_XR_RESULT(xrBeginSession(impl_->session, &begin), out_error, &result);
      if (ok) machine_.onSessionBegun(); else machine_.onSessionBeginFailed();
      return handleResult(ok, result);
    }
    case SessionAction::kEndSession: {
      const bool ok = TELESPHERE_CHECK_XR_RESULT(xrEndSession(impl_->session), out_error, &result);
      machine_.onSessionEnded();
      return handleResult(ok, result);
    }
    case SessionAction::kRequestExit:
      return handleResult(TELESPHERE_CHECK_XR_RESULT(xrRequestExitSession(impl_->session), out_error, &result), result);
    case SessionAction::kNone:
    case SessionAction::kDestroySession:
    case SessionAction::kRecreateSession:
      break;  // the owner destroys this object
  }
  return true;
}

bool OpenXrSession::pollEvents(std::string* out_error) {
  for (;;) {
    auto event = xrStruct<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
    XrResult result = XR_SUCCESS;
    if (!TELESPHERE_CHECK_XR_RESULT(xrPollEvent(impl_->instance, &event), out_error, &result))
      return handleResult(false, result);
    if (result == XR_EVENT_UNAVAILABLE) return true;
    switch (event.type) {
      case XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED: {
        const auto& changed = reinterpret_cast<const XrEventDataSessionStateChanged&>(event);
        if (!apply(machine_.onStateChanged(sessionStateFromXr(int(changed.state))), out_error))
          return false;
        break;
      }
      case XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING:
        machine_.onLost();
        break;
      default:
        break;  // reference space changes, interaction profiles, events lost: nothing to do
    }
  }
}

std::int64_t OpenXrSession::steadyNsFromXrTime(std::int64_t xr_time) const {
  if (!impl_->time_to_timespec) return 0;
  timespec ts{};
  if (XR_FAILED(impl_->time_to_timespec(impl_->instance, XrTime(xr_time), &ts))) return 0;
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

bool OpenXrSession::requestExit(std::string* out_error) {
  return apply(machine_.requestExit(), out_error);
}

bool OpenXrSession::frame(const OpenXrRenderEye& render, const OpenXrReadEye& read_back,
                          OpenXrFrameResult* out_result, std::string* out_error) {
  OpenXrFrameResult local;
  OpenXrFrameResult& r = out_result ? *out_result : local;
  r = {};
  if (!machine_.shouldSyncFrames()) return true;
  XrResult result = XR_SUCCESS;

  auto frame_state = xrStruct<XrFrameState>(XR_TYPE_FRAME_STATE);
  auto wait_info = xrStruct<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
  if (!TELESPHERE_CHECK_XR_RESULT(xrWaitFrame(impl_->session, &wait_info, &frame_state), out_error, &result))
    return handleResult(false, result);
  auto begin_info = xrStruct<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
  if (!TELESPHERE_CHECK_XR_RESULT(xrBeginFrame(impl_->session, &begin_info), out_error, &result))
    return handleResult(false, result);
  r.waited = true;
  r.predicted_display_time_ns = frame_state.predictedDisplayTime;
  r.predicted_display_period_ns = frame_state.predictedDisplayPeriod;
  r.predicted_display_steady_ns = steadyNsFromXrTime(frame_state.predictedDisplayTime);
  if (r.predicted_display_steady_ns == 0) {  // no conversion: one display period from now
    r.predicted_display_steady_ns =
        link::linkNowNs() +
        frame_state.predictedDisplayPeriod;
  }
  const std::uint64_t frame_index = frame_index_++;

  std::array<XrCompositionLayerProjectionView, 2> layer_views{};
  bool rendered = false;
  if (machine_.state() == SessionState::kFocused) {  // input only reaches the focused app
    XrActiveActionSet active{impl_->action_set, XR_NULL_PATH};
    auto sync = xrStruct<XrActionsSyncInfo>(XR_TYPE_ACTIONS_SYNC_INFO);
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    if (!TELESPHERE_CHECK_XR_RESULT(xrSyncActions(impl_->session, &sync), out_error, &result))
      return handleResult(false, result);
    auto get = xrStruct<XrActionStateGetInfo>(XR_TYPE_ACTION_STATE_GET_INFO);
    get.action = impl_->capture_nominal;
    auto state = xrStruct<XrActionStateBoolean>(XR_TYPE_ACTION_STATE_BOOLEAN);
    if (!TELESPHERE_CHECK_XR_RESULT(xrGetActionStateBoolean(impl_->session, &get, &state), out_error, &result))
      return handleResult(false, result);
    r.capture_nominal_pressed = state.isActive && state.changedSinceLastSync && state.currentState;
  }
  if (frame_state.shouldRender && machine_.shouldRender()) {
    auto locate_info = xrStruct<XrViewLocateInfo>(XR_TYPE_VIEW_LOCATE_INFO);
    locate_info.viewConfigurationType = kOpenXrViewConfig;
    locate_info.displayTime = frame_state.predictedDisplayTime;
    locate_info.space = impl_->space;
    auto view_state = xrStruct<XrViewState>(XR_TYPE_VIEW_STATE);
    std::array<XrView, 2> views{};
    for (auto& v : views) v.type = XR_TYPE_VIEW;
    std::uint32_t view_count = 0;
    if (!TELESPHERE_CHECK_XR_RESULT(xrLocateViews(impl_->session, &locate_info, &view_state, 2, &view_count, views.data()), out_error, &result))
      return handleResult(false, result);
    r.views_valid = view_count == 2 && viewPoseValid(view_state.viewStateFlags);
    if (r.views_valid) {
      rendered = true;
      for (int i = 0; i < 2 && rendered; ++i) {
        Impl::Eye& eye = impl_->eyes[std::size_t(i)];
        std::uint32_t index = 0;
        auto acquire = xrStruct<XrSwapchainImageAcquireInfo>(XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO);
        if (!TELESPHERE_CHECK_XR_RESULT(xrAcquireSwapchainImage(eye.swapchain, &acquire, &index), out_error, &result))
          return handleResult(false, result);
        auto wait = xrStruct<XrSwapchainImageWaitInfo>(XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
        wait.timeout = XR_INFINITE_DURATION;
        if (!TELESPHERE_CHECK_XR_RESULT(xrWaitSwapchainImage(eye.swapchain, &wait), out_error, &result))
          return handleResult(false, result);
        const GLuint texture = eye.images[index].image;
        glNamedFramebufferTexture(eye.framebuffer.id(), GL_COLOR_ATTACHMENT0, texture, 0);

        OpenXrEye e;
        e.eye = i;
        e.frame_index = frame_index;
        e.predicted_display_time_ns = frame_state.predictedDisplayTime;
        e.predicted_display_steady_ns = r.predicted_display_steady_ns;
        e.T_vr_eye = isometryFromXrPose(views[std::size_t(i)].pose);
        e.T_vr_hmd = midpointPose(isometryFromXrPose(views[0].pose), isometryFromXrPose(views[1].pose));
        e.fov = fovFromXr(views[std::size_t(i)].fov);
        e.width = width_;
        e.height = height_;
        e.srgb_swapchain = format_.srgb;
        // sRGB swapchain: the renderer's sRGB-encoded values are stored as they are.
        glDisable(GL_FRAMEBUFFER_SRGB);
        if (format_.srgb) {
          e.framebuffer = eye.framebuffer.id();
          rendered = render(e);
        } else {
          e.framebuffer = eye.staging_framebuffer.id();
          rendered = render(e);
          // Linear swapchain: decode sRGB → linear on the way (GL 4.4+ blit with FRAMEBUFFER_SRGB).
          glEnable(GL_FRAMEBUFFER_SRGB);
          glBlitNamedFramebuffer(eye.staging_framebuffer.id(), eye.framebuffer.id(), 0, 0, width_,
                                 height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
          glDisable(GL_FRAMEBUFFER_SRGB);
        }
        if (rendered && read_back) {
          e.framebuffer = eye.framebuffer.id();
          read_back(e);
        }
        glNamedFramebufferTexture(eye.framebuffer.id(), GL_COLOR_ATTACHMENT0, 0, 0);
        auto release = xrStruct<XrSwapchainImageReleaseInfo>(XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO);
        if (!TELESPHERE_CHECK_XR_RESULT(xrReleaseSwapchainImage(eye.swapchain, &release), out_error, &result))
          return handleResult(false, result);

        XrCompositionLayerProjectionView& lv = layer_views[std::size_t(i)];
        lv.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW;
        lv.pose = views[std::size_t(i)].pose;
        lv.fov = views[std::size_t(i)].fov;
        lv.subImage.swapchain = eye.swapchain;
        lv.subImage.imageRect.extent = {width_, height_};
      }
    }
  }

  auto layer = xrStruct<XrCompositionLayerProjection>(XR_TYPE_COMPOSITION_LAYER_PROJECTION);
  layer.space = impl_->space;
  layer.viewCount = 2;
  layer.views = layer_views.data();
  const XrCompositionLayerBaseHeader* layers[] = {reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer)};
  auto end_info = xrStruct<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  end_info.displayTime = frame_state.predictedDisplayTime;
  end_info.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  end_info.layerCount = rendered ? 1 : 0;
  end_info.layers = rendered ? layers : nullptr;
  if (!TELESPHERE_CHECK_XR_RESULT(xrEndFrame(impl_->session, &end_info), out_error, &result))
    return handleResult(false, result);
  r.submitted = rendered;
  return true;
}

}  // namespace telesphere::xr::openxr
