// The ecosystem's readers on a tern flight log (issue 44): Foxglove's @mcap/core opens RUN's
// flight.mcap through its summary and indexes (McapIndexedReader), every channel is decoded with
// its own ros2msg schema by @foxglove/rosmsg + @foxglove/rosmsg2-serialization, and every value
// is compared with the flight's CSV tables (CSV_DIR/<topic>.csv): doubles bit for bit (Object.is:
// -0 and NaN included), float32 as the float the CSV's shortest text names, 64-bit integers as
// BigInt, bools as 0/1, the time column as the message's log_time in ns exactly. The statistics'
// counts, the attachments and the footer's summary CRC (checked by the reader) are read too.
//
// usage: node test_mcap_reader.mjs RUN_DIR CSV_DIR
import { McapIndexedReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { decompress } from "fzstd";
import { open } from "node:fs/promises";
import { readFileSync } from "node:fs";
import { join } from "node:path";

const [runDir, csvDir] = process.argv.slice(2);
const fail = (msg) => {
  console.error(`FAIL: ${msg}`);
  process.exit(1);
};

const fh = await open(join(runDir, "flight.mcap"), "r");
const size = (await fh.stat()).size;
const readable = {
  size: async () => BigInt(size),
  read: async (offset, length) => {
    const buf = new Uint8Array(Number(length));
    await fh.read(buf, 0, buf.length, Number(offset));
    return buf;
  },
};
const reader = await McapIndexedReader.Initialize({
  readable,
  decompressHandlers: { zstd: (data, decompressedSize) => decompress(data, new Uint8Array(Number(decompressedSize))) },
});

/// "12.345000000" -> 12345000000n (exact)
const nanos = (cell) => {
  const neg = cell.startsWith("-");
  const [s, f] = (neg ? cell.slice(1) : cell).split(".");
  const v = BigInt(s) * 1000000000n + BigInt(f.padEnd(9, "0"));
  return neg ? -v : v;
};
const number = (cell) => (cell === "nan" || cell === "-nan" ? NaN : cell === "inf" ? Infinity : cell === "-inf" ? -Infinity : Number(cell));
const same = (type, cell, value) => {
  switch (type) {
    case "float64": return Object.is(number(cell), value);
    case "float32": return Object.is(Math.fround(number(cell)), value);
    case "int64": case "uint64": return BigInt(cell) === BigInt(value);
    case "bool": return (cell === "1") === value && (cell === "0" || cell === "1");
    default: return Number(cell) === value;  // 8 to 32-bit integers
  }
};

/// A topic's copy in its ROS type (tern.topic: /tern/estimated_state is rosplane_msgs/msg/State
/// of topic state): every message decoded with the file's schema, one per tern message (a
/// waypoint list: a clear, then one per waypoint), header.stamp equal to the tern message's stamp,
/// and for the state the ROSplane fields equal to the float of tern's columns.
const CHECKED = { "rosplane_msgs/msg/State": { p_n: "p_n", p_e: "p_e", p_d: "p_d", va: "Va", chi: "chi", phi: "phi" } };
const STAMP = { "rosflight_msgs/msg/GNSS": "time_of_validity" };  // rosflight_io stamps a fix with its time (convert_ros.cpp)
const rosCopy = async (channel, schema, tern) => {
  const decoder = new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true }));
  const lines = readFileSync(join(csvDir, `${tern}.csv`), "utf8").split("\n").filter((l) => l.length > 0);
  const header = lines[0].split(",").map((h) => h.slice(0, h.lastIndexOf(" [")));
  const messages = [];
  for await (const m of reader.readMessages({ topics: [channel.topic] })) if (m.channelId === channel.id) messages.push(m);
  messages.sort((a, b) => a.sequence - b.sequence);
  const rows = lines.slice(1).map((l) => l.split(","));
  if (schema.name !== "rosplane_msgs/msg/Waypoint" && messages.length !== rows.length)
    fail(`${channel.topic}: ${messages.length} ${schema.name} messages, ${rows.length} rows of ${tern}`);
  const stampCol = header.indexOf(STAMP[schema.name] ?? "stamp");
  messages.forEach((m, k) => {
    const d = decoder.readMessage(m.data);
    if (schema.name === "rosplane_msgs/msg/Waypoint") return;  // decoded; several per tern message
    const row = rows[k];
    const stamp = BigInt(d.header.stamp.sec) * 1000000000n + BigInt(d.header.stamp.nanosec);
    if (stampCol >= 0 && stamp !== BigInt(row[stampCol])) fail(`${channel.topic} #${k}: header.stamp ${stamp}, ${tern}.${header[stampCol]} ${row[stampCol]}`);
    for (const [field, column] of Object.entries(CHECKED[schema.name] ?? {}))
      if (!Object.is(Math.fround(number(row[header.indexOf(column)])), d[field]))
        fail(`${channel.topic} #${k}: ${field} ${d[field]}, ${tern}.${column} ${row[header.indexOf(column)]}`);
  });
  return messages.length;
};

let total = 0, values = 0, rosChannels = 0, sceneChannels = 0;
for (const channel of reader.channelsById.values()) {
  const schema = reader.schemasById.get(channel.schemaId);
  if (schema.encoding !== "ros2msg" || channel.messageEncoding !== "cdr") fail(`${channel.topic}: ${schema.encoding}/${channel.messageEncoding}`);
  if (channel.metadata.has("tern.scene")) {  // the 3-D scene (scene_channels.hpp): decoded here, checked by test_foxglove_scene.mjs
    const decoder = new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true }));
    let n = 0;
    for await (const m of reader.readMessages({ topics: [channel.topic] })) if (m.channelId === channel.id && decoder.readMessage(m.data)) ++n;
    if ((reader.statistics.channelMessageCounts.get(channel.id) ?? 0n) !== BigInt(n)) fail(`${channel.topic}: statistics' count`);
    total += n;
    ++sceneChannels;
    continue;
  }
  if (channel.metadata.has("tern.topic")) {
    const n = await rosCopy(channel, schema, channel.metadata.get("tern.topic"));
    if ((reader.statistics.channelMessageCounts.get(channel.id) ?? 0n) !== BigInt(n)) fail(`${channel.topic}: statistics' count`);
    total += n;
    ++rosChannels;
    continue;
  }
  const definitions = parse(new TextDecoder().decode(schema.data), { ros2: true });
  const fields = definitions[0].definitions.filter((d) => !d.isConstant);
  const decoder = new MessageReader(definitions);
  const topic = channel.topic.replace(/^\//, "");
  const lines = readFileSync(join(csvDir, `${topic}.csv`), "utf8").split("\n").filter((l) => l.length > 0);
  const header = lines[0].split(",");
  if (header.length !== fields.length + 1) fail(`${topic}: ${fields.length} schema fields, ${header.length - 1} CSV columns`);
  fields.forEach((f, i) => {
    // ROS 2 field names are lower case (tern's cdr_columns.hpp): column "Va [m/s]" is field va
    const column = header[i + 1].slice(0, header[i + 1].lastIndexOf(" [")).toLowerCase().replace(/[^a-z0-9]+/g, "_").replace(/^_|_$/g, "");
    if (!f.name.startsWith(column)) fail(`${topic}: field ${f.name} is CSV column '${header[i + 1]}'`);
  });
  const messages = [];
  for await (const m of reader.readMessages({ topics: [channel.topic] })) if (m.channelId === channel.id) messages.push(m);
  messages.sort((a, b) => a.sequence - b.sequence);
  if (messages.length !== lines.length - 1) fail(`${topic}: ${messages.length} messages, ${lines.length - 1} CSV rows`);
  messages.forEach((m, k) => {
    const cells = lines[k + 1].split(",");
    if (nanos(cells[0]) !== m.logTime) fail(`${topic} row ${k + 1}: t ${cells[0]} s, log_time ${m.logTime} ns`);
    const decoded = decoder.readMessage(m.data);
    fields.forEach((f, i) => {
      if (!same(f.type, cells[i + 1], decoded[f.name]))
        fail(`${topic} row ${k + 1} ${f.name} (${f.type}): CSV ${cells[i + 1]}, decoded ${decoded[f.name]}`);
      ++values;
    });
  });
  if ((reader.statistics.channelMessageCounts.get(channel.id) ?? 0n) !== BigInt(messages.length)) fail(`${topic}: statistics' count`);
  total += messages.length;
}
if (reader.statistics.messageCount !== BigInt(total)) fail(`statistics: ${reader.statistics.messageCount} messages, ${total} read`);
const attachments = reader.attachmentIndexes.map((a) => a.name).sort().join(",");
if (attachments !== "config.yaml,definitions.json,params.csv,summary.json") fail(`attachments: ${attachments}`);
if (process.env.TERN_MCAP_ROS_CHANNELS === "1" && rosChannels === 0) fail("no ROS-typed channel (a tern built with Fast DDS writes them)");
console.log(`@mcap/core + rosmsg2-serialization: ${reader.channelsById.size} channels (${rosChannels} in ROS types, ${sceneChannels} of the 3-D scene), ${total} messages, ${values} values equal to the CSV tables`);
await fh.close();
