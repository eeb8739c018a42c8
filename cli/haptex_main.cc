// haptex: the command-line front door. Each subcommand lives in its own *_command.cc.
//
// Exit codes: 0 success; 1 a runtime failure; 2 bad usage, scene or input; 3 a check that ran
// and found the result unsuitable (e.g. netcheck's verdict).

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

#include "cli/fabric_command.h"
#include "cli/key_command.h"
#include "cli/netcheck_command.h"
#include "cli/relay_command.h"
#include "cli/scene_command.h"
#include "cli/sim_command.h"
#include "cli/tactile_command.h"
#include "cli/trace_command.h"
#include "cli/view_command.h"
#include "launch/launch_command.h"
#include "libs/flags/finite_number.h"
#include "libs/scene/text_proto.h"

int main(int argc, char** argv) {
  CLI::App app{"haptex: touch virtual fabrics with two fingers (see README.md)", "haptex"};
  app.require_subcommand(1);
  int exit_code = 0;
  haptex::cli::AddNetcheckCommand(app, &exit_code);
  haptex::cli::AddSceneCommand(app, &exit_code);
  haptex::cli::AddKeyCommand(app, &exit_code);
  haptex::cli::AddFabricCommand(app, &exit_code);
  haptex::cli::AddSimCommand(app, &exit_code);
  haptex::cli::AddTactileCommand(app, &exit_code);
  haptex::launch::AddLaunchCommand(app, &exit_code);
  haptex::cli::AddTraceCommand(app, &exit_code);
  haptex::cli::AddRelayCommand(app, &exit_code);
  haptex::cli::AddViewCommand(app, &exit_code);
  haptex::flags::RefuseNonFiniteNumbers(app);  // every numeric flag of every subcommand
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const haptex::scene::TextProtoError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "haptex: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "haptex: " << e.what() << "\n";
    return 1;
  }
  return exit_code;
}
