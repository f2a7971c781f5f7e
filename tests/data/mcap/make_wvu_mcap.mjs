// Writes wvu_pathfinder_ros1.mcap: the bundled WVU Pathfinder log
// (tests/data/test17run.mat) as a rover running ROS would have recorded it,
// laid out as resources/mappings/ros_pathfinder.json says (the same topics as
// the bag tests/app/ros_bag_cli_test.cpp writes), with the MCAP project's
// own writer and Foxglove's ROS 1 serialiser, zstd chunks. The message
// definitions are ROS's own (ros1msg/*.msg, printed from Debian's
// libsensor-msgs-dev and libnav-msgs-dev headers; BSD licence, ROS common_msgs).
//
// Regenerate (from the repository root, after a build; versions as in make_fixtures.mjs):
//   for s in imu wheels gps odometry; do
//     build/app/roverlab convert tests/data/test17run.mat /tmp/wvu_$s.csv -m wvu_pathfinder -s $s; done
//   cd tests/data/mcap && npm install --no-save @mcap/core@2.2.2 @foxglove/rosmsg@5.0.5 \
//     @foxglove/rosmsg-serialization@2.0.4 @foxglove/wasm-zstd@1.0.1 \
//     && node make_wvu_mcap.mjs /tmp/wvu_ && rm -rf node_modules package-lock.json
//
// Times: each message's log time and header.stamp are the log's seconds to
// the nanosecond after 1566770959.742861032 s (the MATLAB file's first sample).
import { McapWriter } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageWriter } from "@foxglove/rosmsg-serialization";
import * as zstd from "@foxglove/wasm-zstd";
import { readFileSync, writeFileSync } from "node:fs";

const prefix = process.argv[2];
const ORIGIN = 1566770959742861032n;

function csv(stream) {
  const lines = readFileSync(`${prefix}${stream}.csv`, "utf8").trim().split("\n");
  const names = lines[0].split(",").map((h) => h.replace(/ \[.*\]$/, ""));
  const rows = lines.slice(1).map((l) => l.split(",").map(Number));
  const col = Object.fromEntries(names.map((n, k) => [n, rows.map((r) => r[k])]));
  return col;
}

const stamp = (t) => {
  const ns = ORIGIN + BigInt(Math.round(t * 1e9));
  return { ns, ros: { sec: Number(ns / 1000000000n), nsec: Number(ns % 1000000000n) } };
};

await zstd.isLoaded;
const imu = csv("imu");
const wheels = csv("wheels");
const gps = csv("gps");
const odometry = csv("odometry");

const chunks = [];
let size = 0n;
const writer = new McapWriter({
  writable: { write: async (b) => { chunks.push(Buffer.from(b)); size += BigInt(b.byteLength); }, position: () => size },
  chunkSize: 256 * 1024,
  compressChunk: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 19) }),
});
await writer.start({ profile: "ros1", library: "roverlab make_wvu_mcap.mjs" });
const channels = {};
const writers = {};
for (const [topic, type, file] of [
  ["/imu/data", "sensor_msgs/Imu", "Imu"],
  ["/joint_states", "sensor_msgs/JointState", "JointState"],
  ["/navsat/fix", "sensor_msgs/NavSatFix", "NavSatFix"],
  ["/odometry/gps", "nav_msgs/Odometry", "Odometry"],
  ["/odom", "nav_msgs/Odometry", "Odometry"],
]) {
  const text = readFileSync(new URL(`ros1msg/${file}.msg`, import.meta.url), "utf8");
  const schemaId = await writer.registerSchema({ name: type, encoding: "ros1msg", data: new TextEncoder().encode(text) });
  channels[topic] = await writer.registerChannel({ topic, messageEncoding: "ros1", schemaId, metadata: new Map() });
  writers[topic] = new MessageWriter(parse(text));
}
const zero3 = { x: 0, y: 0, z: 0 };
const covariance = Array(36).fill(0);
let sequence = 0;
const add = async (topic, ns, message) => {
  await writer.addMessage({ channelId: channels[topic], sequence: sequence++, logTime: ns, publishTime: ns,
                            data: writers[topic].writeMessage(message) });
};
let i = 0;
let w = 0;
const nImu = imu.time.length;
const nWheels = wheels.time.length;
while (i < nImu || w < nWheels) {
  if (i < nImu && (w >= nWheels || imu.time[i] <= wheels.time[w])) {
    const t = stamp(imu.time[i]);
    await add("/imu/data", t.ns, {
      header: { seq: i, stamp: t.ros, frame_id: "" },
      orientation: { x: 0, y: 0, z: 0, w: 0 },
      orientation_covariance: [-1, 0, 0, 0, 0, 0, 0, 0, 0],
      angular_velocity: { x: imu.angular_rate_x[i], y: imu.angular_rate_y[i], z: imu.angular_rate_z[i] },
      angular_velocity_covariance: Array(9).fill(0),
      linear_acceleration: { x: imu.specific_force_x[i], y: imu.specific_force_y[i], z: imu.specific_force_z[i] },
      linear_acceleration_covariance: Array(9).fill(0),
    });
    ++i;
    continue;
  }
  const t = stamp(wheels.time[w]);
  const header = { seq: 0, stamp: t.ros, frame_id: "" };
  await add("/joint_states", t.ns, {
    header,
    name: ["front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"],
    position: [wheels.angle_FL[w], wheels.angle_FR[w], wheels.angle_RL[w], wheels.angle_RR[w]],
    velocity: [],
    effort: [],
  });
  await add("/navsat/fix", t.ns, {
    header,
    status: { status: 0, service: 0 },
    latitude: (gps.latitude[w] * 180) / Math.PI,
    longitude: (gps.longitude[w] * 180) / Math.PI,
    altitude: gps.height[w],
    position_covariance: Array(9).fill(0),
    position_covariance_type: 0,
  });
  const odom = (x, y, z, speed, yawRate) => ({
    header,
    child_frame_id: "",
    pose: { pose: { position: { x, y, z }, orientation: { x: 0, y: 0, z: 0, w: 1 } }, covariance },
    twist: { twist: { linear: { x: speed, y: 0, z: 0 }, angular: { x: 0, y: 0, z: yawRate } }, covariance },
  });
  await add("/odometry/gps", t.ns, odom(gps.east[w], gps.north[w], gps.up[w], 0, 0));
  await add("/odom", t.ns, odom(odometry.x[w], odometry.y[w], 0, odometry.forward_speed[w], odometry.yaw_rate[w]));
  ++w;
}
await writer.end();
const out = new URL("wvu_pathfinder_ros1.mcap", import.meta.url);
writeFileSync(out, Buffer.concat(chunks));
console.log("wvu_pathfinder_ros1.mcap", Number(size), "bytes");
