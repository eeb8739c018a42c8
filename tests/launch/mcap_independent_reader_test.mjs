// run.mcap read by an MCAP reader haptex did not write: @mcap/core's indexed reader (through the
// summary and chunk indexes, CRCs checked) and its stream reader, with every message decoded by
// protobufjs from the FileDescriptorSet in its channel's schema alone. The run is a short real one
// (`haptex launch`); per-channel counts must equal summary.json's. Fails (never skips) when node's
// packages are missing: scripts/setup installs them (cd web && npm ci).
//
// usage: node mcap_independent_reader_test.mjs NODE_MODULES HAPTEX SCENE RUN_DIR
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";

function fail(message) {
  console.error(`FAIL: ${message}`);
  process.exit(1);
}
function check(condition, message) {
  if (!condition) fail(message);
}

const [nodeModules, haptex, scene, runDir] = process.argv.slice(2);
check(runDir !== undefined, "usage: node mcap_independent_reader_test.mjs NODE_MODULES HAPTEX SCENE RUN_DIR");

// the packages, from web/'s node_modules
const require = createRequire(path.join(path.resolve(nodeModules), "noop.js"));
function load(name) {
  try {
    return require(name);
  } catch (e) {
    fail(`cannot load ${name} from ${nodeModules} (run: cd web && npm ci --no-audit --no-fund): ${e.message}`);
  }
}
const { McapIndexedReader, McapStreamReader } = load("@mcap/core");
const protobuf = load("protobufjs");
const descriptor = load("protobufjs/ext/descriptor");

// a short real run
fs.rmSync(runDir, { recursive: true, force: true });
const launch = spawnSync(haptex, ["launch", scene, "--duration", "3", "--no-plots", "--out", runDir], {
  encoding: "utf8",
  timeout: 180_000,
});
check(launch.error === undefined, `haptex launch did not run: ${launch.error}`);
check(launch.status === 0, `haptex launch exited ${launch.status}\n${launch.stdout}\n${launch.stderr}`);
const summary = JSON.parse(fs.readFileSync(path.join(runDir, "summary.json"), "utf8"));
const recording = summary.recording;
check(recording && recording.mcap === "run.mcap", `summary.json has no run.mcap: ${JSON.stringify(recording)}`);
const mcapPath = path.join(runDir, recording.mcap);

// decoders from each schema's FileDescriptorSet, and nothing else
const decoders = new Map(); // schema id -> protobufjs Type
function decoderFor(schema) {
  if (!decoders.has(schema.id)) {
    check(schema.encoding === "protobuf", `schema ${schema.name}: encoding ${schema.encoding}`);
    const set = descriptor.FileDescriptorSet.decode(schema.data);
    const root = protobuf.Root.fromDescriptor(set);
    decoders.set(schema.id, root.lookupType(schema.name));
  }
  return decoders.get(schema.id);
}

// 1. the indexed reader: footer, summary, chunk indexes, message indexes
const handle = await fs.promises.open(mcapPath, "r");
const readable = {
  size: async () => BigInt((await handle.stat()).size),
  read: async (offset, size) => {
    const buffer = new Uint8Array(Number(size));
    const { bytesRead } = await handle.read(buffer, 0, Number(size), Number(offset));
    check(bytesRead === Number(size), `short read at ${offset}`);
    return buffer;
  },
};
const reader = await McapIndexedReader.Initialize({ readable });
check(reader.header.library === "haptex", `header library ${reader.header.library}`);
check(reader.chunkIndexes.length > 0, "no chunk indexes in the summary");
check(reader.statistics !== undefined, "no statistics in the summary");
check(reader.summaryOffsetsByOpcode.size > 0, "no summary offsets");

const counts = {};
const nonEmpty = {};
let previousLogTime = -1n;
for await (const message of reader.readMessages({ validateCrcs: true })) {
  const channel = reader.channelsById.get(message.channelId);
  check(channel !== undefined, `message on unknown channel ${message.channelId}`);
  check(channel.messageEncoding === "protobuf", `${channel.topic}: message encoding ${channel.messageEncoding}`);
  check(message.logTime >= previousLogTime, `${channel.topic}: log times go back`);
  previousLogTime = message.logTime;
  const schema = reader.schemasById.get(channel.schemaId);
  check(schema !== undefined, `${channel.topic}: no schema ${channel.schemaId}`);
  let decoded;
  try {
    decoded = decoderFor(schema).decode(message.data);
  } catch (e) {
    fail(`${channel.topic}: a message does not decode as ${schema.name}: ${e.message}`);
  }
  counts[channel.topic] = (counts[channel.topic] ?? 0) + 1;
  if (Object.keys(decoded.toJSON()).length > 0) nonEmpty[channel.topic] = true;
}
await handle.close();

const expected = recording.channels;
check(Object.keys(expected).length > 0, "summary.json counts no channels");
check(
  JSON.stringify(Object.keys(counts).sort()) === JSON.stringify(Object.keys(expected).sort()),
  `topics differ: run.mcap ${Object.keys(counts).sort()} summary.json ${Object.keys(expected).sort()}`,
);
let total = 0;
for (const [topic, n] of Object.entries(expected)) {
  check(counts[topic] === n, `${topic}: ${counts[topic]} messages in run.mcap, summary.json says ${n}`);
  check(nonEmpty[topic], `${topic}: every message decoded empty`);
  total += n;
}
check(total === recording.messages, `summary.json: ${recording.messages} messages, its channels sum to ${total}`);
check(reader.statistics.messageCount === BigInt(total), `statistics: ${reader.statistics.messageCount} messages`);
for (const [id, n] of reader.statistics.channelMessageCounts) {
  const topic = reader.channelsById.get(id).topic;
  check(BigInt(expected[topic]) === n, `statistics: ${topic} ${n}, summary.json ${expected[topic]}`);
}
for (const topic of ["/device_bridge/finger_states", "/local_contact/force_model", "/tactile/pin_frame"]) {
  check(topic in expected, `no ${topic} channel`);
}

// 2. the stream reader, start to end, CRCs checked
const stream = new McapStreamReader({ validateCrcs: true });
stream.append(fs.readFileSync(mcapPath));
let streamed = 0;
let sawDataEnd = false;
let sawFooter = false;
for (let record; (record = stream.nextRecord()); ) {
  if (record.type === "Message") streamed += 1;
  if (record.type === "DataEnd") sawDataEnd = true;
  if (record.type === "Footer") sawFooter = true;
}
check(stream.done(), "the stream reader did not reach the end");
check(sawDataEnd && sawFooter, "no Data End or Footer");
check(streamed === total, `stream reader: ${streamed} messages, summary.json ${total}`);

console.log(`run.mcap: ${total} messages on ${Object.keys(counts).length} channels, all decoded; counts match summary.json`);
for (const [topic, n] of Object.entries(counts).sort()) console.log(`  ${topic}: ${n}`);
