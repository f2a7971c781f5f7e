// Writes kapvik_ros1_zstd.mcap and kapvik_cdr_lz4_no_summary.mcap: the planar
// rocker-bogie log that tests/importers/kapvik_ros_log.h describes (IMU,
// JointState, TwistStamped, three WrenchStamped, TFMessage), ROS 1 encoded in
// zstd chunks with a summary, and ROS 2 (CDR) encoded in lz4 chunks without
// one, by the MCAP project's own writer (@mcap/core) and Foxglove's ROS 1 and
// ROS 2 serialisers. Read by tests/importers/mcap_test.cpp through
// resources/mappings/ros_kapvik.json. The fixtures are committed.
//
// Regenerate as make_fixtures.mjs says (the same npm packages), then
//   node make_kapvik_mcap.mjs
import { McapWriter } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageWriter as Ros1Writer } from "@foxglove/rosmsg-serialization";
import { MessageWriter as Ros2Writer } from "@foxglove/rosmsg2-serialization";
import * as zstd from "@foxglove/wasm-zstd";
import lz4 from "lz4js";
import { writeFileSync } from "node:fs";

const value = (i, k) => 0.1 * i + 1e-7 * k - 3.3;
const START = 1700000000250000000n; // ns
const COUNT = 40;
const SEP = "\n================================================================================\n";

// ROS 1 (ros1msg) and ROS 2 (ros2msg) definitions, as the bag and rosbag2 carry them.
const defs = (ros2) => {
  const header = ros2
    ? "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id" + SEP + "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec"
    : "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id";
  const h = ros2 ? "std_msgs/Header header" : "Header header";
  const vector3 = "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z";
  const quaternion = "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w";
  return {
    "sensor_msgs/Imu": [
      `${h}\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance`,
      header, quaternion, vector3,
    ].join(SEP),
    "sensor_msgs/JointState": [`${h}\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort`, header].join(SEP),
    "geometry_msgs/TwistStamped": [`${h}\ngeometry_msgs/Twist twist`, header, "MSG: geometry_msgs/Twist\nVector3 linear\nVector3 angular", vector3].join(SEP),
    "geometry_msgs/WrenchStamped": [`${h}\ngeometry_msgs/Wrench wrench`, header, "MSG: geometry_msgs/Wrench\nVector3 force\nVector3 torque", vector3].join(SEP),
    "tf2_msgs/TFMessage": [
      "geometry_msgs/TransformStamped[] transforms",
      `MSG: geometry_msgs/TransformStamped\n${h}\nstring child_frame_id\nTransform transform`,
      header, "MSG: geometry_msgs/Transform\nVector3 translation\nQuaternion rotation", vector3, quaternion,
    ].join(SEP),
  };
};

function messages(i, stamp) {
  const header = (frame) => ({ seq: i, stamp, frame_id: frame });
  const cov = Array(9).fill(0);
  const out = [
    ["/imu/data", "sensor_msgs/Imu", {
      header: header("imu"), orientation: { x: 0, y: 0, z: 0, w: 1 }, orientation_covariance: cov,
      angular_velocity: { x: 0, y: value(i, 4), z: 0 }, angular_velocity_covariance: cov,
      linear_acceleration: { x: value(i, 0), y: 0, z: value(i, 2) }, linear_acceleration_covariance: cov }],
    ["/joint_states", "sensor_msgs/JointState", {
      header: header(""), name: ["wheel_1", "bogie", "wheel_2", "wheel_3"],
      position: [0, 1, 2, 3].map((k) => value(i, 10 + k)), velocity: [], effort: [] }],
    ["/joint_commands", "sensor_msgs/JointState", {
      header: header(""), name: ["wheel_1", "wheel_2", "wheel_3"], position: [], velocity: [],
      effort: [0, 1, 2].map((k) => value(i, 20 + k)) }],
    ["/velocimeter", "geometry_msgs/TwistStamped", {
      header: header("base_link"), twist: { linear: { x: value(i, 30), y: 0, z: 0 }, angular: { x: 0, y: value(i, 31), z: 0 } } }],
  ];
  for (let w = 0; w < 3; ++w) {
    out.push([`/wheel_${w + 1}/wrench`, "geometry_msgs/WrenchStamped", {
      header: header(`wheel_${w + 1}`),
      wrench: { force: { x: value(i, 40 + w), y: 0, z: value(i, 50 + w) }, torque: { x: 0, y: value(i, 60 + w), z: 0 } } }]);
  }
  const mast = { header: header("base_link"), child_frame_id: "mast",
    transform: { translation: { x: value(i, 79), y: 0, z: 0 }, rotation: { x: 0, y: 0, z: 0, w: 1 } } };
  const pitch = 0.01 * i;
  const base = { header: header("odom"), child_frame_id: "base_link",
    transform: { translation: { x: value(i, 70), y: value(i, 71), z: value(i, 72) },
      rotation: { x: 0, y: Math.sin(pitch / 2), z: 0, w: Math.cos(pitch / 2) } } };
  const transforms = i % 4 === 3 ? [mast] : i % 2 === 1 ? [mast, base] : [base, mast];
  out.push(["/tf", "tf2_msgs/TFMessage", { transforms }]);
  return out;
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

async function write(file, ros2, compression, summary) {
  const sink = new Sink();
  const writer = new McapWriter({
    writable: sink, useChunks: true, chunkSize: 4096, compressChunk: compression,
    useStatistics: summary, useChunkIndex: summary, useMessageIndex: summary, useSummaryOffsets: summary,
    repeatSchemas: summary, repeatChannels: summary, useAttachmentIndex: summary, useMetadataIndex: summary,
  });
  await writer.start({ profile: ros2 ? "ros2" : "ros1", library: "roverlab make_kapvik_mcap.mjs" });
  const definitions = defs(ros2);
  const schemas = {};
  const serialisers = {};
  for (const [type, text] of Object.entries(definitions)) {
    const name = ros2 ? type.replace("/", "/msg/") : type;
    schemas[type] = await writer.registerSchema({ name, encoding: ros2 ? "ros2msg" : "ros1msg", data: new TextEncoder().encode(text) });
    serialisers[type] = ros2 ? new Ros2Writer(parse(text, { ros2: true })) : new Ros1Writer(parse(text));
  }
  const channels = {};
  for (let i = 0; i < COUNT; ++i) {
    const t = START + BigInt(i) * 50000000n;
    const stamp = ros2
      ? { sec: Number(t / 1000000000n), nanosec: Number(t % 1000000000n) }
      : { sec: Number(t / 1000000000n), nsec: Number(t % 1000000000n) };
    for (const [topic, type, message] of messages(i, stamp)) {
      if (channels[topic] === undefined) {
        channels[topic] = await writer.registerChannel({
          topic, messageEncoding: ros2 ? "cdr" : "ros1", schemaId: schemas[type], metadata: new Map() });
      }
      await writer.addMessage({ channelId: channels[topic], sequence: i, logTime: t, publishTime: t,
        data: serialisers[type].writeMessage(message) });
    }
  }
  await writer.end();
  const bytes = Buffer.concat(sink.chunks);
  writeFileSync(file, bytes);
  console.log(file, bytes.length, "bytes");
}

await zstd.isLoaded;
await write("kapvik_ros1_zstd.mcap", false, (d) => ({ compression: "zstd", compressedData: zstd.compress(d, 3) }), true);
await write("kapvik_cdr_lz4_no_summary.mcap", true, (d) => ({ compression: "lz4", compressedData: lz4.compress(d) }), false);
