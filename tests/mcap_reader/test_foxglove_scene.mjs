// Foxglove's 3-D panel on a tern flight log (issue 65; core/formats/ros/scene_channels.hpp), read
// with Foxglove's own libraries as the panel reads it: @mcap/core opens RUN's flight.mcap, the
// scene's channels are decoded with their ros2msg schemas (@foxglove/rosmsg,
// @foxglove/rosmsg2-serialization), and:
//   - each scene schema's types are field for field ROS 2 Jazzy's (@foxglove/rosmsg-msgs-common)
//   - /tf: map -> base_link at every truth message copied equals truth's position in ENU (e, n, -d)
//     and its attitude as FLU in ENU, bit for bit; map -> map_estimate -> base_link_estimate at
//     every state message, its position the state's in ENU
//   - the aircraft model: a truth and an estimate model, boxes frame-locked to base_link and
//     base_link_estimate, the wing as wide as the aircraft file's span b
//   - the track, mission, current path and wind markers decode, are non-empty and finite
//   - the layout file parses and names only channels, fields and frames the log has
// A fleet vehicle's log (PREFIX "uav1/"): its frames and marker namespaces under the prefix; the
// layout (one vehicle's, following base_link) is not checked against it.
//
// usage: node test_foxglove_scene.mjs RUN_DIR LAYOUT_JSON AIRCRAFT_YAML [PREFIX]
import { McapIndexedReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { ros2jazzy } from "@foxglove/rosmsg-msgs-common";
import { decompress } from "fzstd";
import { open } from "node:fs/promises";
import { readFileSync } from "node:fs";
import { join } from "node:path";

const [runDir, layoutFile, aircraftFile, prefix = ""] = process.argv.slice(2);
const fail = (msg) => {
  console.error(`FAIL: ${msg}`);
  process.exit(1);
};

const fh = await open(join(runDir, "flight.mcap"), "r");
const size = (await fh.stat()).size;
const reader = await McapIndexedReader.Initialize({
  readable: {
    size: async () => BigInt(size),
    read: async (offset, length) => {
      const buf = new Uint8Array(Number(length));
      await fh.read(buf, 0, buf.length, Number(offset));
      return buf;
    },
  },
  decompressHandlers: { zstd: (data, n) => decompress(data, new Uint8Array(Number(n))) },
});

const channels = new Map([...reader.channelsById.values()].map((c) => [c.topic, c]));
const definitionsOf = (channel) => parse(new TextDecoder().decode(reader.schemasById.get(channel.schemaId).data), { ros2: true });
/// Every message of `topic`, decoded, with its log time.
const read = async (topic) => {
  const channel = channels.get(topic);
  if (!channel) fail(`no channel ${topic}`);
  const decoder = new MessageReader(definitionsOf(channel));
  const out = [];
  for await (const m of reader.readMessages({ topics: [topic] })) out.push({ t: m.logTime, seq: m.sequence, msg: decoder.readMessage(m.data) });
  return out.sort((a, b) => (a.t === b.t ? a.seq - b.seq : a.t < b.t ? -1 : 1));
};

// ---- the schemas are ROS 2's ----
const norm = (type) => ({ "builtin_interfaces/Time": "time", "builtin_interfaces/Duration": "duration" })[type.replace("/msg/", "/")] ?? type.replace("/msg/", "/");
const fieldsOf = (d) => d.definitions.map((f) => `${f.isConstant ? "const " : ""}${norm(f.type)}${f.isArray ? "[]" : ""} ${f.name}${f.isConstant ? `=${f.value}` : ""}`).join("; ");
for (const [topic, type] of [["/tf", "tf2_msgs/TFMessage"], ["/tern/markers/aircraft", "visualization_msgs/MarkerArray"]]) {
  const schema = reader.schemasById.get(channels.get(topic)?.schemaId ?? -1);
  if (!schema || schema.name !== type.replace("/", "/msg/") || schema.encoding !== "ros2msg") fail(`${topic}: schema ${schema?.name} ${schema?.encoding}`);
  const defs = definitionsOf(channels.get(topic));
  defs.forEach((d, k) => {
    const name = k === 0 ? type : norm(d.name);
    if (name === "time" || name === "duration") return;
    if (!ros2jazzy[name]) fail(`${topic}: ${name} is not a ROS 2 type`);
    if (fieldsOf(d) !== fieldsOf(ros2jazzy[name])) fail(`${topic}: ${name}:\n  ${fieldsOf(d)}\nROS 2 Jazzy's:\n  ${fieldsOf(ros2jazzy[name])}`);
  });
}

// ---- /tf against truth and the estimate ----
const tf = await read("/tf");
const truth = await read("/truth"), state = await read("/state");
const byChild = new Map();
for (const { t, msg } of tf)
  for (const x of msg.transforms) {
    if (!byChild.has(x.child_frame_id)) byChild.set(x.child_frame_id, []);
    byChild.get(x.child_frame_id).push({ t, x });
  }
const base = byChild.get(`${prefix}base_link`) ?? [], estimate = byChild.get(`${prefix}base_link_estimate`) ?? [];
const origin = byChild.get(`${prefix}map_estimate`) ?? [];
if (base.length !== truth.length || base.length < 10) fail(`/tf: ${base.length} map -> base_link for ${truth.length} truth messages`);
if (estimate.length !== state.length || origin.length !== state.length) fail(`/tf: ${estimate.length} base_link_estimate, ${origin.length} map_estimate for ${state.length} state messages`);
/// A FRD -> NED quaternion (w, x, y, z) as FLU -> ENU: q_enu_ned * q * q_frd_flu (scene_channels.cpp), as [x, y, z, w]
const mul = (a, b) => [a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
  a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]];
const fluInEnu = (m) => {
  const h = Math.sqrt(0.5);
  const q = mul(mul([0, h, h, 0], [m.quat_w, m.quat_x, m.quat_y, m.quat_z]), [0, 1, 0, 0]);
  const n = Math.hypot(...q);
  return [q[1] / n, q[2] / n, q[3] / n, q[0] / n];
};
base.forEach(({ t, x }, k) => {
  const m = truth[k].msg, tr = x.transform.translation, r = x.transform.rotation;
  if (t !== truth[k].t || x.header.frame_id !== "map") fail(`/tf #${k}: ${x.header.frame_id} at ${t} for truth at ${truth[k].t}`);
  if (tr.x !== m.p_e || tr.y !== m.p_n || tr.z !== -m.p_d) fail(`/tf #${k}: base_link at ${tr.x} ${tr.y} ${tr.z}, truth n e d ${m.p_n} ${m.p_e} ${m.p_d}`);
  const want = fluInEnu(m), got = [r.x, r.y, r.z, r.w];
  const dot = want.reduce((s, v, i) => s + v * got[i], 0);  // q and -q are one attitude
  if (Math.abs(Math.abs(dot) - 1) > 1e-12) fail(`/tf #${k}: base_link attitude ${got}, truth's as FLU in ENU ${want}`);
  if (BigInt(x.header.stamp.sec) * 1000000000n + BigInt(x.header.stamp.nanosec) !== m.stamp) fail(`/tf #${k}: stamp, truth's ${m.stamp}`);
});
estimate.forEach(({ x }, k) => {
  const m = state[k].msg, tr = x.transform.translation;
  if (x.header.frame_id !== `${prefix}map_estimate` || tr.x !== m.p_e || tr.y !== m.p_n || tr.z !== -m.p_d) fail(`/tf: base_link_estimate #${k} in ${x.header.frame_id} at ${tr.x} ${tr.y} ${tr.z}`);
});

// ---- the markers ----
const b = Number(/^\s+b:\s*([0-9.eE+-]+)/m.exec(readFileSync(aircraftFile, "utf8"))?.[1]);
const model = (await read("/tern/markers/aircraft")).flatMap((m) => m.msg.markers);
for (const [ns, frame] of [["truth", "base_link"], ["estimate", "base_link_estimate"]]) {
  const boxes = model.filter((m) => m.ns === prefix + ns);
  if (boxes.length !== 4 || boxes.some((m) => m.type !== 1 || m.header.frame_id !== prefix + frame || !m.frame_locked)) fail(`model ${ns}: ${JSON.stringify(boxes.map((m) => [m.type, m.header.frame_id]))}`);
  if (!boxes.some((m) => m.scale.y === b)) fail(`model ${ns}: no box as wide as the span b ${b} of ${aircraftFile}`);
}
const counts = {};
for (const topic of ["/tern/markers/track", "/tern/markers/mission", "/tern/markers/current_path", "/tern/markers/wind"]) {
  const markers = (await read(topic)).flatMap((m) => m.msg.markers);
  const points = markers.flatMap((m) => m.points);
  if (markers.length === 0 || points.length === 0) fail(`${topic}: ${markers.length} markers, ${points.length} points`);
  if (points.some((p) => ![p.x, p.y, p.z].every(Number.isFinite))) fail(`${topic}: a point not finite`);
  counts[topic] = markers.length;
}
const mission = (await read("/tern/markers/mission")).at(-1).msg.markers;
if (!mission.some((m) => m.ns === `${prefix}mission` && m.type === 7 && m.points.length >= 2)) fail("/tern/markers/mission: no waypoints");

// ---- the layout names what the log has ----
const layout = prefix ? { configById: {} } : JSON.parse(readFileSync(layoutFile, "utf8"));
const frames = new Set(["map", ...byChild.keys()]);
let named = 0;
for (const [id, config] of Object.entries(layout.configById)) {
  if (id.startsWith("3D!")) {
    if (!frames.has(config.followTf)) fail(`${layoutFile}: ${id} follows ${config.followTf}, not a frame of the log`);
    for (const topic of Object.keys(config.topics)) if (!channels.has(topic)) fail(`${layoutFile}: ${id} shows ${topic}, not in the log`);
    named += Object.keys(config.topics).length;
  }
  for (const { value } of config.paths ?? []) {
    const [topic, field] = value.split(".");
    const defs = channels.has(topic) ? definitionsOf(channels.get(topic)) : null;
    if (!defs?.[0].definitions.some((f) => f.name === field)) fail(`${layoutFile}: ${id} plots ${value}, not in the log`);
    ++named;
  }
}
console.log(`Foxglove's 3-D scene: ${base.length} map -> base_link equal to truth in ENU/FLU, ${estimate.length} estimates, model ${model.length} boxes (span ${b} m), markers ${JSON.stringify(counts)}; ${layoutFile}: ${named} topics and paths in the log`);
await fh.close();
