// An independent client of FoxgloveServer: Foxglove's own client library (@foxglove/ws-protocol
// over the ws package) connects to foxglove_test_server, subscribes to /cloth and /scene, and
// decodes their messages with protobufjs from nothing but the advertised FileDescriptorSets (types
// built from descriptors keep the .proto field names: snake_case).
// usage: node foxglove_ws_client_test.mjs <foxglove_test_server> <web/node_modules>
// Fails (exit 1), never skips, when node's packages are missing.
import assert from "node:assert/strict";
import { spawn } from "node:child_process";
import { createRequire } from "node:module";
import path from "node:path";
import readline from "node:readline";

const kTimeoutMs = 30000;
const kMessagesPerTopic = 5;
const kPositions = [0, 0, 0, 0.5, 0, 0, 0, 0.25, 0, 0.5, 0.25, 0.125];

function fail(message) {
  console.error(`FAIL: ${message}`);
  process.exit(1);
}

const [serverPath, nodeModules] = process.argv.slice(2);
if (!serverPath || !nodeModules) fail("usage: foxglove_ws_client_test.mjs <foxglove_test_server> <web/node_modules>");

// Resolve packages from web/node_modules, wherever this file is run from.
const requireFromWeb = createRequire(path.join(path.resolve(nodeModules), "resolve-from-here.js"));
let FoxgloveClient, WebSocket, protobuf, descriptor;
try {
  ({ FoxgloveClient } = requireFromWeb("@foxglove/ws-protocol"));
  WebSocket = requireFromWeb("ws");
  protobuf = requireFromWeb("protobufjs");
  descriptor = requireFromWeb("protobufjs/ext/descriptor");
} catch (error) {
  fail(`npm packages missing in ${nodeModules} (scripts/setup installs them: cd web && npm ci): ${error.message}`);
}

const server = spawn(serverPath, ["20"], { stdio: ["ignore", "pipe", "inherit"] });
server.on("error", (error) => fail(`cannot start ${serverPath}: ${error.message}`));
server.on("exit", (code) => {
  if (!finished) fail(`test server exited early with code ${code}`);
});
let finished = false;
const timer = setTimeout(() => fail(`timed out; state: ${JSON.stringify(summary())}`), kTimeoutMs);

const port = await new Promise((resolve) => {
  const lines = readline.createInterface({ input: server.stdout });
  lines.on("line", (line) => {
    const match = /^port (\d+)$/.exec(line);
    if (match) resolve(Number(match[1]));
  });
});

let serverInfo;
const advertised = new Map(); // topic -> channel
const subscriptions = new Map(); // subscription id -> { topic, type }
const received = new Map(); // topic -> [{ timestamp, message }]
const errors = [];

function summary() {
  return {
    serverInfo: serverInfo?.name,
    advertised: [...advertised.keys()],
    received: Object.fromEntries([...received].map(([topic, list]) => [topic, list.length])),
    errors,
  };
}

function typeOf(channel) {
  const set = descriptor.FileDescriptorSet.decode(Buffer.from(channel.schema, "base64"));
  const root = protobuf.Root.fromDescriptor(set);
  return root.lookupType(channel.schemaName);
}

const client = new FoxgloveClient({
  ws: new WebSocket(`ws://127.0.0.1:${port}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]),
});
client.on("error", (error) => errors.push(String(error)));
client.on("serverInfo", (info) => {
  serverInfo = info;
});
client.on("advertise", (channels) => {
  for (const channel of channels) {
    advertised.set(channel.topic, channel);
    if (channel.topic === "/cloth" || channel.topic === "/scene") {
      const type = typeOf(channel);
      subscriptions.set(client.subscribe(channel.id), { topic: channel.topic, type });
    }
  }
});
client.on("message", ({ subscriptionId, timestamp, data }) => {
  const subscription = subscriptions.get(subscriptionId);
  if (!subscription) {
    errors.push(`message for unknown subscription ${subscriptionId}`);
    return;
  }
  const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  const message = subscription.type.toObject(subscription.type.decode(bytes), {
    longs: Number,
    enums: String,
    defaults: true,
    arrays: true,
  });
  const list = received.get(subscription.topic) ?? [];
  list.push({ timestamp, message });
  received.set(subscription.topic, list);
  if (done()) finish();
});

function done() {
  return (
    advertised.has("/late") &&
    (received.get("/cloth")?.length ?? 0) >= kMessagesPerTopic &&
    (received.get("/scene")?.length ?? 0) >= kMessagesPerTopic
  );
}

function closeTo(actual, expected, what) {
  assert.ok(Math.abs(actual - expected) < 1e-6, `${what}: ${actual} != ${expected}`);
}

function check() {
  assert.deepEqual(errors, []);
  assert.equal(serverInfo.name, "haptex-test");
  assert.ok(serverInfo.supportedEncodings.includes("protobuf"));
  for (const [topic, schemaName] of [
    ["/cloth", "haptex.v1.ClothFrame"],
    ["/scene", "foxglove.SceneUpdate"],
    ["/late", "haptex.v1.ClothFrame"],
  ]) {
    const channel = advertised.get(topic);
    assert.equal(channel.encoding, "protobuf", topic);
    assert.equal(channel.schemaName, schemaName, topic);
    assert.equal(channel.schemaEncoding, "protobuf", topic);
  }

  const cloth = received.get("/cloth");
  for (let i = 0; i < cloth.length; ++i) {
    const { timestamp, message } = cloth[i];
    assert.equal(typeof timestamp, "bigint");
    assert.ok(timestamp > 1_600_000_000_000_000_000n, `log time ${timestamp} is not now`);
    if (i > 0) {
      assert.ok(timestamp >= cloth[i - 1].timestamp, "log times go back");
      assert.ok(message.frame_index > cloth[i - 1].message.frame_index, "frame index does not grow");
    }
    assert.equal(message.particles_u, 2);
    assert.equal(message.particles_v, 2);
    assert.equal(message.chunk_count, 1);
    // the documented rule (cloth_frame.proto): x = quantum_m * the running sum of position_q
    assert.equal(message.quantum_m, 1e-6);
    assert.equal(message.position_q.length, kPositions.length);
    const sum = [0, 0, 0];
    message.position_q.forEach((q, k) => {
      sum[k % 3] += q;
      closeTo(message.quantum_m * sum[k % 3], kPositions[k], `position ${k}`);
    });
  }

  for (const { timestamp, message } of received.get("/scene")) {
    assert.equal(message.deletions.length, 0);
    assert.equal(message.entities.length, 1);
    const entity = message.entities[0];
    assert.equal(entity.id, "cloth");
    assert.equal(entity.frame_id, "world");
    assert.equal(BigInt(entity.timestamp.seconds) * 1_000_000_000n + BigInt(entity.timestamp.nanos), timestamp);
    const mesh = entity.triangles[0];
    assert.equal(mesh.points.length, 4);
    mesh.points.forEach((point, k) => {
      closeTo(point.x, kPositions[3 * k], `point ${k}.x`);
      closeTo(point.y, kPositions[3 * k + 1], `point ${k}.y`);
      closeTo(point.z, kPositions[3 * k + 2], `point ${k}.z`);
    });
    assert.deepEqual(mesh.indices, [0, 1, 2, 1, 3, 2]);
    assert.deepEqual(mesh.color, { r: 0.25, g: 0.5, b: 0.75, a: 1 });
    assert.equal(mesh.pose.orientation.w, 1);
    closeTo(entity.arrows[0].shaft_length, 0.05, "arrow shaft length");
    closeTo(entity.arrows[0].pose.position.z, 0.125, "arrow z");
    closeTo(entity.spheres[0].size.x, 0.016, "sphere size");
  }
}

function finish() {
  finished = true;
  clearTimeout(timer);
  try {
    check();
  } catch (error) {
    server.kill();
    fail(`${error.message}\nstate: ${JSON.stringify(summary())}`);
  }
  client.close();
  server.kill();
  console.log(`PASS: ${JSON.stringify(summary())}`);
  process.exit(0);
}
