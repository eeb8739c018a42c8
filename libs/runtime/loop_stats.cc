#include "libs/runtime/loop_stats.h"

namespace haptex::runtime {

void LoopStats::FillProto(v1::LoopStats* out) const {
  if (out->name() != name) out->set_name(name);
  out->set_target_rate_hz(target_rate_hz);
  out->set_ticks(ticks);
  out->set_overruns(overruns);
  out->set_period_p50_us(period.Percentile(0.50) * 1e-3);
  out->set_period_p99_us(period.Percentile(0.99) * 1e-3);
  out->set_period_max_us(static_cast<double>(period.max_ns()) * 1e-3);
  out->set_compute_p50_us(compute.Percentile(0.50) * 1e-3);
  out->set_compute_p99_us(compute.Percentile(0.99) * 1e-3);
  out->set_compute_max_us(static_cast<double>(compute.max_ns()) * 1e-3);
}

}  // namespace haptex::runtime
