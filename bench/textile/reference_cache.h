#pragma once
// A converged reference of dynamic_accuracy (0.1 ms steps, minutes at 41 x 41, most of an hour at
// 81 x 81) kept on disk, so that runs of more settings or steps reuse it. A file holds one
// MotionTrace; it is read back only when its header matches the motion asked for (particle count,
// duration, step, and the start state's coordinates summed), else refused with the reason.
// Delete the folder when the fabric model or the reference's solver changes: the header cannot
// tell.

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>

#include "libs/textile/motion_accuracy.h"

namespace haptex::textile {

inline constexpr char kReferenceMagic[8] = {'H', 'X', 'R', 'E', 'F', '0', '0', '1'};

struct ReferenceHeader {
  char magic[8];
  std::int64_t coordinates = 0, samples = 0;
  double dt_s = 0.0, duration_s = 0.0, start_sum_m = 0.0, peak_strain = 0.0;
};

inline ReferenceHeader HeaderFor(const validation::Motion& motion, double dt_s) {
  ReferenceHeader h{};
  std::copy(std::begin(kReferenceMagic), std::end(kReferenceMagic), h.magic);
  h.coordinates = motion.start.x_W_m.size();
  h.dt_s = dt_s;
  h.duration_s = motion.duration_s;
  h.start_sum_m = motion.start.x_W_m.sum();
  return h;
}

/// The trace in `path` when it is a reference of `motion` at `dt_s`; nothing when there is no file.
/// @throws std::runtime_error naming the mismatch for any other file.
inline std::optional<validation::MotionTrace> ReadReference(const std::string& path, const validation::Motion& motion,
                                                            double dt_s) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  const ReferenceHeader want = HeaderFor(motion, dt_s);
  ReferenceHeader got{};
  in.read(reinterpret_cast<char*>(&got), sizeof got);
  auto fail = [&path](const std::string& why) { return std::runtime_error(path + ": " + why + " (delete it)"); };
  if (!in || !std::equal(std::begin(got.magic), std::end(got.magic), kReferenceMagic)) throw fail("not a reference");
  constexpr std::int64_t kMostSamples = 1 << 20;
  if (got.coordinates != want.coordinates || got.dt_s != want.dt_s || got.duration_s != want.duration_s ||
      got.start_sum_m != want.start_sum_m || got.samples < 1 || got.samples > kMostSamples) {
    throw fail("a reference of another motion, mesh or step");
  }
  validation::MotionTrace t;
  t.dt_s = got.dt_s;
  t.peak_strain = got.peak_strain;
  for (std::int64_t k = 0; k < got.samples; ++k) {
    double energy_J = 0.0, strain = 0.0;
    Eigen::VectorXd x(got.coordinates);
    in.read(reinterpret_cast<char*>(&energy_J), sizeof energy_J);
    in.read(reinterpret_cast<char*>(&strain), sizeof strain);
    in.read(reinterpret_cast<char*>(x.data()), static_cast<std::streamsize>(sizeof(double) * x.size()));
    if (!in) throw fail("cut short");
    t.energy_J.push_back(energy_J);
    t.largest_strain.push_back(strain);
    t.x_W_m.push_back(std::move(x));
  }
  return t;
}

/// Writes `trace` (a reference of `motion`) to `path`. @throws std::runtime_error when it cannot.
inline void WriteReference(const std::string& path, const validation::Motion& motion,
                           const validation::MotionTrace& trace) {
  ReferenceHeader h = HeaderFor(motion, trace.dt_s);
  h.samples = static_cast<std::int64_t>(trace.x_W_m.size());
  h.peak_strain = trace.peak_strain;
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(&h), sizeof h);
  for (std::size_t k = 0; k < trace.x_W_m.size(); ++k) {
    out.write(reinterpret_cast<const char*>(&trace.energy_J[k]), sizeof(double));
    out.write(reinterpret_cast<const char*>(&trace.largest_strain[k]), sizeof(double));
    out.write(reinterpret_cast<const char*>(trace.x_W_m[k].data()),
              static_cast<std::streamsize>(sizeof(double) * trace.x_W_m[k].size()));
  }
  if (!out) throw std::runtime_error(path + ": cannot write the reference");
}

}  // namespace haptex::textile
