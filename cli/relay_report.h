#pragma once
// What `haptex relay` did, per direction, as text and as JSON.

#include <cstdint>
#include <string>

#include "libs/netsim/impairment_config.h"
#include "libs/netsim/impairment_model.h"

namespace haptex::cli {

struct RelayDirectionReport {
  netsim::ImpairmentConfig config;
  std::uint64_t seed = 0;
  netsim::ImpairmentStats stats;
};

struct RelayReport {
  std::string listen;
  std::string upstream;
  std::string to;
  std::string back_to;  // empty: the last client seen
  double duration_s = 0.0;
  RelayDirectionReport forward;  // listen -> to
  RelayDirectionReport back;     // server side -> client
};

/// One line per direction: received, forwarded, duplicated, reordered, dropped by cause,
/// achieved delay p50/p99/max in ms.
std::string RelayReportToText(const RelayReport& report);
/// One JSON object: addresses, duration_s, and per direction its config, seed and counts
/// (dropped by cause, delay_ms p50/p99/max/mean).
std::string RelayReportToJson(const RelayReport& report);

}  // namespace haptex::cli
