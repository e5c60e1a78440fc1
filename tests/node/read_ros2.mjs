// SPDX-License-Identifier: MIT
// Reads ROS 2 recordings with the MCAP and Foxglove projects' own readers, printing JSON:
//   node read_ros2.mjs summary FILE.mcap        {"profile", "library", "channels": [{"topic",
//                                                "messageEncoding", "schemaName", "schemaEncoding",
//                                                "count"}], "messageCount", "chunks"}
//   node read_ros2.mjs poses FILE.mcap TOPIC    [[t_ns (string), [x, y, z], [qx, qy, qz, qw]], ...]
//   node read_ros2.mjs cdr-poses TYPE FILE      the same, of CDR messages of TYPE one after the
//                                                other, each after its length (u32, little-endian)
//   node read_ros2.mjs decode FILE.mcap         {TOPIC: {"count", "first", "last"}}: every message
//                                                decoded, the first and last as JSON (byte arrays
//                                                as their length, 64-bit integers as strings)
// Every message of the file is read through @mcap/core's indexed reader (chunks decompressed by
// lz4js and @foxglove/wasm-zstd) and decoded by @foxglove/rosmsg2-serialization from the schema
// the file holds (cdr-poses: the definitions of ros2_definitions.mjs).
import { open, readFile } from "node:fs/promises";
import { McapIndexedReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import lz4 from "lz4js";
import * as zstd from "@foxglove/wasm-zstd";
import { schemaText } from "./ros2_definitions.mjs";

const [command, path, third] = process.argv.slice(2);

async function indexedReader(file) {
  await zstd.isLoaded;
  const handle = await open(file, "r");
  const size = BigInt((await handle.stat()).size);
  const readable = {
    size: async () => size,
    read: async (offset, length) => {
      const buffer = new Uint8Array(Number(length));
      await handle.read(buffer, 0, Number(length), Number(offset));
      return buffer;
    },
  };
  return McapIndexedReader.Initialize({
    readable,
    decompressHandlers: {
      lz4: (buffer, decompressedSize) => new Uint8Array(lz4.decompress(buffer, Number(decompressedSize))),
      zstd: (buffer, decompressedSize) => zstd.decompress(buffer, Number(decompressedSize)),
    },
  });
}

const ns = (stamp) => (BigInt(stamp.sec) * 1000000000n + BigInt(stamp.nanosec)).toString();

// The poses in one decoded message of `type`.
function poses(type, m) {
  const row = (header, p, q) => [ns(header.stamp), [p.x, p.y, p.z], [q.x, q.y, q.z, q.w]];
  switch (type.replace("/msg/", "/")) {
    case "geometry_msgs/PoseStamped": return [row(m.header, m.pose.position, m.pose.orientation)];
    case "geometry_msgs/PoseWithCovarianceStamped":
    case "nav_msgs/Odometry": return [row(m.header, m.pose.pose.position, m.pose.pose.orientation)];
    case "geometry_msgs/TransformStamped": return [row(m.header, m.transform.translation, m.transform.rotation)];
    case "tf2_msgs/TFMessage":
      return m.transforms.map((t) => [...row(t.header, t.transform.translation, t.transform.rotation), t.child_frame_id]);
    default: throw new Error(`not a pose type: ${type}`);
  }
}

if (command === "summary") {
  const reader = await indexedReader(path);
  const counts = new Map();
  let total = 0;
  for await (const message of reader.readMessages()) {
    counts.set(message.channelId, (counts.get(message.channelId) ?? 0) + 1);
    total += 1;
  }
  const channels = [...reader.channelsById.values()].map((c) => {
    const schema = reader.schemasById.get(c.schemaId);
    return { topic: c.topic, messageEncoding: c.messageEncoding, schemaName: schema?.name,
             schemaEncoding: schema?.encoding, count: counts.get(c.id) ?? 0 };
  });
  console.log(JSON.stringify({ profile: reader.header.profile, library: reader.header.library, channels,
                               messageCount: total, chunks: reader.chunkIndexes.length }));
} else if (command === "poses") {
  const reader = await indexedReader(path);
  const channel = [...reader.channelsById.values()].find((c) => c.topic === third);
  const schema = reader.schemasById.get(channel.schemaId);
  const decoder = new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true }));
  const rows = [];
  for await (const message of reader.readMessages({ topics: [third] })) {
    rows.push(...poses(schema.name, decoder.readMessage(message.data)));
  }
  console.log(JSON.stringify(rows));
} else if (command === "cdr-poses") {
  const bytes = await readFile(third);
  const decoder = new MessageReader(parse(schemaText(path), { ros2: true }));
  const rows = [];
  for (let at = 0; at < bytes.length;) {
    const length = bytes.readUInt32LE(at);
    rows.push(...poses(path, decoder.readMessage(bytes.subarray(at + 4, at + 4 + length))));
    at += 4 + length;
  }
  console.log(JSON.stringify(rows));
} else if (command === "decode") {
  const reader = await indexedReader(path);
  const decoders = new Map();
  const topics = {};
  const plain = (key, value) =>
    value instanceof Uint8Array ? value.length : typeof value === "bigint" ? value.toString() : value;
  for await (const message of reader.readMessages()) {
    const channel = reader.channelsById.get(message.channelId);
    if (!decoders.has(channel.schemaId)) {
      const schema = reader.schemasById.get(channel.schemaId);
      decoders.set(channel.schemaId, new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true })));
    }
    const decoded = JSON.parse(JSON.stringify(decoders.get(channel.schemaId).readMessage(message.data), plain));
    const entry = topics[channel.topic] ?? (topics[channel.topic] = { count: 0, first: decoded });
    entry.count += 1;
    entry.last = decoded;
  }
  console.log(JSON.stringify(topics));
} else {
  console.error("usage: node read_ros2.mjs summary FILE | poses FILE TOPIC | cdr-poses TYPE FILE | decode FILE");
  process.exit(2);
}
