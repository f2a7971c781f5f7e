// Reading a ROS 1 bag of 10 topics (IMU at 400 Hz, joints, four wheel
// wrenches, GPS, odometry, commands, TF, and camera-sized images that are
// skipped), about ROVERLAB_BENCH_BAG_MB megabytes (default 100), written
// once with the ROS library's own writer (uncompressed chunks): RoverLab's reader
// (load_log: decode every numeric field into channels; the crash guard's
// trial alone) beside the rosbag C++
// API merely iterating the same bag, copying out each message's bytes
// (size() and write()) or not (instantiate() of a type that points at them),
// in the same run (issue 31).
//
//   build/bench/bench_ros_bag [ROVERLAB_BENCH_DIR=/tmp] [ROVERLAB_BENCH_BAG_MB=100]
//
// Counters: file_MB, MBps (file bytes per second), payload_MB (the numeric
// channels RoverLab keeps), kept_ratio (bytes still allocated after the read,
// mallinfo2, over the payload), peak_MB (one more read in a fresh process:
// its peak resident set, VmHWM, less that of one that reads nothing) and
// peak_ratio (peak_MB over the payload). The 1 GB figure of
// docs/performance.md: ROVERLAB_BENCH_BAG_MB=1000.
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

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
#include <zlib.h>

#include "importers/log_file.h"
#include "importers/log_reader.h"
#include "importers/mcap_file.h"

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

constexpr double kImageBytes = 160.0 * 120.0 * 3.0;  // a small colour camera at 5 Hz

// Seconds of recording that make about `megabytes()` (the images dominate).
double recording_seconds() {
  const double per_second =
      5 * kImageBytes + 400 * 330 + 50 * 300 + 4 * 100 * 120 + 10 * 120 + 50 * 700 + 20 * 90 + 50 * 120;
  return megabytes() * 1e6 / per_second;
}

void write_bag(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);  // uncompressed chunks: the file is its size
  const double image_bytes = kImageBytes;
  const int ticks = static_cast<int>(recording_seconds() * 400);
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
    return p;
  }();
  // Registered after `path` is made, so run before it is destroyed (an exit
  // handler registered inside its initialiser ran after, and removed nothing).
  static const bool removed_at_exit = std::atexit([] {
                                        std::error_code ec;
                                        fs::remove(bag_path(), ec);
                                      }) == 0;
  (void)removed_at_exit;
  return path;
}

// The same messages as an MCAP file (format version 0): ROS 1 encoding,
// uncompressed 1 MB chunks with their CRC-32, a summary with schemas,
// channels and chunk indexes. Written here from the bag (a minimal writer for the benchmark
// only; the reader's tests use the MCAP project's own writer).
class McapWriter {
 public:
  explicit McapWriter(const std::string& path) : out_(path, std::ios::binary) {
    out_.write(kMagic, 8);
    std::string header;
    put_string(header, "ros1");
    put_string(header, "roverlab bench");
    record(out_, 0x01, header);
  }

  std::uint16_t channel(const std::string& topic, const std::string& type, const std::string& definition) {
    const auto it = channels_.find(topic);
    if (it != channels_.end()) return it->second;
    const auto id = static_cast<std::uint16_t>(channels_.size() + 1);
    std::string schema;
    put<std::uint16_t>(schema, id);
    put_string(schema, type);
    put_string(schema, "ros1msg");
    put_string(schema, definition);
    std::string ch;
    put<std::uint16_t>(ch, id);
    put<std::uint16_t>(ch, id);
    put_string(ch, topic);
    put_string(ch, "ros1");
    put<std::uint32_t>(ch, 0);  // no metadata
    summary_records_.push_back({0x03, schema});
    summary_records_.push_back({0x04, ch});
    append_record(0x03, schema);
    append_record(0x04, ch);
    channels_.emplace(topic, id);
    return id;
  }

  void message(std::uint16_t channel, std::uint64_t time_ns, const std::uint8_t* data, std::uint32_t size) {
    std::string m;
    put<std::uint16_t>(m, channel);
    put<std::uint32_t>(m, 0);
    put<std::uint64_t>(m, time_ns);
    put<std::uint64_t>(m, time_ns);
    m.append(reinterpret_cast<const char*>(data), size);
    if (chunk_.empty()) chunk_start_ = time_ns;
    chunk_end_ = time_ns;
    chunk_channels_.insert(channel);
    ++counts_[channel];
    append_record(0x05, m);
    if (chunk_.size() > (1U << 20)) flush();
  }

  void close() {
    flush();
    std::string data_end;
    put<std::uint32_t>(data_end, 0);
    record(out_, 0x0F, data_end);
    const auto summary_start = static_cast<std::uint64_t>(out_.tellp());
    for (const auto& [op, content] : summary_records_) record(out_, op, content);
    std::string statistics;
    std::uint64_t total = 0;
    for (const auto& [id, n] : counts_) total += n;
    put<std::uint64_t>(statistics, total);
    put<std::uint16_t>(statistics, static_cast<std::uint16_t>(channels_.size()));
    put<std::uint32_t>(statistics, static_cast<std::uint32_t>(channels_.size()));
    put<std::uint32_t>(statistics, 0);
    put<std::uint32_t>(statistics, 0);
    put<std::uint32_t>(statistics, chunks_);
    put<std::uint64_t>(statistics, 0);
    put<std::uint64_t>(statistics, 0);
    put<std::uint32_t>(statistics, static_cast<std::uint32_t>(10 * counts_.size()));
    for (const auto& [id, n] : counts_) {
      put<std::uint16_t>(statistics, id);
      put<std::uint64_t>(statistics, n);
    }
    record(out_, 0x0B, statistics);
    std::string footer;
    put<std::uint64_t>(footer, summary_start);
    put<std::uint64_t>(footer, 0);
    put<std::uint32_t>(footer, 0);
    record(out_, 0x02, footer);
    out_.write(kMagic, 8);
  }

 private:
  static constexpr char kMagic[] = "\x89MCAP0\r\n";
  template <class T>
  static void put(std::string& s, T v) {
    s.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  static void put_string(std::string& s, const std::string& v) {
    put<std::uint32_t>(s, static_cast<std::uint32_t>(v.size()));
    s += v;
  }
  static void record(std::ostream& out, std::uint8_t op, const std::string& content) {
    out.put(static_cast<char>(op));
    const auto n = static_cast<std::uint64_t>(content.size());
    out.write(reinterpret_cast<const char*>(&n), 8);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
  }
  void append_record(std::uint8_t op, const std::string& content) {
    chunk_ += static_cast<char>(op);
    put<std::uint64_t>(chunk_, content.size());
    chunk_ += content;
  }
  void flush() {
    if (chunk_.empty()) return;
    const auto offset = static_cast<std::uint64_t>(out_.tellp());
    std::string c;
    put<std::uint64_t>(c, chunk_start_);
    put<std::uint64_t>(c, chunk_end_);
    put<std::uint64_t>(c, chunk_.size());
    // The CRC-32 of the records, as the MCAP project's writer gives it (the reader checks it).
    put<std::uint32_t>(c, static_cast<std::uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(chunk_.data()),
                                                           static_cast<uInt>(chunk_.size()))));
    put_string(c, "");
    put<std::uint64_t>(c, chunk_.size());
    c += chunk_;
    record(out_, 0x06, c);
    std::string index;
    put<std::uint64_t>(index, chunk_start_);
    put<std::uint64_t>(index, chunk_end_);
    put<std::uint64_t>(index, offset);
    put<std::uint64_t>(index, 9 + c.size());
    put<std::uint32_t>(index, static_cast<std::uint32_t>(10 * chunk_channels_.size()));
    for (std::uint16_t id : chunk_channels_) {
      put<std::uint16_t>(index, id);
      put<std::uint64_t>(index, 0);  // no message index records
    }
    put<std::uint64_t>(index, 0);
    put_string(index, "");
    put<std::uint64_t>(index, chunk_.size());
    put<std::uint64_t>(index, chunk_.size());
    summary_records_.push_back({0x08, index});
    ++chunks_;
    chunk_.clear();
    chunk_channels_.clear();
  }

  std::ofstream out_;
  std::map<std::string, std::uint16_t> channels_;
  std::vector<std::pair<std::uint8_t, std::string>> summary_records_;
  std::string chunk_;
  std::set<std::uint16_t> chunk_channels_;
  std::uint64_t chunk_start_ = 0;
  std::uint64_t chunk_end_ = 0;
  std::map<std::uint16_t, std::uint64_t> counts_;
  std::uint32_t chunks_ = 0;
};

const std::string& mcap_path() {
  static const std::string path = [] {
    const std::string p = bag_path() + ".mcap";
    rosbag::Bag bag(bag_path(), rosbag::bagmode::Read);
    rosbag::View view(bag);
    McapWriter writer(p);
    for (const rosbag::MessageInstance& m : view) {
      const auto bytes = m.instantiate<RawBytes>();
      const std::uint16_t channel = writer.channel(m.getTopic(), m.getDataType(), m.getMessageDefinition());
      writer.message(channel, m.getTime().toNSec(), bytes->data, bytes->size);
    }
    writer.close();
    return p;
  }();
  // Registered after `path` is made, so run before it is destroyed (an exit
  // handler registered inside its initialiser ran after, and removed nothing).
  static const bool removed_at_exit = std::atexit([] {
                                        std::error_code ec;
                                        fs::remove(mcap_path(), ec);
                                      }) == 0;
  (void)removed_at_exit;
  return path;
}

std::size_t allocated_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

// One read, alone in a fresh process (this program run with --peak-child
// MODE FILE): "rosbag" iterates the bag as BM_RosbagIterate, "bag" is
// RoverLab's bag reader, "guarded" load_log, "mcap" and "mcap-range" the MCAP
// reader (all, or the middle 10 % of the time), "none" nothing.
void rosbag_iterate(const std::string& path);
log::Log read_mcap_part(const std::string& path, bool range, io::McapReadStats* stats);

// Prints the process's peak resident set (VmHWM, kB): this process's own,
// where getrusage's ru_maxrss would also hold the forking parent's.
int peak_child(const std::string& mode, const std::string& path) {
  if (mode == "rosbag") rosbag_iterate(path);
  if (mode == "bag") benchmark::DoNotOptimize(io::find_log_reader(path)->read(path, {}));
  if (mode == "guarded") benchmark::DoNotOptimize(io::load_log(path).log);
  if (mode == "mcap" || mode == "mcap-range") benchmark::DoNotOptimize(read_mcap_part(path, mode != "mcap", nullptr));
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) std::printf("%s\n", line.substr(6).c_str());
  }
  return 0;
}

// The peak resident set (VmHWM, MB) of that fresh process, less the peak of
// one that reads nothing (the program and its libraries).
double peak_mb(const std::string& mode, const std::string& path) {
  const auto run = [](const std::string& m, const std::string& p) {
    const std::string command = "'/proc/" + std::to_string(::getpid()) + "/exe' --peak-child " + m + " '" + p + "'";
    std::FILE* child = ::popen(command.c_str(), "r");
    if (child == nullptr) return -1.0;
    double kb = -1.0;
    if (std::fscanf(child, "%lf", &kb) != 1) kb = -1.0;
    return ::pclose(child) == 0 && kb >= 0 ? kb * 1024.0 / 1e6 : -1.0;
  };
  static const double idle = run("none", path);
  return run(mode, path) - idle;
}

void rosbag_iterate(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::vector<std::uint8_t> buffer;
  for (const rosbag::MessageInstance& m : view) {
    buffer.resize(m.size());
    ros::serialization::OStream s(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
    m.write(s);
  }
  benchmark::DoNotOptimize(buffer.data());
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
  state.counters["peak_MB"] = peak_mb("rosbag", path);
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
  state.counters["peak_MB"] = peak_mb(guarded ? "guarded" : "bag", path);
  state.counters["peak_ratio"] = state.counters["peak_MB"] / payload_mb;
  state.counters["file_MB"] = file_mb;
  state.counters["payload_MB"] = payload_mb;
  state.counters["kept_ratio"] = kept_ratio;
  state.counters["MBps"] = benchmark::Counter(file_mb * 1e6 * static_cast<double>(state.iterations()),
                                              benchmark::Counter::kIsRate, benchmark::Counter::kIs1000);
}

// What the crash guard's child runs before load_log reads (the reader's
// trial_read): the library opens the bag and decompresses each compressed
// chunk, whose records are walked; an uncompressed chunk is not read.
void BM_RoverLabScanBag(benchmark::State& state) {
  const std::string& path = bag_path();
  const double file_mb = static_cast<double>(fs::file_size(path)) / 1e6;
  const io::LogReader* reader = io::find_log_reader(path);
  for (auto _ : state) reader->trial_read(path, {});
  state.counters["file_MB"] = file_mb;
  state.counters["MBps"] = benchmark::Counter(file_mb * 1e6 * static_cast<double>(state.iterations()),
                                              benchmark::Counter::kIsRate, benchmark::Counter::kIs1000);
}

// The same data as MCAP: all of it, and a time range of 10 % through the
// chunk indexes (bytes_fraction: bytes read over the file's size).
void BM_RoverLabReadMcap(benchmark::State& state) {
  const bool range = state.range(0) != 0;
  const std::string& path = mcap_path();
  const double file_mb = static_cast<double>(fs::file_size(path)) / 1e6;
  double payload_mb = 0.0;
  double kept_ratio = 0.0;
  io::McapReadStats stats;
  for (auto _ : state) {
    const std::size_t before = allocated_bytes();
    log::Log lg = read_mcap_part(path, range, &stats);
    const std::size_t after = allocated_bytes();
    payload_mb = static_cast<double>(lg.payload_bytes()) / 1e6;
    kept_ratio = static_cast<double>(after - before) / static_cast<double>(lg.payload_bytes());
    benchmark::DoNotOptimize(lg);
  }
  state.counters["peak_MB"] = peak_mb(range ? "mcap-range" : "mcap", path);
  state.counters["peak_ratio"] = state.counters["peak_MB"] / payload_mb;
  state.counters["chunks_read"] = static_cast<double>(stats.chunks_read);
  state.counters["chunks_in_file"] = static_cast<double>(stats.chunks_in_file);
  state.counters["file_MB"] = file_mb;
  state.counters["payload_MB"] = payload_mb;
  state.counters["kept_ratio"] = kept_ratio;
  state.counters["bytes_fraction"] = static_cast<double>(stats.bytes_read) / (file_mb * 1e6);
  state.counters["MBps"] = benchmark::Counter(file_mb * 1e6 * static_cast<double>(state.iterations()),
                                              benchmark::Counter::kIsRate, benchmark::Counter::kIs1000);
}

}  // namespace

namespace {
log::Log read_mcap_part(const std::string& path, bool range, io::McapReadStats* stats) {
  io::McapSelection selection;
  if (range) {
    const std::uint64_t start = at(0.0).toNSec();
    const auto span = static_cast<std::uint64_t>(recording_seconds() * 1e9);
    selection.start_ns = start + span / 2;
    selection.end_ns = start + span / 2 + span / 10;
  }
  return io::read_mcap(path, {}, selection, stats);
}
}  // namespace

BENCHMARK(BM_RosbagIterate)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RosbagIterateZeroCopy)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RoverLabScanBag)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RoverLabReadBag)->ArgName("guarded")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RoverLabReadMcap)->ArgName("range")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);
int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--peak-child") return peak_child(argv[2], argv[3]);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
