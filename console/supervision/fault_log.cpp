// SPDX-License-Identifier: MIT
/// @brief FaultLog: open, clear, acknowledge.
#include "console/supervision/fault_log.h"

namespace telesphere::console::supervision {

Fault* FaultLog::open(const std::string& key) {
  for (auto it = faults_.rbegin(); it != faults_.rend(); ++it)
    if (it->key == key) return it->cleared_ns == 0 || !it->acknowledged ? &*it : nullptr;
  return nullptr;
}

void FaultLog::raise(const std::string& key, const std::string& text, std::int64_t now_ns) {
  if (Fault* f = open(key)) {
    if (f->acknowledged) return;  // still holds, already seen
    if (f->cleared_ns != 0) {     // back before anyone acknowledged it
      f->cleared_ns = 0;
      ++f->times;
      ++version_;
    }
    if (f->text != text) {
      f->text = text;
      ++version_;
    }
    return;
  }
  faults_.push_back(Fault{key, text, now_ns, 0, 1, false});
  if (faults_.size() > kHistory) faults_.pop_front();
  ++version_;
}

void FaultLog::clear(const std::string& key, std::int64_t now_ns) {
  Fault* f = open(key);
  if (!f || f->cleared_ns != 0) return;
  f->cleared_ns = now_ns;
  ++version_;
}

void FaultLog::acknowledgeAll() {
  bool changed = false;
  for (Fault& f : faults_) {
    changed = changed || !f.acknowledged;
    f.acknowledged = true;
  }
  if (changed) ++version_;
}

std::vector<Fault> FaultLog::unacknowledged() const {
  std::vector<Fault> out;
  for (const Fault& f : faults_)
    if (!f.acknowledged) out.push_back(f);
  return out;
}

}  // namespace telesphere::console::supervision
