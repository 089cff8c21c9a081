// SPDX-License-Identifier: MIT
/// @brief Table printing and the topic registry of telesphere-bench.
#include "app/bench/bench_table.h"

#include <algorithm>
#include <cstdio>

#include "app/bench/bench_topic.h"

namespace telesphere::bench {

std::vector<BenchTopic>& benchTopics() {
  static std::vector<BenchTopic> topics;
  return topics;
}

std::string formatNumber(double value, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, value);
  return buf;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double at = std::clamp(q, 0.0, 1.0) * double(values.size() - 1) + 0.5;
  return values[std::min(values.size() - 1, std::size_t(at))];
}

void Table::print(std::ostream& out) const {
  std::vector<std::size_t> width(header_.size(), 0);
  for (std::size_t c = 0; c < header_.size(); ++c) width[c] = header_[c].size();
  for (const auto& row : rows_)
    for (std::size_t c = 0; c < row.size() && c < width.size(); ++c)
      width[c] = std::max(width[c], row[c].size());
  const auto line = [&](const std::vector<std::string>& cells, bool right_align) {
    out << '|';
    for (std::size_t c = 0; c < width.size(); ++c) {
      const std::string cell = c < cells.size() ? cells[c] : "";
      const std::string pad(width[c] - std::min(width[c], cell.size()), ' ');
      const bool numeric = right_align && c > 0;
      out << ' ' << (numeric ? pad + cell : cell + pad) << " |";
    }
    out << '\n';
  };
  line(header_, false);
  out << '|';
  for (std::size_t c = 0; c < width.size(); ++c)
    out << (c > 0 ? std::string(width[c] + 1, '-') + ":|" : std::string(width[c] + 2, '-') + "|");
  out << '\n';
  for (const auto& row : rows_) line(row, true);
}

}  // namespace telesphere::bench
