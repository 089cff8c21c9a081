// SPDX-License-Identifier: MIT
/// @brief TrialTelemetryBuffer (see trial_telemetry_buffer.h).
#include "console/study/trial_telemetry_buffer.h"

namespace telesphere::console::study {

void TrialTelemetryBuffer::start(std::int64_t trial_id, std::int64_t now_ns) {
  batches_.clear();
  trial_id_ = trial_id;
  last_flush_ns_ = now_ns;
}

bool TrialTelemetryBuffer::flush(StudyStore& store, std::int64_t now_ns, std::string* why) {
  if (batches_.empty() || trial_id_ == 0) return true;
  const bool stored = store.addTelemetry(trial_id_, batches_, why);
  batches_.clear();
  last_flush_ns_ = now_ns;
  return stored;
}

}  // namespace telesphere::console::study
