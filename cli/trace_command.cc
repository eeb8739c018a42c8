#include "cli/trace_command.h"

#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "launch/recording.h"
#include "launch/trace_export.h"

namespace haptex::cli {
namespace {

struct ExportOptions {
  std::string run;
  std::string out;
  bool csv = false;
};

int Export(const ExportOptions& o) {
  if (!o.csv) throw std::invalid_argument("trace export: say the format, --csv (the only one so far)");
  // a run folder (with recordings/), or a folder of recordings
  std::string folder = o.run + "/recordings";
  if (!std::filesystem::is_directory(folder)) folder = o.run;
  if (!std::filesystem::is_directory(folder)) throw std::invalid_argument("no run folder " + o.run);
  const auto recordings = launch::ReadRecordings(folder);
  if (recordings.empty()) throw std::invalid_argument("no recordings (*.pb) in " + folder);
  const std::string out = o.out.empty() ? o.run + "/csv" : o.out;
  for (const auto& r : recordings) {
    std::cout << r.path << ": " << r.envelopes.size() << " messages"
              << (r.unparsable ? ", " + std::to_string(r.unparsable) + " unparsable" : std::string())
              << (r.truncated ? ", ends inside a record (cut short)" : "") << "\n";
  }
  for (const auto& [file, rows] : launch::ExportCsv(recordings, out)) {
    std::cout << "wrote " << out << "/" << file << " (" << rows << " rows)\n";
  }
  return 0;
}

}  // namespace

void AddTraceCommand(CLI::App& app, int* exit_code) {
  CLI::App* trace = app.add_subcommand("trace", "A run's recordings (haptex launch)");
  trace->require_subcommand(1);
  auto options = std::make_shared<ExportOptions>();
  CLI::App* exp = trace->add_subcommand("export", "Recordings as CSV, one file per message type");
  exp->add_option("RUN", options->run, "run folder of haptex launch")->required();
  exp->add_flag("--csv", options->csv, "write CSV");
  exp->add_option("--out", options->out, "output folder (default: RUN/csv)");
  exp->callback([options, exit_code] { *exit_code = Export(*options); });
}

}  // namespace haptex::cli
