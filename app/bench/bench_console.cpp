// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench console`: the console's live plot under load — 12 series at 1 kHz
///        each (10× the densest real telemetry, the 100 Hz head ticks), one redraw per 1/30 s of
///        data, on a real QCustomPlot widget (offscreen): redraw time p50/p99, CPU per second of
///        data, memory over time. The knobs measured both ways: the time window (how much is kept
///        and drawn), the min/max decimation (off: every sample handed to QCustomPlot) and
///        antialiased curves. Data time runs
///        as fast as the machine allows; "keeps up" is data seconds per wall second.
#include <sys/resource.h>
#include <unistd.h>

#include <QApplication>
#include <QElapsedTimer>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>

#include "console/widgets/live_plot.h"
#include "console/telemetry/series_store.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"

namespace telesphere::bench {
namespace {

double residentMb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / 1e6;
}

double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

struct ConsoleBenchCase {
  double window_s;
  bool decimation;
  double data_s;
  bool antialiased = false;
};

struct ConsoleBenchResult {
  double redraw_p50 = 0, redraw_p99 = 0, cpu_ms_per_data_s = 0, keeps_up = 0;
  double rss_growth_mb_per_min = 0, rss_end_mb = 0, store_mb = 0;
  std::size_t points_per_redraw = 0;
};

constexpr int kSeries = 12;
constexpr double kInputHz = 1000.0;
constexpr double kRedrawHz = 30.0;

ConsoleBenchResult runCase(const ConsoleBenchCase& c) {
  console::telemetry::SeriesStore store;
  store.setRetention(c.window_s);
  double now = 0.0;
  console::PlotSpec spec{"bench", "value [units]", "", {}};
  for (int i = 0; i < kSeries; ++i) {
    const std::string name = "bench." + std::to_string(i);
    store.series({name, name, "units"}, 0.5);
    spec.lines.push_back({name, QString::fromStdString(name), QColor::fromHsv(i * 30, 200, 200)});
  }
  console::LivePlot plot(store, [&] { return now; }, spec);
  plot.setWindowSeconds(c.window_s);
  plot.setDecimation(c.decimation);
  plot.setAntialiased(c.antialiased);
  plot.resize(1200, 600);
  plot.show();
  QApplication::processEvents();

  std::vector<console::telemetry::TimeSeries*> series;
  for (int i = 0; i < kSeries; ++i) series.push_back(&store.series({"bench." + std::to_string(i), "", ""}));
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<double> redraw_ms;
  const int samples_per_frame = int(kInputHz / kRedrawHz);  // 33 per series per redraw
  std::int64_t sample = 0;
  const double cpu0 = cpuSeconds();
  QElapsedTimer wall;
  wall.start();
  // RSS once the window has filled and everything warmed up, and at the end.
  const double settle_s = std::min(c.data_s / 2, c.window_s + 15.0);
  double rss_settled = 0, settled_at = 0;
  while (now < c.data_s) {
    for (int k = 0; k < samples_per_frame; ++k, ++sample) {
      const double t = double(sample) / kInputHz;
      for (int i = 0; i < kSeries; ++i) series[std::size_t(i)]->append(t, std::sin(t * (1 + i)) * 10 + i * 5 + noise(rng));
      now = t;
    }
    store.markChanged();
    store.trim(now, now);
    plot.refresh();
    redraw_ms.push_back(plot.lastRefreshMs());
    QApplication::processEvents();
    if (rss_settled == 0 && now >= settle_s) {
      rss_settled = residentMb();
      settled_at = now;
    }
  }
  ConsoleBenchResult r;
  const double cpu = cpuSeconds() - cpu0;
  r.cpu_ms_per_data_s = cpu * 1000.0 / c.data_s;
  r.keeps_up = c.data_s / (double(wall.nsecsElapsed()) * 1e-9);
  r.rss_end_mb = residentMb();
  r.rss_growth_mb_per_min = (r.rss_end_mb - rss_settled) / ((now - settled_at) / 60.0);
  r.store_mb = double(store.bytes()) / 1e6;
  r.points_per_redraw = plot.lastPointCount();
  std::sort(redraw_ms.begin(), redraw_ms.end());
  r.redraw_p50 = redraw_ms[redraw_ms.size() / 2];
  r.redraw_p99 = redraw_ms[std::min(redraw_ms.size() - 1, std::size_t(double(redraw_ms.size()) * 0.99))];
  return r;
}

nlohmann::json runConsoleBench(const BenchContext& ctx) {
  if (!std::getenv("QT_QPA_PLATFORM") && !std::getenv("DISPLAY")) setenv("QT_QPA_PLATFORM", "offscreen", 1);
  static int argc = 1;
  static char name[] = "telesphere-bench";
  static char* argv[] = {name, nullptr};
  QApplication app(argc, argv);

  // The first case is the main figure: the default 30 s window over ten minutes of data.
  const std::vector<ConsoleBenchCase> cases =
      ctx.quick ? std::vector<ConsoleBenchCase>{{30.0, true, 90.0}, {10.0, true, 30.0}, {10.0, false, 10.0},
                                                {10.0, true, 5.0, true}}
                : std::vector<ConsoleBenchCase>{{30.0, true, 600.0},
                                                {10.0, true, 120.0},
                                                {120.0, true, 360.0},
                                                {10.0, false, 60.0},         // every sample drawn
                                                {10.0, true, 30.0, true}};  // antialiased curves
  Table table({"window s", "decimation", "antialiased", "data s", "points/redraw", "redraw ms p50", "p99", "CPU ms per data s",
               "keeps up ×", "store MB", "RSS MB", "RSS growth MB/min"});
  nlohmann::json rows = nlohmann::json::array();
  nlohmann::json main;
  for (const ConsoleBenchCase& c : cases) {
    ctx.out << "console: " << kSeries << " series at " << kInputHz << " Hz, window " << c.window_s << " s, "
            << (c.decimation ? "min/max decimation" : "no decimation") << ", " << c.data_s << " s of data…\n"
            << std::flush;
    const ConsoleBenchResult r = runCase(c);
    table.addRow({formatNumber(c.window_s), c.decimation ? "min/max" : "off", c.antialiased ? "yes" : "no",
                  formatNumber(c.data_s),
                  std::to_string(r.points_per_redraw), formatNumber(r.redraw_p50), formatNumber(r.redraw_p99),
                  formatNumber(r.cpu_ms_per_data_s), formatNumber(r.keeps_up), formatNumber(r.store_mb),
                  formatNumber(r.rss_end_mb), formatNumber(r.rss_growth_mb_per_min, 2)});
    nlohmann::json row = {{"window_s", c.window_s},
                          {"decimation", c.decimation},
                          {"antialiased", c.antialiased},
                          {"data_s", c.data_s},
                          {"points_per_redraw", r.points_per_redraw},
                          {"redraw_ms_p50", r.redraw_p50},
                          {"redraw_ms_p99", r.redraw_p99},
                          {"cpu_ms_per_data_s", r.cpu_ms_per_data_s},
                          {"keeps_up", r.keeps_up},
                          {"store_mb", r.store_mb},
                          {"rss_mb", r.rss_end_mb},
                          {"rss_growth_mb_per_min", r.rss_growth_mb_per_min}};
    rows.push_back(row);
    if (main.is_null()) main = row;
  }
  ctx.out << "\n12 series × 1 kHz, one redraw per 1/30 s of data, 1200×600 QCustomPlot (offscreen):\n";
  table.print(ctx.out);
  ctx.out << "goal: redraw p99 ≤ 5 ms with decimation, RSS flat once the window is full\n";
  return {{"series", kSeries},
          {"input_hz", kInputHz},
          {"redraw_hz", kRedrawHz},
          {"redraw_ms_p50", main["redraw_ms_p50"]},
          {"redraw_ms_p99", main["redraw_ms_p99"]},
          {"cpu_ms_per_data_s", main["cpu_ms_per_data_s"]},
          {"rss_growth_mb_per_min", main["rss_growth_mb_per_min"]},
          {"rows", rows}};
}

TELESPHERE_BENCH_TOPIC(console, BenchTopic{"console",
                                           "console live plot: 12 series at 1 kHz, redraw time, CPU, memory "
                                           "(window and decimation knobs)",
                                           {},
                                           runConsoleBench});

}  // namespace
}  // namespace telesphere::bench
