// The page's side of the Foxglove WebSocket protocol (v1): takes the server's advertised channels,
// subscribes to those it shows, and hands each message on decoded with the channel's own schema.

import { makeDecoder } from "./proto_decoder.js";

const OP_MESSAGE_DATA = 0x01;

function base64ToBytes(text) {
  const raw = atob(text);
  const out = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; ++i) out[i] = raw.charCodeAt(i);
  return out;
}

/// Connects to `url`; calls onMessage(topic, schemaName, decoded, logTimeNs) for every message of
/// a channel whose schema `wanted(schemaName, topic)` accepts, and onStatus(text) on changes.
export function connectLive(url, { wanted, onMessage, onStatus }) {
  const ws = new WebSocket(url, ["foxglove.websocket.v1"]);
  ws.binaryType = "arraybuffer";
  const subscriptions = new Map();  // subscription id -> {topic, schemaName, decode}
  let nextSubscription = 1;
  ws.onopen = () => onStatus("connected");
  ws.onclose = () => onStatus("disconnected");
  ws.onerror = () => onStatus("connection error");
  ws.onmessage = (event) => {
    if (typeof event.data === "string") {
      const message = JSON.parse(event.data);
      if (message.op !== "advertise") return;
      const subscribe = [];
      for (const channel of message.channels) {
        if (channel.encoding !== "protobuf" || !wanted(channel.schemaName, channel.topic)) continue;
        let decode;
        try {
          decode = makeDecoder(base64ToBytes(channel.schema), channel.schemaName);
        } catch (e) {
          onStatus(`schema of ${channel.topic} unreadable: ${e.message}`);
          continue;
        }
        const id = nextSubscription++;
        subscriptions.set(id, { topic: channel.topic, schemaName: channel.schemaName, decode });
        subscribe.push({ id, channelId: channel.id });
      }
      if (subscribe.length > 0) ws.send(JSON.stringify({ op: "subscribe", subscriptions: subscribe }));
      return;
    }
    const view = new DataView(event.data);
    if (view.byteLength < 13 || view.getUint8(0) !== OP_MESSAGE_DATA) return;
    const sub = subscriptions.get(view.getUint32(1, true));
    if (!sub) return;
    const logTimeNs = view.getBigUint64(5, true);
    onMessage(sub.topic, sub.schemaName, sub.decode(new Uint8Array(event.data, 13)), logTimeNs);
  };
  return ws;
}
