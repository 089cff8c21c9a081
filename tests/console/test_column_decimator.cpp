// SPDX-License-Identifier: MIT
/// @brief ColumnDecimator against a brute-force reference on seeded random streams with gaps,
///        NaN values, bursts from 1 Hz to 2 kHz: after every step of a live session (appends,
///        trims, out-of-order inserts, clears, scrolling, pausing, zooming, dragging back) the
///        cached output equals the decimation computed from scratch; every pixel column keeps its
///        exact min and max; a redraw looks only at new samples; output size does not grow with
///        the input rate.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "console/telemetry/column_decimator.h"

namespace telesphere::console::telemetry {
namespace {

/// The decimation written out plainly: all samples in columns [k_first, k_last] in order, a new
/// run at every column change, gap (with a NaN break at the midpoint) or NaN sample; each run's
/// first smallest and first largest sample in time order.
std::vector<Sample> reference(const TimeSeries& s, double t0, double t1, double width) {
  const auto column = [&](double t) { return static_cast<long long>(std::floor(t / width)); };
  const long long k_first = column(t0) - 1, k_last = column(t1) + 1;
  std::vector<Sample> out;
  std::vector<Sample> run;
  const auto flush = [&] {
    if (run.empty()) return;
    std::size_t mn = 0, mx = 0;
    for (std::size_t j = 1; j < run.size(); ++j) {
      if (run[j].v < run[mn].v) mn = j;
      if (run[j].v > run[mx].v) mx = j;
    }
    const bool min_first = run[mn].t <= run[mx].t;
    const Sample& a = min_first ? run[mn] : run[mx];
    const Sample& b = min_first ? run[mx] : run[mn];
    out.push_back(a);
    if (a.t != b.t || a.v != b.v) out.push_back(b);
    run.clear();
  };
  long long current = std::numeric_limits<long long>::min();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const long long k = column(s[i].t);
    if (k < k_first || k > k_last) continue;
    if (k != current) {
      flush();
      current = k;
    }
    if (i > 0 && s[i].t - s[i - 1].t > s.maxGap()) {
      flush();
      out.push_back({0.5 * (s[i].t + s[i - 1].t), std::numeric_limits<double>::quiet_NaN()});
    }
    if (std::isnan(s[i].v)) {
      flush();
      out.push_back(s[i]);
      continue;
    }
    run.push_back(s[i]);
  }
  flush();
  return out;
}

void expectSame(const std::vector<Sample>& got, const std::vector<Sample>& want, const std::string& where) {
  ASSERT_EQ(got.size(), want.size()) << where;
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].t, want[i].t) << where << " point " << i;
    if (std::isnan(want[i].v))
      ASSERT_TRUE(std::isnan(got[i].v)) << where << " point " << i;
    else
      ASSERT_EQ(got[i].v, want[i].v) << where << " point " << i;
  }
}

TEST(ColumnDecimator, EdgeCases) {
  TimeSeries s;
  ColumnDecimator d;
  std::vector<Sample> out;
  d.decimate(s, 0, 1, 0.1, out);
  EXPECT_TRUE(out.empty());
  s.append(0.55, 1);
  d.decimate(s, 0, 1, 0.1, out);
  ASSERT_EQ(out.size(), 1u);
  d.decimate(s, 0, 1, 0.0, out);  // no width
  EXPECT_TRUE(out.empty());
  d.decimate(s, 1, 0, 0.1, out);  // backwards
  EXPECT_TRUE(out.empty());
  // Lines reach the edges: the columns on each side of the view are included.
  TimeSeries t(10.0);
  for (int i = 0; i < 10; ++i) t.append(i, i);
  d.decimate(t, 3.5, 5.5, 1.0, out);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(out.front().t, 2.0);
  EXPECT_EQ(out.back().t, 6.0);
}

TEST(ColumnDecimator, LiveSessionMatchesTheReferenceAtEveryStep) {
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    TimeSeries s(0.05);
    ColumnDecimator d;
    std::vector<Sample> out;
    double t = 0, rate = 500;
    double window = 2.0 + 8.0 * u(rng);
    int columns = 50 + int(rng() % 800);
    bool paused = false;
    double pause_t0 = 0, pause_t1 = 0;
    for (int step = 0; step < 600; ++step) {
      // New data: a burst at the current rate, sometimes a silence, a NaN, an old sample.
      if (u(rng) < 0.02) rate = 1.0 + 2000.0 * u(rng);
      const int n = int(rate / 30.0 + u(rng));
      for (int i = 0; i < n; ++i) {
        t += (1.0 / rate) * (0.5 + u(rng));
        s.append(t, u(rng) < 0.01 ? std::numeric_limits<double>::quiet_NaN() : std::sin(t * 5) * 10 + u(rng));
      }
      if (u(rng) < 0.02) t += 0.1 + u(rng);                            // the link was silent
      if (u(rng) < 0.01 && s.size() > 10) s.append(t - 0.5 * u(rng), 3.0);  // a late sample
      if (u(rng) < 0.003) s.clear();
      // The view: live, sometimes paused, zoomed, dragged back, resumed; the window changes.
      if (u(rng) < 0.02) {
        paused = !paused;
        pause_t0 = t - window;
        pause_t1 = t;
      }
      if (paused && u(rng) < 0.1) {
        const double shift = (u(rng) - 0.7) * window;  // mostly back in time
        const double zoom = u(rng) < 0.3 ? 0.5 + u(rng) : 1.0;
        const double mid = 0.5 * (pause_t0 + pause_t1) + shift;
        const double half = 0.5 * (pause_t1 - pause_t0) * zoom;
        pause_t0 = mid - half;
        pause_t1 = mid + half;
      }
      if (u(rng) < 0.01) window = 2.0 + 8.0 * u(rng);
      if (u(rng) < 0.01) columns = 50 + int(rng() % 800);
      const double t1 = paused ? pause_t1 : t;
      const double t0 = paused ? pause_t0 : t - window;
      s.trimBefore(std::min(t0, t - 20.0));
      const double width = (paused ? t1 - t0 : window) / columns;
      d.decimate(s, t0, t1, width, out);
      expectSame(out, reference(s, t0, t1, width), "trial " + std::to_string(trial) + " step " + std::to_string(step));
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

TEST(ColumnDecimator, EveryColumnKeepsItsExtremes) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  TimeSeries s(1.0);
  for (int i = 0; i < 20000; ++i) s.append(i * 1e-3, noise(rng));
  ColumnDecimator d;
  std::vector<Sample> out;
  const double width = 10.0 / 700;
  d.decimate(s, 5.0, 15.0, width, out);
  std::map<long long, std::pair<double, double>> want, got;
  const auto add = [&](std::map<long long, std::pair<double, double>>& m, const Sample& p) {
    const long long k = static_cast<long long>(std::floor(p.t / width));
    auto [it, fresh] = m.emplace(k, std::pair{p.v, p.v});
    if (!fresh) it->second = {std::min(it->second.first, p.v), std::max(it->second.second, p.v)};
  };
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s[i].t >= 5.0 && s[i].t < 15.0 - width) add(want, s[i]);
  for (const Sample& p : out) add(got, p);
  for (const auto& [k, range] : want) {
    ASSERT_TRUE(got.count(k)) << k;
    EXPECT_EQ(got[k], range) << k;
  }
}

TEST(ColumnDecimator, ScrollingLooksOnlyAtNewSamplesAndOutputDoesNotGrowWithTheRate) {
  for (const double rate : {100.0, 1000.0, 10000.0}) {
    TimeSeries s(1.0);
    ColumnDecimator d;
    std::vector<Sample> out;
    const double window = 30.0;
    const int columns = 1000;
    double t = 0;
    std::int64_t n = 0;
    std::size_t scanned_max = 0;
    for (int frame = 0; frame < 60 * 30; ++frame) {
      const double until = (frame + 1) / 30.0;
      for (; double(n) / rate < until; ++n) s.append(double(n) / rate, std::sin(double(n) * 0.01));
      t = until;
      s.trimBefore(t - window - 1.0);
      d.decimate(s, t - window, t, window / columns, out);
      if (frame > 30) scanned_max = std::max(scanned_max, d.lastSamplesScanned());
      EXPECT_LE(out.size(), 2u * (columns + 3)) << rate;
    }
    // New samples (rate / 30) plus the open column's (rate · width), never the whole window.
    EXPECT_LE(scanned_max, std::size_t(rate / 30.0 + rate * window / columns + 4)) << rate;
    EXPECT_LE(d.cachedColumns(), std::size_t(columns + 4));
  }
}

}  // namespace
}  // namespace telesphere::console::telemetry
