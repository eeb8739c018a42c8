#pragma once
// One named spdlog logger per service, level from the command line. Include from .cc files only;
// hot loops use RtEventLog instead.

#include <memory>
#include <string>
#include <string_view>

#include <spdlog/common.h>

namespace spdlog {
class logger;
}

namespace haptex::runtime {

/// "trace", "debug", "info", "warn", "error", "critical", "off". Throws std::invalid_argument
/// listing the valid names otherwise.
spdlog::level::level_enum ParseLogLevel(std::string_view name);

/// Creates (or replaces) the logger named `service`, writing to stderr and, when log_file is not
/// empty, to that file; makes it the default logger. Also captures protobuf's own log lines into
/// a counter (see protobuf_log_capture.h).
std::shared_ptr<spdlog::logger> SetupLogging(const std::string& service, std::string_view level,
                                             const std::string& log_file = "");

}  // namespace haptex::runtime
