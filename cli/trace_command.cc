#include "cli/trace_command.h"

#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "launch/recording.h"
#include "launch/run_mcap.h"
#include "launch/trace_export.h"

namespace haptex::cli {
namespace {

struct ExportOptions {
  std::string run;
  std::string out;
  bool csv = false;
};

// A run's recordings: its run.mcap (the run folder's, or an .mcap path), else the .pb recordings of
// the run folder (RUN/recordings) or of a folder of recordings.
std::vector<launch::Recording> ReadRun(const std::string& run) {
  namespace fs = std::filesystem;
  std::string mcap;
  if (fs::path(run).extension() == ".mcap") mcap = run;
  if (mcap.empty() && fs::is_regular_file(run + "/run.mcap")) mcap = run + "/run.mcap";
  if (!mcap.empty()) {
    auto recordings = launch::RecordingsFromMcap(mcap);  // a clear error for a missing, cut or foreign file
    if (recordings.empty()) throw std::invalid_argument("no messages in " + mcap);
    return recordings;
  }
  if (fs::exists(run) && !fs::is_directory(run)) {
    throw std::invalid_argument(run + " is neither a run folder nor an .mcap file");
  }
  std::string folder = run + "/recordings";
  if (!fs::is_directory(folder)) folder = run;
  if (!fs::is_directory(folder)) throw std::invalid_argument("no run folder " + run);
  auto recordings = launch::ReadRecordings(folder);
  if (recordings.empty()) throw std::invalid_argument("no run.mcap and no recordings (*.pb) in " + run);
  return recordings;
}

int Export(const ExportOptions& o) {
  if (!o.csv) throw std::invalid_argument("trace export: say the format, --csv (the only one so far)");
  const auto recordings = ReadRun(o.run);
  // beside the run's recordings, or beside the .mcap file
  namespace fs = std::filesystem;
  const fs::path root = fs::path(o.run).extension() == ".mcap" ? fs::path(o.run).parent_path() : fs::path(o.run);
  const std::string out = o.out.empty() ? (root / "csv").string() : o.out;
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
  CLI::App* exp = trace->add_subcommand("export", "A run's messages as CSV, one file per message type");
  exp->add_option("RUN", options->run,
                  "run folder of haptex launch (its run.mcap, else its recordings), or an .mcap file")
      ->required();
  exp->add_flag("--csv", options->csv, "write CSV");
  exp->add_option("--out", options->out, "output folder (default: RUN/csv)");
  exp->callback([options, exit_code] { *exit_code = Export(*options); });
}

}  // namespace haptex::cli
