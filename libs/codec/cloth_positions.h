#pragma once
// The cloth's positions in a ClothFrame chunk: quantised to a fixed step and sent as differences
// between consecutive particles. Grid neighbours are millimetres apart, so a difference takes two
// bytes where a float takes four, and every particle is within half a step of where it was (the
// differences are of the rounded positions, so no error accumulates along the chunk).

#include <cstddef>

#include "haptex/v1/cloth_frame.pb.h"

namespace haptex::codec {

/// The step the cloth's positions are sent at [m]: far below what a view can show.
inline constexpr double kClothQuantumM = 1e-6;

/// Largest |position| / quantum a chunk carries: positions beyond (over a kilometre at the default
/// step) are clamped to it, so that every difference fits a sint32.
inline constexpr int kClothQuantisedLimit = 1 << 30;

/// Writes `count` particles of `x_W_m` (3 per particle) into `out`'s quantum_m and position_q,
/// replacing what was there (the field keeps its storage). A coordinate that is not finite is sent
/// as the particle before it had it (0 for the first).
void EncodeClothPositions(const double* x_W_m, int count, double quantum_m, v1::ClothFrame* out);

/// Positions of `chunk` into `out_W_m` (3 per particle, `capacity` floats at most). The number of
/// floats written, or -1 when the chunk is malformed: quantum not finite and positive, position_q
/// not 3 per particle, more than `capacity`, a sum beyond kClothQuantisedLimit or a position a float
/// cannot hold; `out_W_m` is left as it was then.
long DecodeClothPositions(const v1::ClothFrame& chunk, float* out_W_m, std::size_t capacity);

}  // namespace haptex::codec
