// Message count and sizes per channel of an MCAP file (a run's run.mcap), read with @mcap/core:
// what each topic costs on the wire and on disk.
//   node web/tools/mcap_channel_sizes.mjs RUN_FOLDER/run.mcap
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";

const requireFromWeb = createRequire(new URL("../package.json", import.meta.url));
const { McapStreamReader } = requireFromWeb("@mcap/core");

const [path] = process.argv.slice(2);
if (!path) {
  console.error("usage: mcap_channel_sizes.mjs FILE.mcap");
  process.exit(2);
}
const reader = new McapStreamReader();
reader.append(readFileSync(path));
const topics = new Map();
const sizes = new Map();
for (let record; (record = reader.nextRecord());) {
  if (record.type === "Channel") topics.set(record.id, record.topic);
  if (record.type === "Message") {
    const topic = topics.get(record.channelId);
    if (!sizes.has(topic)) sizes.set(topic, []);
    sizes.get(topic).push(record.data.byteLength);
  }
}
console.log("topic messages median_bytes largest_bytes total_bytes");
for (const [topic, list] of [...sizes].sort()) {
  list.sort((a, b) => a - b);
  const total = list.reduce((a, b) => a + b, 0);
  console.log(`${topic} ${list.length} ${list[list.length >> 1]} ${list[list.length - 1]} ${total}`);
}
