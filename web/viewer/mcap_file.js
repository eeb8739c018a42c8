// Reads a haptex run's MCAP recording in the page for replay: schemas, channels and every message
// of the data section (chunks uncompressed, as haptex writes them). Throws an Error saying what
// is wrong on a file that is not MCAP or ends early.

const MAGIC = [0x89, 0x4d, 0x43, 0x41, 0x50, 0x30, 0x0d, 0x0a];  // "\x89MCAP0\r\n"
const OP = { HEADER: 0x01, FOOTER: 0x02, SCHEMA: 0x03, CHANNEL: 0x04, MESSAGE: 0x05, CHUNK: 0x06, DATA_END: 0x0f };
const utf8 = new TextDecoder();

class Cursor {
  constructor(bytes, start, end) {
    this.bytes = bytes;
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.pos = start;
    this.end = end;
  }
  need(n) {
    if (this.pos + n > this.end) throw new Error(`MCAP: record ends early at byte ${this.pos}`);
  }
  u8() { this.need(1); return this.bytes[this.pos++]; }
  u16() { this.need(2); const v = this.view.getUint16(this.pos, true); this.pos += 2; return v; }
  u32() { this.need(4); const v = this.view.getUint32(this.pos, true); this.pos += 4; return v; }
  u64() { this.need(8); const v = this.view.getBigUint64(this.pos, true); this.pos += 8; return v; }
  string() { const n = this.u32(); this.need(n); const s = utf8.decode(this.bytes.subarray(this.pos, this.pos + n)); this.pos += n; return s; }
  bytesOf(n) { this.need(n); const b = this.bytes.subarray(this.pos, this.pos + n); this.pos += n; return b; }
}

function readRecords(bytes, start, end, out, insideChunk) {
  const c = new Cursor(bytes, start, end);
  while (c.pos < end) {
    const op = c.u8();
    const length = Number(c.u64());
    c.need(length);
    const body = new Cursor(bytes, c.pos, c.pos + length);
    c.pos += length;
    if (op === OP.SCHEMA) {
      const id = body.u16(), name = body.string(), encoding = body.string();
      const data = body.bytesOf(body.u32());
      out.schemas.set(id, { id, name, encoding, data });
    } else if (op === OP.CHANNEL) {
      const id = body.u16(), schemaId = body.u16(), topic = body.string(), messageEncoding = body.string();
      out.channels.set(id, { id, schemaId, topic, messageEncoding });
    } else if (op === OP.MESSAGE) {
      const channelId = body.u16(), sequence = body.u32();
      const logTime = body.u64(), publishTime = body.u64();
      out.messages.push({ channelId, sequence, logTimeNs: logTime, publishTimeNs: publishTime,
                          data: bytes.subarray(body.pos, body.end) });
    } else if (op === OP.CHUNK) {
      body.u64(); body.u64();  // message start and end time
      body.u64(); body.u32();  // uncompressed size and crc
      const compression = body.string();
      const recordsLength = Number(body.u64());
      if (compression !== "") throw new Error(`MCAP: chunk compression '${compression}' is not supported here`);
      body.need(recordsLength);
      readRecords(bytes, body.pos, body.pos + recordsLength, out, true);
    } else if (op === OP.DATA_END || op === OP.FOOTER) {
      if (!insideChunk) return true;
    }
  }
  return false;
}

/// { schemas: Map id -> {name, encoding, data}, channels: Map id -> {topic, schemaId, ...},
///   messages: [{channelId, logTimeNs (BigInt), data}] in log-time order }.
export function readMcap(arrayBuffer) {
  const bytes = new Uint8Array(arrayBuffer);
  if (bytes.length < 16 || MAGIC.some((b, i) => bytes[i] !== b)) throw new Error("not an MCAP file (no MCAP magic)");
  const out = { schemas: new Map(), channels: new Map(), messages: [] };
  const complete = readRecords(bytes, MAGIC.length, bytes.length, out, false);
  if (!complete) throw new Error("MCAP: the file ends before its data section does (truncated)");
  out.messages.sort((a, b) => (a.logTimeNs < b.logTimeNs ? -1 : a.logTimeNs > b.logTimeNs ? 1 : 0));
  return out;
}
