// SPDX-License-Identifier: MIT
/// @brief `telesphere-console status|control` (see console_robot_commands.h).
#include "app/console_robot_commands.h"

#include <google/protobuf/util/json_util.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <thread>

#include "app/console_calibrate_command.h"
#include "robot/link/link_client.h"
#include "robot/link/link_trust_text.h"
#include "robot/link/proto_enums.h"
#include "robot/link/visual_mode.h"

namespace telesphere::app {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kNoAnswer = 3, kRefused = 5;

std::chrono::milliseconds waitOf(const RobotCommandOptions& o) {
  return std::chrono::milliseconds(static_cast<long>(o.wait_s * 1000.0));
}

/// The newest state and health, once both have arrived (nothing when not within `wait`, or as
/// soon as the robot refused this program's keys: waiting longer would not change that).
bool awaitRobot(link::LinkClient& client, std::chrono::milliseconds wait) {
  const auto deadline = Clock::now() + wait;
  while (Clock::now() < deadline) {
    if (client.latestRobotState() && client.latestRobotHealth()) return true;
    if (client.activity().refusal_settled) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

std::string json(const google::protobuf::Message& m) {
  std::string out;
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  (void)google::protobuf::util::MessageToJsonString(m, &out, options);
  return out;
}

std::string holdText(const link::proto::HeadHold& h, std::int64_t now_ns) {
  if (h.lease() == 0) return h.last_release().empty() ? "none" : "none (last: " + h.last_release() + ")";
  char buf[160];
  std::snprintf(buf, sizeof buf, " for %.0f s (lease %llu", double(now_ns - h.since_ns()) * 1e-9,
                static_cast<unsigned long long>(h.lease()));
  std::string text = "held by " + h.holder() + buf;
  if (h.pattern_amplitude_deg() > 0) text += ", pattern ±" + std::to_string(int(std::lround(h.pattern_amplitude_deg()))) + "°";
  return text + ")";
}

/// Why a client heard nothing: the robot refused its key, or it is not there.
std::string whyNoAnswer(const link::LinkClient& client) {
  const auto activity = client.activity();
  if (!activity.refused_reason.empty()) return activity.refused_reason;
  return "is telesphere-robot running?";
}

void printStatus(const std::string& robot, const link::proto::RobotState& s, const link::proto::RobotHealth& h) {
  const auto& st = h.settings();
  const auto mode = link::fromProto(st.visual_mode());
  std::printf("robot      %s (instance %016llx), up %.0f s\n", robot.c_str(),
              static_cast<unsigned long long>(h.instance()), double(h.t_ns() - h.started_ns()) * 1e-9);
  std::printf("arm        %s%s%s (%s)\n", s.arm_ok() ? "ok" : "NOT OK: ", s.arm_ok() ? "" : s.fault().c_str(), "",
              h.arm().c_str());
  std::printf("head       %s, nominal %s, head target age %s\n",
              s.nominal_step() == link::proto::NOMINAL_STEP_FOLLOWING ? "following" : "nominal-pose step",
              s.nominal_set() ? "set" : "not set",
              h.head_target_age_ns() < 0 ? "- (none yet)"
                                         : (std::to_string(h.head_target_age_ns() / 1'000'000) + " ms").c_str());
  std::printf("hold       %s\n", holdText(s.hold(), s.t_ns()).c_str());
  const auto& rec = h.recording();
  std::printf("recording  %s\n", !rec.available() ? "off (no --record-dir)"
                                 : rec.active()   ? ("● " + rec.file() + ", " + std::to_string(rec.bytes() / 1'000'000) +
                                                   " MB, " + std::to_string(rec.dropped()) + " dropped").c_str()
                                                  : "not recording");
  const auto proxy = link::fromProto(st.depth_proxy());
  std::printf("settings   mode %s, radius %g m, scene proxy %s, JPEG quality %d, filter %s, jump %g cm / %g°\n",
              mode ? std::string(link::visualModeName(*mode)).c_str() : "?", st.sphere_radius(),
              proxy ? std::string(link::depthProxyName(*proxy)).c_str()
                    : st.depth_proxy() == link::proto::DEPTH_PROXY_UNSPECIFIED ? "none chosen (the XR app's own)"
                                                                             : "?",
              st.jpeg_quality(),
              std::isinf(st.filter_cutoff_hz()) ? "off" : (std::to_string(int(std::lround(st.filter_cutoff_hz()))) + " Hz").c_str(),
              st.jump_position_m() * 100.0, st.jump_angle_deg());
  if (const auto codec = link::fromProto(st.video_codec()); codec && *codec != link::VideoCodec::kMjpeg)
    std::printf("video      %s (%s), %g Mbit/s\n", link::videoCodecName(*codec),
                st.video_encoder().empty() ? "opening" : st.video_encoder().c_str(), st.video_mbit());
  else
    std::printf("video      %s\n", codec ? "mjpeg" : "unknown codec (a newer robot?)");
  std::printf("calibration generation %llu\n", static_cast<unsigned long long>(s.calibration_generation()));
  std::printf("link       %s\n", link::trustSummary(h.trust()).c_str());
  if (const std::string refused = link::refusalSummary(h.trust()); !refused.empty())
    std::printf("refused    %s\n", refused.c_str());
  for (const auto& c : h.cameras())
    std::printf("camera     %s: %.1f fps, %llu frames%s%s\n", c.name().c_str(), c.fps(),
                static_cast<unsigned long long>(c.frames()), c.last_error().empty() ? "" : ", last error: ",
                c.last_error().c_str());
}

std::optional<link::proto::ControlRequest> requestOf(const std::vector<std::string>& a, std::string* error) {
  link::proto::ControlRequest r;
  const std::string verb = a.empty() ? "" : a[0];
  const auto arguments = [&](std::size_t n) {
    if (a.size() == n + 1) return true;
    *error = "'" + verb + "' takes " + std::to_string(n) + " argument" + (n == 1 ? "" : "s");
    return false;
  };
  if (verb == "stop") {
    if (!arguments(0)) return std::nullopt;
    r.set_arm_stop(true);
  } else if (verb == "clear-fault") {
    if (!arguments(0)) return std::nullopt;
    r.set_clear_fault(true);
  } else if (verb == "mode") {
    if (!arguments(1)) return std::nullopt;
    const auto mode = link::parseVisualMode(a[1]);
    if (!mode) {
      *error = "mode '" + a[1] + "': full6d, orientation3d or fixed";
      return std::nullopt;
    }
    r.set_set_visual_mode(link::toProto(*mode));
  } else if (verb == "radius") {
    if (!arguments(1)) return std::nullopt;
    char* end = nullptr;
    const double radius = std::strtod(a[1].c_str(), &end);
    if (end == a[1].c_str() || *end != '\0') {
      *error = "radius '" + a[1] + "' is not a number (metres)";
      return std::nullopt;
    }
    r.set_set_sphere_radius(radius);  // the robot checks the range and says it
  } else if (verb == "depth-proxy") {
    if (!arguments(1)) return std::nullopt;
    const auto proxy = link::parseDepthProxy(a[1]);
    if (!proxy) {
      *error = "depth proxy '" + a[1] + "': fixed, radius or grid";
      return std::nullopt;
    }
    r.set_set_depth_proxy(link::toProto(*proxy));
  } else if (verb == "codec") {
    if (!arguments(1)) return std::nullopt;
    const auto codec = link::parseVideoCodec(a[1]);
    if (!codec) {
      *error = "codec '" + a[1] + "': mjpeg, h264 or hevc";
      return std::nullopt;
    }
    r.set_set_video_codec(link::toProto(*codec));  // the robot says when it cannot (its media path)
  } else if (verb == "release-hold") {
    if (!arguments(0)) return std::nullopt;
    r.mutable_calibration_head_pose()->set_release(true);
    r.mutable_calibration_head_pose()->set_holder("telesphere-console control, pid " + std::to_string(getpid()));
  } else if (verb == "record" && a.size() >= 2 && a[1] == "start") {
    if (a.size() != 3) {
      *error = "'record start' takes the recording's NAME";
      return std::nullopt;
    }
    r.mutable_recording()->set_start(true);
    r.mutable_recording()->set_name(a[2]);
  } else if (verb == "record" && a.size() == 2 && a[1] == "stop") {
    r.mutable_recording()->set_start(false);
  } else if (verb == "seat") {
    // The operator seat (DESIGN.md §10): "seat NAME" seats that operator key, "seat free" frees it.
    if (!arguments(1)) return std::nullopt;
    r.mutable_hand_over_operator_seat()->set_name(a[1] == "free" ? "" : a[1]);
  } else {
    *error = "unknown action '" + verb +
             "': stop, clear-fault, mode M, radius R, depth-proxy P, codec C, release-hold, record start NAME, record stop, seat NAME|free";
    return std::nullopt;
  }
  return r;
}

/// After a pending clear-fault: the arm's outcome as the robot states show it (states published
/// before the request may still arrive, so the first 100 ms are not taken as the outcome).
int awaitClearOutcome(link::LinkClient& client, std::chrono::milliseconds wait) {
  const auto start = Clock::now();
  const auto deadline = start + wait;
  std::string last = "no robot state";
  while (Clock::now() < deadline) {
    if (const auto s = client.latestRobotState(); s && Clock::now() - start >= std::chrono::milliseconds(100)) {
      if (s->arm_ok()) {
        std::printf("arm ok\n");
        return 0;
      }
      last = s->fault();
      if (last.rfind("clearing the fault", 0) != 0) {
        std::printf("not cleared: %s\n", last.c_str());
        return kRefused;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::printf("no outcome within %.0f s: %s\n", std::chrono::duration<double>(wait).count(), last.c_str());
  return kRefused;
}

}  // namespace

CLI::App* addStatusCommand(CLI::App& app, RobotCommandOptions& o) {
  CLI::App* status = app.add_subcommand("status", "the robot's health, arm, hold, recording and settings (headless)");
  status->add_option("--robot", o.robot, "the robot's link, tcp://HOST:PORT")->capture_default_str();
  status->add_flag("--json", o.json, "the robot's state and health as JSON (protobuf field names)");
  status->add_option("--wait", o.wait_s, "seconds to wait for the robot")->capture_default_str()->check(CLI::Range(0.1, 600.0));
  addLinkSecurityOptions(*status, o.security, "a supervisor or viewer key pair and the robot's .pub");
  return status;
}

CLI::App* addControlCommand(CLI::App& app, RobotCommandOptions& o) {
  CLI::App* control = app.add_subcommand(
      "control", "one control request: stop | clear-fault | mode M | radius R | depth-proxy fixed|radius|grid | codec mjpeg|h264|hevc | release-hold | record start NAME | record stop | seat NAME|free");
  control->add_option("--robot", o.robot, "the robot's link, tcp://HOST:PORT")->capture_default_str();
  control->add_option("--wait", o.wait_s, "seconds to wait for the robot's reply (clear-fault: for the arm's outcome)")
      ->capture_default_str()->check(CLI::Range(0.1, 600.0));
  control->add_option("action", o.action, "what to do")->required();
  addLinkSecurityOptions(*control, o.security, "a supervisor key pair (other roles are refused by the robot) and the robot's .pub");
  return control;
}

int runStatusCommand(const RobotCommandOptions& o) {
  link::LinkEndpoints endpoints;
  if (!parseRobotEndpoint(o.robot, &endpoints)) {
    std::cerr << "telesphere-console status: --robot '" << o.robot << "' is not tcp://HOST:PORT\n";
    return 1;
  }
  std::string error;
  auto credentials = linkCredentialsFrom(o.security, {link::trust::LinkRole::kSupervisor, link::trust::LinkRole::kViewer}, &error);
  if (!credentials) {
    std::cerr << "telesphere-console status: " << error << '\n';
    return 1;
  }
  endpoints.credentials = std::move(*credentials);
  const InsecureLinkWarning insecure_warning(o.security.insecure, "telesphere-console status");
  link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false});
  if (!awaitRobot(client, waitOf(o))) {
    if (const auto activity = client.activity(); activity.refusal_settled)
      std::cerr << "telesphere-console status: no answer from the robot at " << o.robot << " ("
                << activity.refused_reason << ")\n";
    else
      std::cerr << "telesphere-console status: the robot did not answer at " << o.robot << " within " << o.wait_s
                << " s (" << whyNoAnswer(client) << ")\n";
    return kNoAnswer;
  }
  const auto state = *client.latestRobotState();
  const auto health = *client.latestRobotHealth();
  if (o.json)
    std::printf("{\"robot\": \"%s\", \"state\": %s, \"health\": %s}\n", o.robot.c_str(), json(state).c_str(),
                json(health).c_str());
  else
    printStatus(o.robot, state, health);
  return 0;
}

int runControlCommand(const RobotCommandOptions& o) {
  link::LinkEndpoints endpoints;
  if (!parseRobotEndpoint(o.robot, &endpoints)) {
    std::cerr << "telesphere-console control: --robot '" << o.robot << "' is not tcp://HOST:PORT\n";
    return 1;
  }
  std::string error;
  const auto request = requestOf(o.action, &error);
  if (!request) {
    std::cerr << "telesphere-console control: " << error << '\n';
    return 1;
  }
  // Any client key: the robot decides what its role may do, and says why not.
  auto credentials = linkCredentialsFrom(
      o.security, {link::trust::LinkRole::kSupervisor, link::trust::LinkRole::kViewer, link::trust::LinkRole::kOperator},
      &error);
  if (!credentials) {
    std::cerr << "telesphere-console control: " << error << '\n';
    return 1;
  }
  endpoints.credentials = std::move(*credentials);
  const InsecureLinkWarning insecure_warning(o.security.insecure, "telesphere-console control");
  link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false});
  const auto reply = client.request(*request, waitOf(o));
  if (!reply) {
    std::cerr << "telesphere-console control: the robot did not answer at " << o.robot << " within " << o.wait_s
              << " s (" << whyNoAnswer(client) << ")\n";
    return kNoAnswer;
  }
  if (!reply->ok()) {
    std::printf("refused: %s\n", reply->error().c_str());
    return kRefused;
  }
  if (reply->pending()) {
    std::printf("under way: waiting for the outcome\n");
    return awaitClearOutcome(client, waitOf(o));
  }
  std::printf("ok%s%s\n", reply->error().empty() ? "" : ": ", reply->error().c_str());
  if (request->has_recording())
    std::printf("recording: %s%s\n", reply->recording().active() ? "● " : "stopped, ", reply->recording().file().c_str());
  return 0;
}

}  // namespace telesphere::app
