#include "coil_winding_sim/core/run/setpoint_inbox.hpp"

#include "coil_winding_sim/core/base/text_format.hpp"

namespace cws {

namespace {
std::string seconds(std::int64_t ns) { return formatNumber(1e-9 * ns, "%.6f"); }
}  // namespace

SetpointInbox::Verdict SetpointInbox::admit(const std::string& topic, std::int64_t stamp_ns,
                                            std::int64_t clock_ns, bool have_clock,
                                            std::string& why) {
  if (stamp_ns == 0) return Verdict::kAdmitted;
  std::lock_guard<std::mutex> lock(mutex_);
  // The clock went back: stamps of the new time line must not lose against
  // the old one.
  if (clock_ns < last_clock_ns_) last_ns_.clear();
  last_clock_ns_ = clock_ns;
  if (have_clock && 1e-9 * stamp_ns > 1e-9 * clock_ns + tolerance_s_) {
    why = "refused " + topic + " stamped " + seconds(stamp_ns) + " s: more than " +
          formatNumber(tolerance_s_) + " s (~setpoint_stamp_tolerance) ahead of the node's clock " +
          seconds(clock_ns) + " s";
    return Verdict::kAhead;
  }
  std::int64_t& last = last_ns_[topic];
  if (stamp_ns < last) {
    why = "dropped " + topic + " stamped " + seconds(stamp_ns) +
          " s: out of order, older than the last applied one (" + seconds(last) + " s)";
    return Verdict::kOutOfOrder;
  }
  last = stamp_ns;
  return Verdict::kAdmitted;
}

void SetpointInbox::put(Received r) {
  std::lock_guard<std::mutex> lock(mutex_);
  received_.push_back(std::move(r));
}

void SetpointInbox::put(Schedule s) {
  std::lock_guard<std::mutex> lock(mutex_);
  schedules_.push_back(std::move(s));
}

void SetpointInbox::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  last_ns_.clear();
  ports_.clear();
}

}  // namespace cws
