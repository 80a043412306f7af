// The setpoint inbox (core/run/setpoint_inbox): the admission of stamps
// (docs/cell.md, "Bad input") and the handing over of what the callbacks
// received to the loop. Stamps in nanoseconds of the sender's clock.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "coil_winding_sim/core/run/setpoint_inbox.hpp"

namespace {
using cws::SetpointInbox;
using Verdict = SetpointInbox::Verdict;
constexpr std::int64_t kS = 1000000000;  // [ns] in a second

TEST(SetpointInbox, ZeroIsAlwaysAdmitted) {
  SetpointInbox inbox(1.0);
  std::string why;
  EXPECT_EQ(inbox.admit("a", 50 * kS, 50 * kS, true, why), Verdict::kAdmitted);
  EXPECT_EQ(inbox.admit("a", 0, 50 * kS, true, why), Verdict::kAdmitted);
}

TEST(SetpointInbox, AheadOfTheClockBeyondTheToleranceIsRefused) {
  SetpointInbox inbox(1.0);
  std::string why;
  EXPECT_EQ(inbox.admit("tension_setpoint", 11 * kS, 10 * kS, true, why), Verdict::kAdmitted);
  EXPECT_EQ(inbox.admit("tension_setpoint", 11 * kS + kS / 2, 10 * kS, true, why), Verdict::kAhead);
  EXPECT_NE(why.find("tension_setpoint stamped 11.500000 s"), std::string::npos) << why;
  EXPECT_NE(why.find("~setpoint_stamp_tolerance"), std::string::npos) << why;
  // Without a clock yet (ROS time zero before the first /clock) there is
  // nothing to compare with.
  EXPECT_EQ(inbox.admit("other", 1000000 * kS, 0, false, why), Verdict::kAdmitted);
}

TEST(SetpointInbox, OlderThanTheTopicsLastIsDroppedPerTopic) {
  SetpointInbox inbox(1.0);
  std::string why;
  EXPECT_EQ(inbox.admit("a", 5 * kS, 5 * kS, true, why), Verdict::kAdmitted);
  EXPECT_EQ(inbox.admit("a", 4 * kS, 5 * kS, true, why), Verdict::kOutOfOrder);
  EXPECT_NE(why.find("older than the last applied one (5.000000 s)"), std::string::npos) << why;
  // One nanosecond older is out of order too (stamps compare exactly).
  EXPECT_EQ(inbox.admit("a", 5 * kS - 1, 5 * kS, true, why), Verdict::kOutOfOrder);
  // Another topic has its own order; an equal stamp is in order.
  EXPECT_EQ(inbox.admit("b", 4 * kS, 5 * kS, true, why), Verdict::kAdmitted);
  EXPECT_EQ(inbox.admit("a", 5 * kS, 5 * kS, true, why), Verdict::kAdmitted);
}

TEST(SetpointInbox, AClockGoingBackOrANewRunForgetsTheLastStamps) {
  SetpointInbox inbox(1.0);
  std::string why;
  EXPECT_EQ(inbox.admit("a", 9 * kS, 10 * kS, true, why), Verdict::kAdmitted);
  // A looping bag: the clock starts again at 2 s.
  EXPECT_EQ(inbox.admit("a", 1 * kS + kS / 2, 2 * kS, true, why), Verdict::kAdmitted);
  EXPECT_EQ(inbox.admit("a", 2 * kS + kS / 2, 3 * kS, true, why), Verdict::kAdmitted);
  inbox.clear();  // reset or restore
  EXPECT_EQ(inbox.admit("a", 2 * kS, 3 * kS, true, why), Verdict::kAdmitted);
}

TEST(SetpointInbox, TakeHandsOverWhatWasReceivedOnceInArrivalOrder) {
  SetpointInbox inbox(1.0);
  inbox.put({"core_speed_setpoint", 0, cws::Setpoint::coreSpeed(10.0)});
  inbox.put({"tension_setpoint", 3 * kS, cws::Setpoint::supplyTension(40.0)});
  inbox.put({"core_speed_setpoint", 0, cws::Setpoint::coreSpeed(20.0)});
  inbox.put(
      SetpointInbox::Schedule{"joint_trajectory", kS, {{0.5, cws::Setpoint::coreSpeed(5.0)}}});
  std::vector<double> values;
  std::vector<std::int64_t> stamps;
  int schedules = 0;
  inbox.take(
      [&](SetpointInbox::Received& r) {
        values.push_back(r.setpoint.value);
        stamps.push_back(r.stamp_ns);
      },
      [&](SetpointInbox::Schedule& s) {
        ++schedules;
        EXPECT_EQ(s.points.size(), 1u);
        EXPECT_EQ(s.stamp_ns, kS);
      });
  EXPECT_EQ(values, (std::vector<double>{10.0, 40.0, 20.0}));
  EXPECT_EQ(stamps, (std::vector<std::int64_t>{0, 3 * kS, 0}));
  EXPECT_EQ(schedules, 1);
  // Taken once.
  int again = 0;
  inbox.take([&](SetpointInbox::Received&) { ++again; },
             [&](SetpointInbox::Schedule&) { ++again; });
  EXPECT_EQ(again, 0);
}

}  // namespace
