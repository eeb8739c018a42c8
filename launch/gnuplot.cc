#include "launch/gnuplot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cstring>
#include <filesystem>
#include <string_view>

extern char** environ;

namespace haptex::launch {

std::string RunGnuplot(const std::string& dir, const std::string& script) {
  std::string program = "gnuplot";
  std::string argument = script;
  char* argv[] = {program.data(), argument.data(), nullptr};
  const std::string log = script + ".log";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  // in order: into dir first, so the log (and every file the script names) is relative to it
  posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
  posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    return "cannot run gnuplot in " + dir + ": " + std::strerror(spawned) + " (scripts/setup installs gnuplot-nox)";
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return "gnuplot failed (see " + dir + "/" + log + ")";
  }
  std::error_code ignored;
  std::filesystem::remove(dir + "/" + log, ignored);
  return "";
}

std::string GnuplotLabel(std::string_view text) {
  constexpr std::string_view kKept = " -_.,:;()[]+=/%";
  std::string label = "'";
  for (const char c : text.substr(0, 80)) {
    const bool kept = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      kKept.find(c) != std::string_view::npos;
    label += kept ? c : '_';
  }
  return label + "'";
}

}  // namespace haptex::launch
