// The bad-input rostest (see test_bad_input.cpp): snapshots that cannot be
// written, restores of bad files, restore while paused, reset during
// snapshots.
#include "bad_input_support.hpp"

using namespace bad_input;

// Snapshots to paths that cannot be written: refused with a message naming
// the path; the run goes on untouched.
TEST(BadInput, SnapshotToAnUnwritablePath) {
  ASSERT_TRUE(waitFor([] { return observer->count() > 0; }, 30.0)) << "no metrics";
  // Running as root, permissions do not stop a write: a path below a
  // regular file, one in /proc, a directory, an empty path.
  const std::string file = tmpPath("a_file");
  writeFile(file, "a regular file\n");
  for (const std::string& path :
       {file + "/snapshot.bag", std::string("/proc/cws_no_such_dir/snapshot.bag"),
        std::string("/tmp"), std::string("")}) {
    const WindingMetrics before = fresh();
    const int delete_all = observer->deleteAlls();
    const auto res = snapshot(path);
    EXPECT_FALSE(res.success) << "'" << path << "': " << res.message;
    if (path.empty()) {
      EXPECT_NE(res.message.find("empty"), std::string::npos) << res.message;
    } else {
      EXPECT_NE(res.message.find("'" + path + "'"), std::string::npos) << res.message;
    }
    expectRunWentOn(before, delete_all, "snapshot to '" + path + "'");
  }
  fs::remove(file);
  // Nothing half-written left behind: the node writes `<path>.partial.*`
  // first (for the path /tmp, that is /tmp.partial.* in /).
  for (const auto& e : fs::directory_iterator("/")) {
    EXPECT_NE(e.path().filename().string().rfind("tmp.partial", 0), 0u) << e.path();
  }
}

// Restores of files that are no snapshot: refused with a message naming the
// file and the cause; the run goes on from where it was.
TEST(BadInput, RestoreOfBadFiles) {
  ASSERT_TRUE(waitFor([] { return observer->count() > 0; }, 30.0)) << "no metrics";
  const std::string good = tmpPath("good.bag");
  ASSERT_TRUE(snapshot(good).success);
  const std::string bytes = readFile(good);
  ASSERT_GT(bytes.size(), 1000u);

  // (file, what its refusal must say besides its path)
  std::vector<std::pair<std::string, std::string>> bad;
  // Removes the files also when an assertion below ends the test early.
  struct Cleanup {
    const std::string& good;
    const std::vector<std::pair<std::string, std::string>>& bad;
    ~Cleanup() {
      fs::remove(good);
      for (const auto& b : bad) fs::remove(b.first);
    }
  } cleanup{good, bad};
  // Truncated: the bag's magic only, half of it, all but the last byte.
  for (std::size_t size : {std::size_t{13}, bytes.size() / 2, bytes.size() - 1}) {
    const std::string path = tmpPath("truncated_" + std::to_string(size) + ".bag");
    writeFile(path, bytes.substr(0, size));
    bad.push_back({path, "truncated"});
  }
  // Empty, and random bytes.
  writeFile(tmpPath("empty.bag"), "");
  bad.push_back({tmpPath("empty.bag"), "not a readable bag"});
  std::mt19937 rng(6);
  std::string noise(bytes.size(), '\0');
  for (char& c : noise) c = static_cast<char>(rng());
  writeFile(tmpPath("noise.bag"), noise);
  bad.push_back({tmpPath("noise.bag"), "not a readable bag"});
  // The snapshot with the header length of its message record overwritten
  // (found by fuzzing: rosbag then reads past its buffer and crashes).
  {
    const std::string op_field("\x04\0\0\0op=\x02", 8);
    const std::size_t at = bytes.find(op_field);
    ASSERT_NE(at, std::string::npos);
    ASSERT_GE(at, 17u);
    std::string corrupt = bytes;
    corrupt[at - 17] = static_cast<char>(0xc7);  // 38 -> 199 bytes
    writeFile(tmpPath("bad_record.bag"), corrupt);
    bad.push_back({tmpPath("bad_record.bag"), "corrupt"});
  }
  // Foreign bags: another topic only, another type on the snapshot topic.
  {
    std_msgs::String text;
    text.data = "hello";
    rosbag::Bag other(tmpPath("other_topic.bag"), rosbag::bagmode::Write);
    other.write("/chatter", ros::Time(1.0), text);
    other.close();
    bad.push_back({tmpPath("other_topic.bag"), "no snapshot"});
    rosbag::Bag wrong(tmpPath("wrong_type.bag"), rosbag::bagmode::Write);
    wrong.write(kSnapshotTopic, ros::Time(1.0), text);
    wrong.close();
    bad.push_back({tmpPath("wrong_type.bag"), "std_msgs/String"});
  }
  // Snapshots with values no run can have: another format, a non-finite or
  // absurd core speed, a negative tension, a setpoint the table does not
  // have or the state carries.
  {
    rosbag::Bag in(good, rosbag::bagmode::Read);
    rosbag::View view(in);
    ASSERT_EQ(view.size(), 1u);
    const auto msg = view.begin()->instantiate<coil_winding_sim::SimulationSnapshot>();
    ASSERT_TRUE(msg);
    const auto write = [&](const std::string& name, auto change, const std::string& says) {
      coil_winding_sim::SimulationSnapshot m = *msg;
      change(m);
      m.checksum = cws_ros::snapshotChecksum(m);  // the values, not the checksum, are wrong
      rosbag::Bag out(tmpPath(name), rosbag::bagmode::Write);
      out.write(kSnapshotTopic, ros::Time(1.0), m);
      out.close();
      bad.push_back({tmpPath(name), says});
    };
    write(
        "format.bag", [](auto& m) { m.format = "someone_else/snapshot/1"; }, "format");
    write(
        "nan_speed.bag", [](auto& m) { m.core[3] = std::nan(""); }, "not finite");
    write(
        "fast.bag", [](auto& m) { m.core[3] = 1e6; }, "max_core_speed_rpm");
    // A setpoint appended to the snapshot's held ones (the last of a kind
    // counts).
    const auto holding = [](const std::string& kind, double value) {
      return [kind, value](auto& m) {
        coil_winding_sim::HeldSetpoint h;
        h.kind = kind;
        h.value = value;
        m.setpoints.push_back(h);
      };
    };
    write("negative_tension.bag", holding("tension", -1.0), "tension -1 N is negative");
    write("unknown_setpoint.bag", holding("feed speed", 0.0), "unknown setpoint 'feed speed'");
    write("held_speed.bag", holding("core speed", 0.0), "which the model's state carries");
  }
  // One bit of one number changed in the file (a plausible position): only
  // the checksum tells. The same number changed in a message written anew
  // with its old checksum.
  {
    rosbag::Bag in(good, rosbag::bagmode::Read);
    rosbag::View view(in);
    const auto msg = view.begin()->instantiate<coil_winding_sim::SimulationSnapshot>();
    ASSERT_TRUE(msg);
    ASSERT_GT(msg->state.size(), 10u);
    const double x = msg->state[10];
    const std::string x_bytes(reinterpret_cast<const char*>(&x), sizeof x);
    const std::size_t at = bytes.find(x_bytes);
    ASSERT_NE(at, std::string::npos);
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x01);  // last mantissa bit
    writeFile(tmpPath("flipped_bit.bag"), flipped);
    bad.push_back({tmpPath("flipped_bit.bag"), "checksum"});
    coil_winding_sim::SimulationSnapshot m = *msg;
    m.state[10] += 1e-4;
    rosbag::Bag out(tmpPath("changed_number.bag"), rosbag::bagmode::Write);
    out.write(kSnapshotTopic, ros::Time(1.0), m);
    out.close();
    bad.push_back({tmpPath("changed_number.bag"), "checksum"});
  }
  // A snapshot of another version of the package: the same type name with
  // another message definition (as the snapshot/3 bags, before the
  // checksum field).
  {
    rosbag::Bag in(good, rosbag::bagmode::Read);
    rosbag::View view(in);
    const auto msg = view.begin()->instantiate<coil_winding_sim::SimulationSnapshot>();
    ASSERT_TRUE(msg);
    std::vector<uint8_t> data(ros::serialization::serializationLength(*msg));
    ros::serialization::OStream os(data.data(), static_cast<uint32_t>(data.size()));
    ros::serialization::serialize(os, *msg);
    topic_tools::ShapeShifter older;
    older.morph("0123456789abcdef0123456789abcdef", "coil_winding_sim/SimulationSnapshot",
                "string format\n", "");
    ros::serialization::IStream is(data.data(), static_cast<uint32_t>(data.size()));
    older.read(is);
    rosbag::Bag out(tmpPath("older_version.bag"), rosbag::bagmode::Write);
    out.write(kSnapshotTopic, ros::Time(1.0), older);
    out.close();
    bad.push_back({tmpPath("older_version.bag"), "another version of coil_winding_sim"});
  }

  for (const auto& [path, says] : bad) {
    const WindingMetrics before = fresh();
    const int delete_all = observer->deleteAlls();
    const auto res = restore(path);
    EXPECT_FALSE(res.success) << path << ": " << res.message;
    EXPECT_NE(res.message.find(path), std::string::npos) << res.message;
    // The cause, in the message without the path (whose name may hold it).
    std::string cause = res.message;
    for (std::size_t at; (at = cause.find(path)) != std::string::npos;)
      cause.erase(at, path.size());
    EXPECT_NE(cause.find(says), std::string::npos)
        << "expected '" << says << "' in: " << res.message;
    std::printf("%s: %s\n", fs::path(path).filename().c_str(), res.message.c_str());
    expectRunWentOn(before, delete_all, "restore of " + path);
  }
}

// Restore while paused: the restored run stays paused at the snapshot's
// time until resumed.
TEST(BadInput, RestoreWhilePaused) {
  ASSERT_TRUE(waitFor([] { return observer->count() > 0; }, 30.0)) << "no metrics";
  Resume resume;
  const std::string path = tmpPath("paused.bag");
  ASSERT_TRUE(pause(true));
  // (While paused the metrics come once a second.)
  const WindingMetrics at_snapshot = fresh(2);
  ASSERT_TRUE(snapshot(path).success);
  ASSERT_TRUE(pause(false));
  ASSERT_TRUE(waitFor([&] { return observer->latest().sim_time > at_snapshot.sim_time; }, 10.0));
  ASSERT_TRUE(pause(true));
  const WindingMetrics before = fresh(2);
  ASSERT_GT(before.sim_time, at_snapshot.sim_time);

  const auto res = restore(path);
  ASSERT_TRUE(res.success) << res.message;
  // Paused at the snapshot's state for two seconds of wall time.
  const WindingMetrics restored = fresh(2);
  EXPECT_EQ(restored.sim_time, at_snapshot.sim_time);
  EXPECT_EQ(restored.steps_accepted, at_snapshot.steps_accepted);
  const WindingMetrics later = fresh(2);
  EXPECT_EQ(later.sim_time, at_snapshot.sim_time) << "the restored run did not stay paused";
  // Resumed, it runs on.
  ASSERT_TRUE(pause(false));
  EXPECT_TRUE(waitFor([&] { return observer->latest().sim_time > at_snapshot.sim_time; }, 10.0));
  fs::remove(path);
}

// Reset and snapshot at once (and two snapshots to one path): all succeed,
// without deadlock, and every snapshot file is complete and restores.
TEST(BadInput, ResetDuringSnapshot) {
  ASSERT_TRUE(waitFor([] { return observer->count() > 0; }, 30.0)) << "no metrics";
  for (int round = 0; round < 20; ++round) {
    const std::string path = tmpPath("concurrent_" + std::to_string(round) + ".bag");
    coil_winding_sim::Snapshot::Response snap_a, snap_b;
    std_srvs::Trigger::Response reset_res;
    std::thread a([&] { snap_a = snapshot(path); });
    std::thread b([&] { snap_b = snapshot(path); });
    std::thread r([&] { reset_res = reset(); });
    a.join();
    b.join();
    r.join();
    EXPECT_TRUE(snap_a.success) << "round " << round << ": " << snap_a.message;
    EXPECT_TRUE(snap_b.success) << "round " << round << ": " << snap_b.message;
    EXPECT_TRUE(reset_res.success) << "round " << round << ": " << reset_res.message;

    // The file is a complete bag with one snapshot, and it restores.
    {
      rosbag::Bag bag(path, rosbag::bagmode::Read);
      rosbag::View view(bag);
      ASSERT_EQ(view.size(), 1u) << path;
      const auto msg = view.begin()->instantiate<coil_winding_sim::SimulationSnapshot>();
      ASSERT_TRUE(msg) << path;
      const auto res = restore(path);
      EXPECT_TRUE(res.success) << res.message;
      const WindingMetrics restored = fresh(2);
      EXPECT_GE(restored.sim_time, msg->time) << "restored " << path;
    }
    fs::remove(path);
  }
  // The node still runs.
  const WindingMetrics before = fresh();
  EXPECT_TRUE(waitFor([&] { return observer->latest().sim_time > before.sim_time; }, 10.0));
}
