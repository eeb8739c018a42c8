#include "cli/key_command.h"

#include <sys/stat.h>

#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "libs/net/session_key.h"

namespace haptex::cli {

void AddKeyCommand(CLI::App& app, int* exit_code) {
  CLI::App* key = app.add_subcommand("key", "Session keys");
  key->require_subcommand(1);
  auto out = std::make_shared<std::string>();
  CLI::App* generate = key->add_subcommand("generate", "Print (or write) a fresh random session key");
  generate->add_option("--out", *out, "write the key to this file (mode 0600) instead of printing it");
  generate->callback([out, exit_code] {
    const std::string hex = net::SessionKey::Generate().ToHex();
    if (out->empty()) {
      std::cout << hex << "\n";
    } else {
      std::ofstream file(*out);
      if (!file) throw std::runtime_error("cannot write key file " + *out);
      file << hex << "\n";
      file.close();
      chmod(out->c_str(), S_IRUSR | S_IWUSR);
      std::cout << "wrote session key to " << *out << "\n";
    }
    *exit_code = 0;
  });
}

}  // namespace haptex::cli
