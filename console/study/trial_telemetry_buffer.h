// SPDX-License-Identifier: MIT
/// @brief A running trial's telemetry on its way into the store: the link's envelopes kept as
///        they arrive during the trial and committed with it every flush period and when it ends
///        (TrialWorkflow::setBeforeTrialEnds). Qt-free; the Study panel feeds it from the
///        session's telemetry tap and flushes it on its timer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "console/study/study_store.h"

namespace telesphere::console::study {

class TrialTelemetryBuffer {
 public:
  /// Empties the buffer; what arrives from now on belongs to `trial_id` (steady time now_ns).
  void start(std::int64_t trial_id, std::int64_t now_ns);
  void add(TelemetryBatch batch) { batches_.push_back(std::move(batch)); }
  /// At least `period_ns` since the start or the last flush that stored something.
  bool due(std::int64_t now_ns, std::int64_t period_ns) const { return now_ns - last_flush_ns_ >= period_ns; }
  /// Commits the buffered batches with their trial and empties the buffer (also when the store
  /// refused them: false with its reason in *why). True with nothing to store.
  bool flush(StudyStore& store, std::int64_t now_ns, std::string* why);

 private:
  std::vector<TelemetryBatch> batches_;
  std::int64_t trial_id_ = 0;  ///< the trial the buffered telemetry belongs to (0: none yet)
  std::int64_t last_flush_ns_ = 0;
};

}  // namespace telesphere::console::study
