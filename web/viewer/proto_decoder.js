// Decodes protobuf messages with the schemas that travel with them (a serialized
// google.protobuf.FileDescriptorSet, as a Foxglove server advertises it and an MCAP file embeds it)
// into plain objects keyed by field name. 64-bit integers become Numbers (exact up to 2^53).

const WIRE_VARINT = 0, WIRE_I64 = 1, WIRE_LEN = 2, WIRE_I32 = 5;
const TYPE = {
  DOUBLE: 1, FLOAT: 2, INT64: 3, UINT64: 4, INT32: 5, FIXED64: 6, FIXED32: 7, BOOL: 8, STRING: 9,
  GROUP: 10, MESSAGE: 11, BYTES: 12, UINT32: 13, ENUM: 14, SFIXED32: 15, SFIXED64: 16, SINT32: 17, SINT64: 18,
};
const LABEL_REPEATED = 3;
const utf8 = new TextDecoder();

class Reader {
  constructor(bytes) {
    this.bytes = bytes;
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.pos = 0;
  }
  done() { return this.pos >= this.bytes.length; }
  need(n) {
    if (this.pos + n > this.bytes.length) throw new Error(`protobuf: truncated at byte ${this.pos}`);
  }
  varint() {
    let result = 0n, shift = 0n;
    for (;;) {
      this.need(1);
      const b = this.bytes[this.pos++];
      result |= BigInt(b & 0x7f) << shift;
      if ((b & 0x80) === 0) return result;
      shift += 7n;
      if (shift > 63n) throw new Error("protobuf: varint too long");
    }
  }
  fixed32() { this.need(4); const v = this.view.getUint32(this.pos, true); this.pos += 4; return v; }
  fixed64() { this.need(8); const v = this.view.getBigUint64(this.pos, true); this.pos += 8; return v; }
  float() { this.need(4); const v = this.view.getFloat32(this.pos, true); this.pos += 4; return v; }
  double() { this.need(8); const v = this.view.getFloat64(this.pos, true); this.pos += 8; return v; }
  lengthDelimited() {
    const n = Number(this.varint());
    this.need(n);
    const out = this.bytes.subarray(this.pos, this.pos + n);
    this.pos += n;
    return out;
  }
  skip(wire) {
    if (wire === WIRE_VARINT) this.varint();
    else if (wire === WIRE_I64) { this.need(8); this.pos += 8; }
    else if (wire === WIRE_LEN) this.lengthDelimited();
    else if (wire === WIRE_I32) { this.need(4); this.pos += 4; }
    else throw new Error(`protobuf: wire type ${wire} at byte ${this.pos}`);
  }
}

// The few descriptor.proto fields needed to read a FileDescriptorSet (their numbers are fixed by
// protobuf itself).
function readFields(bytes, onField) {
  const r = new Reader(bytes);
  while (!r.done()) {
    const key = Number(r.varint());
    const number = key >>> 3, wire = key & 7;
    if (wire === WIRE_LEN) onField(number, r.lengthDelimited(), wire);
    else if (wire === WIRE_VARINT) onField(number, r.varint(), wire);
    else r.skip(wire);
  }
}

function readMessageType(bytes, scope, types) {
  const type = { name: "", fields: new Map() };
  const nested = [];
  readFields(bytes, (n, v) => {
    if (n === 1) type.name = utf8.decode(v);
    else if (n === 2) {
      const f = { name: "", number: 0, label: 1, type: 0, typeName: "" };
      readFields(v, (fn, fv) => {
        if (fn === 1) f.name = utf8.decode(fv);
        else if (fn === 3) f.number = Number(fv);
        else if (fn === 4) f.label = Number(fv);
        else if (fn === 5) f.type = Number(fv);
        else if (fn === 6) f.typeName = utf8.decode(fv).replace(/^\./, "");
      });
      type.fields.set(f.number, f);
    } else if (n === 3) nested.push(v);
  });
  const fullName = scope ? `${scope}.${type.name}` : type.name;
  types.set(fullName, type);
  for (const n of nested) readMessageType(n, fullName, types);
}

/// Every message type of a FileDescriptorSet, by full name ("haptex.v1.ClothFrame").
export function parseFileDescriptorSet(bytes) {
  const types = new Map();
  readFields(bytes, (n, file) => {
    if (n !== 1) return;
    let pkg = "";
    const messages = [];
    readFields(file, (fn, fv) => {
      if (fn === 2) pkg = utf8.decode(fv);
      else if (fn === 4) messages.push(fv);
    });
    for (const m of messages) readMessageType(m, pkg, types);
  });
  return types;
}

function scalar(r, type, wire) {
  switch (type) {
    case TYPE.DOUBLE: return r.double();
    case TYPE.FLOAT: return r.float();
    case TYPE.FIXED32: return r.fixed32();
    case TYPE.SFIXED32: return r.fixed32() | 0;
    case TYPE.FIXED64: return Number(r.fixed64());
    case TYPE.SFIXED64: return Number(BigInt.asIntN(64, r.fixed64()));
    case TYPE.BOOL: return r.varint() !== 0n;
    case TYPE.INT32: case TYPE.ENUM: return Number(BigInt.asIntN(32, r.varint()));
    case TYPE.UINT32: return Number(BigInt.asUintN(32, r.varint()));
    case TYPE.INT64: return Number(BigInt.asIntN(64, r.varint()));
    case TYPE.UINT64: return Number(r.varint());
    case TYPE.SINT32: case TYPE.SINT64: {
      const v = r.varint();
      return Number((v >> 1n) ^ -(v & 1n));
    }
    default: throw new Error(`protobuf: type ${type} is not a scalar (wire ${wire})`);
  }
}

function decodeWith(types, typeName, bytes) {
  const type = types.get(typeName);
  if (!type) throw new Error(`protobuf: no schema for ${typeName}`);
  const out = {};
  // proto3: a field not on the wire has its type's default (messages stay undefined)
  for (const f of type.fields.values()) {
    if (f.label === LABEL_REPEATED) out[f.name] = [];
    else if (f.type === TYPE.STRING) out[f.name] = "";
    else if (f.type === TYPE.BOOL) out[f.name] = false;
    else if (f.type !== TYPE.MESSAGE && f.type !== TYPE.BYTES && f.type !== TYPE.GROUP) out[f.name] = 0;
  }
  const r = new Reader(bytes);
  while (!r.done()) {
    const key = Number(r.varint());
    const field = type.fields.get(key >>> 3), wire = key & 7;
    if (!field) { r.skip(wire); continue; }
    let value;
    if (field.type === TYPE.MESSAGE) value = decodeWith(types, field.typeName, r.lengthDelimited());
    else if (field.type === TYPE.STRING) value = utf8.decode(r.lengthDelimited());
    else if (field.type === TYPE.BYTES) value = r.lengthDelimited();
    else if (wire === WIRE_LEN) {  // a packed repeated scalar
      const packed = new Reader(r.lengthDelimited());
      const wireOf = field.type === TYPE.DOUBLE || field.type === TYPE.FIXED64 || field.type === TYPE.SFIXED64 ? WIRE_I64
        : field.type === TYPE.FLOAT || field.type === TYPE.FIXED32 || field.type === TYPE.SFIXED32 ? WIRE_I32 : WIRE_VARINT;
      while (!packed.done()) out[field.name].push(scalar(packed, field.type, wireOf));
      continue;
    } else value = scalar(r, field.type, wire);
    if (field.label === LABEL_REPEATED) out[field.name].push(value);
    else out[field.name] = value;
  }
  return out;
}

/// A function that decodes `typeName` messages with the given FileDescriptorSet's schemas.
export function makeDecoder(fileDescriptorSetBytes, typeName) {
  const types = parseFileDescriptorSet(fileDescriptorSetBytes);
  if (!types.has(typeName)) throw new Error(`protobuf: the schema does not define ${typeName}`);
  return (bytes) => decodeWith(types, typeName, bytes);
}
