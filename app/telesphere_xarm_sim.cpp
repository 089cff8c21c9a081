// SPDX-License-Identifier: MIT
/// @brief telesphere-xarm-sim: a simulated xArm 6 controller speaking the real protocol
///        (robot/arm/xarm/controller_simulator.h), so that a lab can rehearse `telesphere-robot --arm
///        xarm` and its faults without the arm:
///          telesphere-xarm-sim --command-port 5020 &
///          telesphere-robot --arm xarm --arm-address 127.0.0.1 --arm-command-port 5020
///        Faults are typed on stdin, one per line: estop, release, collide, mute-reports,
///        unmute-reports, mute-replies, unmute-replies, drop, ignore-payload. A status line every --status-period s.
///        Exit codes: 0 ok, 1 bad arguments, 2 the ports could not be opened.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>

#include "robot/arm/xarm/controller_simulator.h"
#include "robot/arm/xarm/xarm_codes.h"
#include "robot/arm/xarm/xarm_protocol.h"

namespace {

std::atomic<bool> g_stop{false};
extern "C" void onSignal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  using namespace telesphere;
  CLI::App app{"telesphere-xarm-sim: a simulated xArm 6 controller on its real protocol (command and report ports)"};
  xarm::ControllerSimulatorOptions options;
  options.command_port = 5020;  // 502 needs root; the driver takes --arm-command-port
  options.report_port = xarm::kRealtimeReportPort;
  options.normal_report_port = xarm::kNormalReportPort;
  double latency_ms = double(options.arm.command_latency_ns) / 1e6;
  double duration_s = 0, status_period_s = 2.0;
  app.add_option("--address", options.address, "address to listen on")->capture_default_str();
  app.add_option("--command-port", options.command_port, "command port")->capture_default_str()->check(CLI::Range(0, 65535));
  app.add_option("--report-port", options.report_port, "real-time report port")->capture_default_str()->check(CLI::Range(0, 65535));
  app.add_option("--normal-report-port", options.normal_report_port, "normal report port (payload, sensitivities)")
      ->capture_default_str()->check(CLI::Range(0, 65535));
  app.add_option("--latency-ms", latency_ms, "command-to-motion dead time of the simulated arm, ms")
      ->capture_default_str()->check(CLI::Range(0.0, 2000.0));
  app.add_option("--duration", duration_s, "stop after this many seconds (0: until SIGINT)")->capture_default_str();
  app.add_option("--status-period", status_period_s, "seconds between status lines (0: none)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  options.arm.command_latency_ns = std::llround(latency_ms * 1e6);

  std::string error;
  auto sim = xarm::ControllerSimulator::start(options, &error);
  if (!sim) {
    std::cerr << "telesphere-xarm-sim: " << error << '\n';
    return 2;
  }
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::cerr << "telesphere-xarm-sim: command port " << sim->commandPort() << ", report port " << sim->reportPort()
            << ", normal report port " << sim->normalReportPort() << " on " << options.address << "; faults on stdin: estop, release, collide, mute-reports, "
            << "unmute-reports, mute-replies, unmute-replies, drop, ignore-payload\n";
  std::thread faults([&] {
    std::string line;
    while (!g_stop && std::getline(std::cin, line)) {
      if (line == "estop") sim->pressEmergencyStop();
      else if (line == "release") sim->releaseEmergencyStop();
      else if (line == "collide") sim->collide();
      else if (line == "mute-reports") sim->setReportsPaused(true);
      else if (line == "unmute-reports") sim->setReportsPaused(false);
      else if (line == "mute-replies") sim->setRepliesPaused(true);
      else if (line == "unmute-replies") sim->setRepliesPaused(false);
      else if (line == "drop") sim->dropConnections();
      else if (line == "ignore-payload") sim->setPayloadWritesIgnored(true);
      else if (!line.empty()) std::cerr << "telesphere-xarm-sim: unknown fault '" << line << "'\n";
    }
  });
  faults.detach();  // blocked in getline until stdin closes; the process ends without it

  const auto t0 = std::chrono::steady_clock::now();
  auto next_status = t0;
  while (!g_stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto now = std::chrono::steady_clock::now();
    if (duration_s > 0 && now - t0 >= std::chrono::duration<double>(duration_s)) break;
    if (status_period_s > 0 && now >= next_status) {
      const auto s = sim->snapshot();
      std::fprintf(stderr,
                   "telesphere-xarm-sim: %s, %s mode, %s, motors %s; J1..J6 %.3f %.3f %.3f %.3f %.3f %.3f rad; "
                   "%llu servo targets, %llu reports; clients %d command, %d report\n",
                   xarm::stateName(s.state).c_str(), xarm::modeName(s.mode).c_str(),
                   xarm::controllerErrorText(s.error).c_str(), s.enabled ? "on" : "off", s.q_true[0], s.q_true[1],
                   s.q_true[2], s.q_true[3], s.q_true[4], s.q_true[5],
                   static_cast<unsigned long long>(s.servo_commands), static_cast<unsigned long long>(s.reports_sent),
                   s.command_clients, s.report_clients);
      next_status = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(status_period_s));
    }
  }
  return 0;
}
