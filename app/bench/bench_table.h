// SPDX-License-Identifier: MIT
/// @brief A plain-text table for benchmark output: columns sized to their widest cell, numbers
///        right-aligned. Markdown-compatible, so it can be pasted into the docs as printed.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace telesphere::bench {

class Table {
 public:
  explicit Table(std::vector<std::string> header) : header_(std::move(header)) {}
  void addRow(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  void print(std::ostream& out) const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

/// A number with a fixed count of significant digits (%.{digits}g).
std::string formatNumber(double value, int digits = 3);

/// The q-quantile (0…1) of `values`: the sorted element at round(q·(n − 1)) (q = 0.5: the upper
/// median); 0 for no values.
double quantile(std::vector<double> values, double q);

}  // namespace telesphere::bench
