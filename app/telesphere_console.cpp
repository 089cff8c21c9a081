// SPDX-License-Identifier: MIT
/// @brief telesphere-console: the supervisor's console (DESIGN.md §1, console/README.md). Parses
///        the options, opens the window on a session to the robot, and for headless use runs a
///        fixed time and writes the main window's picture.
///
///   telesphere-console --keys DIR|--insecure [--host H] [--port P] [--study-db FILE [--study STUDY.json]]
///   telesphere-console --screenshot FILE --duration S   (no display needed: offscreen)
///   telesphere-console study report|import …            (headless; app/console_study_command.h)
///   telesphere-console calibrate intrinsics|handeye --auto …  (headless; app/console_calibrate_command.h)
///   telesphere-console status|control --robot URL …     (headless; app/console_robot_commands.h)
///
/// Exit codes: 0 ok; 1 bad arguments; 2 no display to open a window on; 3 the robot never
/// answered within --duration; 4 the screenshot could not be written.
#include <CLI/CLI.hpp>
#include <QApplication>
#include <QDir>
#include <QFileInfo>
#include <QTimer>
#include <cstdlib>
#include <iostream>

#include "app/console_calibrate_command.h"
#include "app/console_robot_commands.h"
#include "app/console_study_command.h"
#include "app/link_security_options.h"
#include "console/widgets/console_session.h"
#include "console/widgets/console_window.h"
#include "console/widgets/study_panel.h"

int main(int argc, char** argv) {
  CLI::App cli{"telesphere-console: the supervisor's view of the robot and the XR app"};
  std::string host = "127.0.0.1";
  int port = 5760;
  std::string screenshot;
  double duration_s = 0.0;
  std::string study_file, study_db;
  cli.add_option("--host", host, "robot (telesphere-robot) address")->capture_default_str();
  cli.add_option("--port", port, "robot link base port")->capture_default_str()->check(CLI::Range(1024, 65532));
  cli.add_option("--screenshot", screenshot, "after --duration, write the main window as PNG and exit");
  cli.add_option("--duration", duration_s, "seconds to run, then exit (0: until the window closes)")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  cli.add_option("--study-db", study_db, "open this study database (created if new) in the Study panel");
  cli.add_option("--study", study_file, "the study file (JSON) for --study-db (default: the paper's study)")
      ->check(CLI::ExistingFile);
  telesphere::app::LinkSecurityOptions security;
  telesphere::app::addLinkSecurityOptions(cli, security, "a supervisor (or viewer) key pair and the robot's .pub");
  telesphere::app::StudyCommandOptions study_options;
  CLI::App* study = telesphere::app::addStudyCommand(cli, study_options);
  telesphere::app::CalibrateCommandOptions calibrate_options;
  CLI::App* calibrate = telesphere::app::addCalibrateCommand(cli, calibrate_options);
  telesphere::app::RobotCommandOptions robot_options;
  CLI::App* status = telesphere::app::addStatusCommand(cli, robot_options);
  CLI::App* control = telesphere::app::addControlCommand(cli, robot_options);
  CLI11_PARSE(cli, argc, argv);
  if (status->parsed()) return telesphere::app::runStatusCommand(robot_options);
  if (control->parsed()) return telesphere::app::runControlCommand(robot_options);
  if (calibrate->parsed()) return telesphere::app::runCalibrateCommand(*calibrate, calibrate_options);
  if (study->parsed()) return telesphere::app::runStudyCommand(*study, study_options, argc, argv);
  if (!screenshot.empty() && duration_s <= 0) {
    std::cerr << "telesphere-console: --screenshot needs --duration S (how long to run first)\n";
    return 1;
  }
  std::string error;
  auto credentials = telesphere::app::linkCredentialsFrom(
      security, {telesphere::link::trust::LinkRole::kSupervisor, telesphere::link::trust::LinkRole::kViewer}, &error);
  if (!credentials) {
    std::cerr << "telesphere-console: " << error << '\n';
    return 1;
  }
  const telesphere::app::InsecureLinkWarning insecure_warning(security.insecure, "telesphere-console");
  const bool headless = !screenshot.empty();
  if (headless && !std::getenv("QT_QPA_PLATFORM")) setenv("QT_QPA_PLATFORM", "offscreen", 1);
  if (!headless && !std::getenv("QT_QPA_PLATFORM") && !std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY")) {
    std::cerr << "telesphere-console: no display (DISPLAY is not set): run it on a desktop, or headless with "
                 "--screenshot FILE --duration S\n";
    return 2;
  }

  QApplication app(argc, argv);
  QApplication::setOrganizationName("telesphere");
  QApplication::setApplicationName("console");

  telesphere::console::ConsoleSessionOptions options;
  options.endpoints.host = host;
  options.endpoints.base_port = port;
  options.endpoints.credentials = std::move(*credentials);
  telesphere::console::ConsoleSession session(options);
  telesphere::console::ConsoleWindow window(session);
  window.show();
  if (!study_db.empty() && !window.studyPanel()->openStudy(QString::fromStdString(study_file),
                                                           QString::fromStdString(study_db))) {
    std::cerr << "telesphere-console: cannot open the study: "
              << window.studyPanel()->statusText().toStdString() << '\n';
    return 1;
  }

  int code = 0;
  if (duration_s > 0) {
    QTimer::singleShot(int(duration_s * 1000.0), &app, [&] {
      if (!session.everHeardRobot()) {
        std::cerr << "telesphere-console: the robot never answered at " << session.endpoint().toStdString()
                  << " within " << duration_s << " s (is telesphere-robot running?)\n";
        code = 3;
      }
      if (!screenshot.empty()) {
        window.redraw(true);
        const QFileInfo info(QString::fromStdString(screenshot));
        QDir().mkpath(info.absolutePath());
        if (!window.grab().save(info.absoluteFilePath(), "PNG")) {
          std::cerr << "telesphere-console: cannot write " << screenshot << '\n';
          code = 4;
        } else {
          std::cerr << "telesphere-console: wrote " << screenshot << '\n';
        }
      }
      app.quit();
    });
  }
  const int rc = app.exec();
  return code != 0 ? code : rc;
}
