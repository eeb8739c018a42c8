// The cloth's positions in a ClothFrame chunk (proto/haptex/v1/cloth_frame.proto): position_q holds
// 3 values a particle, the chunk's first particle as round(x / quantum_m), every next one the
// difference from the particle before; x = quantum_m * running sum. The same checks as global_sim's
// and the viewer service's codec (libs/codec/cloth_positions.h): a malformed chunk writes nothing.

const LIMIT = 2 ** 30;  // largest |running sum| a chunk may reach

// Writes the chunk's positions into `out` from `offset`; the number written, or -1 when malformed.
export function decodeClothPositions(m, out, offset) {
  const q = m.position_q ?? [];
  const quantum = m.quantum_m;
  if (!(Number.isFinite(quantum) && quantum > 0) || q.length % 3 !== 0 || offset + q.length > out.length) return -1;
  const sum = [0, 0, 0];
  for (let i = 0; i < q.length; ++i) {
    sum[i % 3] += q[i];
    if (Math.abs(sum[i % 3]) > LIMIT) return -1;
  }
  sum.fill(0);
  for (let i = 0; i < q.length; ++i) {
    sum[i % 3] += q[i];
    out[offset + i] = quantum * sum[i % 3];
  }
  return q.length;
}
