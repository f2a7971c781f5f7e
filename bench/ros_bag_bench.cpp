// Reading a ROS 1 bag of 10 topics (IMU at 400 Hz, joints, four wheel
// wrenches, GPS, odometry, commands, TF, and camera-sized images that are
// skipped), about ROVERLAB_BENCH_BAG_MB megabytes (default 100), written
// once with the ROS library's own writer (uncompressed chunks): RoverLab's reader
// (load_log: decode every numeric field into channels) beside the rosbag C++
// API merely iterating the same bag, copying out each message's bytes
// (size() and write()) or not (instantiate() of a type that points at them),
// in the same run (issue 31).
//
//   build/bench/bench_ros_bag [ROVERLAB_BENCH_DIR=/tmp] [ROVERLAB_BENCH_BAG_MB=100]
//
// Counters: file_MB, MBps (file bytes per second), payload_MB (the numeric
// channels RoverLab keeps), kept_ratio (bytes still allocated after the read,
// mallinfo2, over the payload).
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/NavSatFix.h>
#include <tf2_msgs/TFMessage.h>

#include "importers/log_file.h"
#include "importers/log_reader.h"

// The fastest way through the library: a message's bytes where the library
// holds them, one header parse, no copy (as importers/ros1_bag_reader.cpp).
struct RawBytes {
  const std::uint8_t* data = nullptr;
  std::uint32_t size = 0;
};
namespace ros {
namespace message_traits {
template <>
struct MD5Sum<RawBytes> {
  static const char* value() { return "*"; }
  static const char* value(const RawBytes&) { return value(); }
};
template <>
struct DataType<RawBytes> {
  static const char* value() { return "*"; }
  static const char* value(const RawBytes&) { return value(); }
};
}  // namespace message_traits
namespace serialization {
template <>
struct Serializer<RawBytes> {
  template <typename Stream>
  static void read(Stream& stream, RawBytes& m) {
    m.data = stream.getData();
    m.size = stream.getLength();
  }
};
}  // namespace serialization
}  // namespace ros

namespace {

namespace fs = std::filesystem;
using namespace roverlab;

double megabytes() {
  const char* mb = std::getenv("ROVERLAB_BENCH_BAG_MB");
  return mb != nullptr ? std::atof(mb) : 100.0;
}

ros::Time at(double t) { return ros::Time(1'700'000'000.0 + t); }

// Seconds of recording that make about `megabytes()` (the images dominate).
void write_bag(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);   // uncompressed chunks: the file is its size
  const double image_bytes = 160.0 * 120.0 * 3.0;  // a small colour camera at 5 Hz
  const double per_second =
      5 * image_bytes + 400 * 330 + 50 * 300 + 4 * 100 * 120 + 10 * 120 + 50 * 700 + 20 * 90 + 50 * 120;
  const double seconds = megabytes() * 1e6 / per_second;
  const int ticks = static_cast<int>(seconds * 400);
  for (int k = 0; k < ticks; ++k) {
    const double t = k / 400.0;
    sensor_msgs::Imu imu;
    imu.header.stamp = at(t);
    imu.angular_velocity.x = 0.01 * k;
    imu.linear_acceleration.z = 9.81 + 1e-4 * (k % 100);
    imu.orientation.w = 1.0;
    bag.write("/imu/data", at(t), imu);
    if (k % 4 == 0) {
      for (int w = 0; w < 4; ++w) {
        geometry_msgs::WrenchStamped f;
        f.header.stamp = at(t);
        f.wrench.force.z = 100.0 + w + 1e-3 * k;
        bag.write("/wheel_" + std::to_string(w) + "/wrench", at(t), f);
      }
    }
    if (k % 8 == 0) {
      sensor_msgs::JointState j;
      j.header.stamp = at(t);
      j.name = {"FL", "FR", "ML", "MR", "RL", "RR"};
      j.position.assign(6, 0.001 * k);
      j.velocity.assign(6, 1.0);
      bag.write("/joint_states", at(t), j);
      nav_msgs::Odometry o;
      o.header.stamp = at(t);
      o.pose.pose.position.x = 0.001 * k;
      o.pose.pose.orientation.w = 1.0;
      bag.write("/odom", at(t), o);
      tf2_msgs::TFMessage tf;
      tf.transforms.resize(1);
      tf.transforms[0].transform.translation.x = 0.001 * k;
      tf.transforms[0].transform.rotation.w = 1.0;
      bag.write("/tf", at(t), tf);
    }
    if (k % 20 == 0) {
      geometry_msgs::TwistStamped c;
      c.header.stamp = at(t);
      c.twist.linear.x = 0.2;
      bag.write("/cmd_vel", at(t), c);
    }
    if (k % 40 == 0) {
      sensor_msgs::NavSatFix fix;
      fix.header.stamp = at(t);
      fix.latitude = 39.6 + 1e-7 * k;
      bag.write("/navsat/fix", at(t), fix);
    }
    if (k % 80 == 0) {
      sensor_msgs::Image image;
      image.header.stamp = at(t);
      image.height = 120;
      image.width = 160;
      image.encoding = "rgb8";
      image.step = 480;
      image.data.assign(static_cast<std::size_t>(image_bytes), static_cast<std::uint8_t>(k));
      bag.write("/camera/image", at(t), image);
    }
  }
  bag.close();
}

const std::string& bag_path() {
  static const std::string path = [] {
    const char* dir = std::getenv("ROVERLAB_BENCH_DIR");
    const std::string p = (fs::path(dir != nullptr ? dir : fs::temp_directory_path().c_str()) /
                           ("roverlab-bench-" + std::to_string(::getpid()) + ".bag"))
                              .string();
    write_bag(p);
    std::atexit([] {
      std::error_code ec;
      fs::remove(bag_path(), ec);
    });
    return p;
  }();
  return path;
}

std::size_t allocated_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

void BM_RosbagIterate(benchmark::State& state) {
  const std::string& path = bag_path();
  const double file_mb = static_cast<double>(fs::file_size(path)) / 1e6;
  std::size_t messages = 0;
  for (auto _ : state) {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    std::vector<std::uint8_t> buffer;
    messages = 0;
    for (const rosbag::MessageInstance& m : view) {
      buffer.resize(m.size());
      ros::serialization::OStream s(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
      m.write(s);
      ++messages;
    }
    benchmark::DoNotOptimize(buffer.data());
  }
  state.counters["file_MB"] = file_mb;
  state.counters["messages"] = static_cast<double>(messages);
  state.counters["MBps"] = benchmark::Counter(file_mb * 1e6 * static_cast<double>(state.iterations()),
                                              benchmark::Counter::kIsRate, benchmark::Counter::kIs1000);
}

// guarded: load_log, whose crash guard first iterates the bag in a forked
// child (the library's calls, no decoding); else the bag reader alone.
void BM_RosbagIterateZeroCopy(benchmark::State& state) {
  const std::string& path = bag_path();
  const double file_mb = static_cast<double>(fs::file_size(path)) / 1e6;
  std::size_t bytes = 0;
  for (auto _ : state) {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    bytes = 0;
    for (const rosbag::MessageInstance& m : view) bytes += m.instantiate<RawBytes>()->size;
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["file_MB"] = file_mb;
  state.counters["MBps"] = benchmark::Counter(file_mb * 1e6 * static_cast<double>(state.iterations()),
                                              benchmark::Counter::kIsRate, benchmark::Counter::kIs1000);
}

void BM_RoverLabReadBag(benchmark::State& state) {
  const bool guarded = state.range(0) != 0;
  const std::string& path = bag_path();
  const double file_mb = static_cast<double>(fs::file_size(path)) / 1e6;
  double payload_mb = 0.0;
  double kept_ratio = 0.0;
  for (auto _ : state) {
    const std::size_t before = allocated_bytes();
    log::Log lg = guarded ? io::load_log(path).log : io::find_log_reader(path)->read(path, {});
    const std::size_t after = allocated_bytes();
    payload_mb = static_cast<double>(lg.payload_bytes()) / 1e6;
    kept_ratio = static_cast<double>(after - before) / static_cast<double>(lg.payload_bytes());
    benchmark::DoNotOptimize(lg);
  }
  state.counters["file_MB"] = file_mb;
  state.counters["payload_MB"] = payload_mb;
  state.counters["kept_ratio"] = kept_ratio;
  state.counters["MBps"] = benchmark::Counter(file_mb * 1e6 * static_cast<double>(state.iterations()),
                                              benchmark::Counter::kIsRate, benchmark::Counter::kIs1000);
}

}  // namespace

BENCHMARK(BM_RosbagIterate)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RosbagIterateZeroCopy)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RoverLabReadBag)->ArgName("guarded")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_MAIN();
