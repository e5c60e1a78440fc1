// SPDX-License-Identifier: MIT
// Writes the messages a manifest lists as a ROS 2 recording, with the MCAP and Foxglove projects'
// own writers:
//   node write_ros2.mjs MANIFEST.json OUT
// MANIFEST: {"format": "mcap" | "cdr", "compression": "none" | "lz4" | "zstd", "chunk_size": N,
//            "chunked": true | false, "raw": FILE, "messages": [{"topic", "type" ("sensor_msgs/msg/Image"), "log_time" (ns,
//            a string), "message" (the fields, as JSON), "data": [offset, length] (optional: the
//            message's uint8[] data, from the raw file)}]}
// mcap: one MCAP file (@mcap/core: chunked, with message and chunk indexes, unless "chunked" is
// false: messages in the data section, no index), schemas in ros2msg,
// messages in cdr. cdr: the messages' CDR bytes one after the other, each after its length (u32,
// little-endian), for a test to put into a rosbag2 SQLite file.
import { open, readFile, writeFile } from "node:fs/promises";
import { McapWriter } from "@mcap/core";
import lz4 from "lz4js";
import * as zstd from "@foxglove/wasm-zstd";
import { schemaText, serialize } from "./ros2_definitions.mjs";

const [manifestPath, outPath] = process.argv.slice(2);
const manifest = JSON.parse(await readFile(manifestPath, "utf8"));
const raw = manifest.raw ? await readFile(manifest.raw) : null;

function cdr(entry) {
  const message = entry.message;
  if (entry.data) message.data = raw.subarray(entry.data[0], entry.data[0] + entry.data[1]);
  return serialize(entry.type, message);
}

if (manifest.format === "cdr") {
  const parts = [];
  for (const entry of manifest.messages) {
    const bytes = cdr(entry);
    const length = Buffer.alloc(4);
    length.writeUInt32LE(bytes.length);
    parts.push(length, bytes);
  }
  await writeFile(outPath, Buffer.concat(parts));
} else {
  await zstd.isLoaded;
  const compressors = {
    none: undefined,
    lz4: (data) => ({ compression: "lz4", compressedData: new Uint8Array(lz4.compress(data)) }),
    zstd: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }),
  };
  const file = await open(outPath, "w");
  let position = 0n;
  const writable = {
    position: () => position,
    write: async (buffer) => {
      await file.write(buffer);
      position += BigInt(buffer.byteLength);
    },
  };
  const writer = new McapWriter({
    writable,
    useChunks: manifest.chunked ?? true,
    chunkSize: manifest.chunk_size ?? 1024 * 1024,
    compressChunk: compressors[manifest.compression ?? "none"],
  });
  await writer.start({ profile: "ros2", library: "dsm tests (@mcap/core)" });
  const channels = new Map();
  let sequence = 0;
  for (const entry of manifest.messages) {
    if (!channels.has(entry.topic)) {
      const schemaId = await writer.registerSchema({
        name: entry.type,
        encoding: "ros2msg",
        data: new TextEncoder().encode(schemaText(entry.type)),
      });
      channels.set(entry.topic, await writer.registerChannel({
        topic: entry.topic, schemaId, messageEncoding: "cdr", metadata: new Map(),
      }));
    }
    const time = BigInt(entry.log_time);
    await writer.addMessage({
      channelId: channels.get(entry.topic), sequence: sequence++, logTime: time, publishTime: time, data: cdr(entry),
    });
  }
  await writer.end();
  await file.close();
}
