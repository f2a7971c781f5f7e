// Writes the MCAP fixtures of tests/importers/mcap_test.cpp with writers that
// are not RoverLab's: the MCAP project's own writer (@mcap/core), Foxglove's
// ROS 1 and ROS 2 (CDR) serialisers, @foxglove/wasm-zstd and lz4js for the
// chunks. The fixtures are committed; ctest never needs npm.
//
// Regenerate (Node 18+, from the repository root):
//   cd tests/data/mcap && npm install --no-save @mcap/core@2.2.2 @foxglove/rosmsg@5.0.5 \
//     @foxglove/rosmsg-serialization@2.0.4 @foxglove/rosmsg2-serialization@3.1.0 \
//     @foxglove/wasm-zstd@1.0.1 lz4js@0.2.0 \
//     && node make_fixtures.mjs && rm -rf node_modules package-lock.json
// (the versions the committed files were made with, on Node 20).
//
// Every value is value(i, k) = 0.1 * i + 1e-7 * k - 3.3, which the C++ test
// computes the same way (IEEE doubles, the same operations in the same order).
import { McapWriter } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageWriter as Ros1Writer } from "@foxglove/rosmsg-serialization";
import { MessageWriter as Ros2Writer } from "@foxglove/rosmsg2-serialization";
import * as zstd from "@foxglove/wasm-zstd";
import lz4 from "lz4js";
import { writeFileSync } from "node:fs";

const value = (i, k) => 0.1 * i + 1e-7 * k - 3.3;
const START = 1700000000250000000n; // ns
const at = (i, stepNs) => START + BigInt(i) * BigInt(stepNs);

const IMU_ROS1 = `Header header
geometry_msgs/Quaternion orientation
float64[9] orientation_covariance
geometry_msgs/Vector3 angular_velocity
float64[9] angular_velocity_covariance
geometry_msgs/Vector3 linear_acceleration
float64[9] linear_acceleration_covariance
================================================================================
MSG: std_msgs/Header
uint32 seq
time stamp
string frame_id
================================================================================
MSG: geometry_msgs/Quaternion
float64 x
float64 y
float64 z
float64 w
================================================================================
MSG: geometry_msgs/Vector3
float64 x
float64 y
float64 z
`;

const IMU_ROS2 = `std_msgs/Header header
geometry_msgs/Quaternion orientation
float64[9] orientation_covariance
geometry_msgs/Vector3 angular_velocity
float64[9] angular_velocity_covariance
geometry_msgs/Vector3 linear_acceleration
float64[9] linear_acceleration_covariance
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
================================================================================
MSG: geometry_msgs/Quaternion
float64 x 0
float64 y 0
float64 z 0
float64 w 1
================================================================================
MSG: geometry_msgs/Vector3
float64 x
float64 y
float64 z
`;

const JOINTS_ROS2 = `std_msgs/Header header
string[] name
float64[] position
float64[] velocity
float64[] effort
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
`;

function imu(i) {
  const cov = (k0) => Array.from({ length: 9 }, (_, k) => value(i, k0 + k));
  return {
    orientation: { x: 0, y: 0, z: Math.sin(0.05 * i), w: Math.cos(0.05 * i) },
    orientation_covariance: cov(0),
    angular_velocity: { x: value(i, 10), y: value(i, 11), z: value(i, 12) },
    angular_velocity_covariance: cov(20),
    linear_acceleration: { x: value(i, 13), y: value(i, 14), z: value(i, 15) },
    linear_acceleration_covariance: cov(30),
  };
}

class Sink {
  chunks = [];
  size = 0n;
  async write(buffer) {
    this.chunks.push(Buffer.from(buffer));
    this.size += BigInt(buffer.byteLength);
  }
  position() {
    return this.size;
  }
}

const compressors = {
  none: undefined,
  zstd: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }),
  lz4: (data) => ({ compression: "lz4", compressedData: lz4.compress(data) }),
};

// summary: chunk indexes, statistics, schemas and channels after the data; without
// it the footer's summary offset is 0 and a reader must scan.
async function write(file, { compression = "none", summary = true, chunks = true, chunkSize = 4096 }, fill) {
  const sink = new Sink();
  const writer = new McapWriter({
    writable: sink,
    useChunks: chunks,
    chunkSize,
    compressChunk: compressors[compression],
    useStatistics: summary,
    useChunkIndex: summary,
    useMessageIndex: summary,
    useSummaryOffsets: summary,
    repeatSchemas: summary,
    repeatChannels: summary,
    useAttachmentIndex: summary,
    useMetadataIndex: summary,
  });
  await writer.start({ profile: "ros1", library: "roverlab make_fixtures.mjs" });
  await fill(writer);
  await writer.end();
  writeFileSync(file, Buffer.concat(sink.chunks));
  console.log(file, Buffer.concat(sink.chunks).length, "bytes");
}

async function ros1Imu(writer, count, stepNs) {
  const schemaId = await writer.registerSchema({
    name: "sensor_msgs/Imu",
    encoding: "ros1msg",
    data: new TextEncoder().encode(IMU_ROS1),
  });
  const channelId = await writer.registerChannel({ topic: "/imu/data", messageEncoding: "ros1", schemaId, metadata: new Map() });
  const ros1 = new Ros1Writer(parse(IMU_ROS1));
  for (let i = 0; i < count; ++i) {
    const t = at(i, stepNs);
    const stamp = t + 3000000n; // header.stamp 3 ms after the log time
    const m = imu(i);
    m.header = { seq: i, stamp: { sec: Number(stamp / 1000000000n), nsec: Number(stamp % 1000000000n) }, frame_id: "imu" };
    await writer.addMessage({ channelId, sequence: i, logTime: t, publishTime: t, data: ros1.writeMessage(m) });
  }
}

async function ros2Rover(writer) {
  const imuSchema = await writer.registerSchema({
    name: "sensor_msgs/msg/Imu",
    encoding: "ros2msg",
    data: new TextEncoder().encode(IMU_ROS2),
  });
  const jointSchema = await writer.registerSchema({
    name: "sensor_msgs/msg/JointState",
    encoding: "ros2msg",
    data: new TextEncoder().encode(JOINTS_ROS2),
  });
  const imuChannel = await writer.registerChannel({ topic: "/imu", messageEncoding: "cdr", schemaId: imuSchema, metadata: new Map() });
  const jointChannel = await writer.registerChannel({ topic: "/joint_states", messageEncoding: "cdr", schemaId: jointSchema, metadata: new Map() });
  const jsonChannel = await writer.registerChannel({ topic: "/status", messageEncoding: "json", schemaId: 0, metadata: new Map() });
  const imuWriter = new Ros2Writer(parse(IMU_ROS2, { ros2: true }));
  const jointWriter = new Ros2Writer(parse(JOINTS_ROS2, { ros2: true }));
  for (let i = 0; i < 50; ++i) {
    const t = at(i, 20000000);
    const stamp = t + 3000000n;
    const header = { stamp: { sec: Number(stamp / 1000000000n), nanosec: Number(stamp % 1000000000n) }, frame_id: "base" };
    await writer.addMessage({ channelId: imuChannel, sequence: i, logTime: t, publishTime: t, data: imuWriter.writeMessage({ header, ...imu(i) }) });
    const joints = {
      header,
      name: ["front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"],
      position: [0, 1, 2, 3].map((k) => value(i, k)),
      velocity: [0, 1, 2, 3].map((k) => value(i, 10 + k)),
      effort: [],
    };
    await writer.addMessage({ channelId: jointChannel, sequence: i, logTime: t, publishTime: t, data: jointWriter.writeMessage(joints) });
    const status = { battery: { voltage: value(i, 40) }, moving: i % 2 === 0, mode: "auto", temps: [value(i, 41), value(i, 42)] };
    await writer.addMessage({ channelId: jsonChannel, sequence: i, logTime: t, publishTime: t, data: new TextEncoder().encode(JSON.stringify(status)) });
  }
}

await zstd.isLoaded;
for (const compression of ["none", "zstd", "lz4"]) {
  await write(`imu_ros1_${compression}.mcap`, { compression }, (w) => ros1Imu(w, 100, 10000000));
}
await write("imu_ros1_zstd_no_summary.mcap", { compression: "zstd", summary: false }, (w) => ros1Imu(w, 100, 10000000));
await write("imu_ros1_unchunked_no_summary.mcap", { chunks: false, summary: false }, (w) => ros1Imu(w, 100, 10000000));
await write("rover_cdr_json_lz4.mcap", { compression: "lz4" }, ros2Rover);
await write("ranged_zstd.mcap", { compression: "zstd", chunkSize: 8192 }, (w) => ros1Imu(w, 1000, 10000000));
await write("unknown_encoding.mcap", {}, async (w) => {
  const schemaId = await w.registerSchema({ name: "pkg.Thing", encoding: "protobuf", data: new Uint8Array([1, 2, 3]) });
  const channelId = await w.registerChannel({ topic: "/thing", messageEncoding: "protobuf", schemaId, metadata: new Map() });
  await w.addMessage({ channelId, sequence: 0, logTime: START, publishTime: START, data: new Uint8Array([8, 1]) });
});
