#include "cli/key_command.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

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
      // created private: the key is never readable by others, not even for a moment
      const int fd = open(out->c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0600);
      if (fd < 0) throw std::runtime_error("cannot write key file " + *out + ": " + std::strerror(errno));
      const std::string text = hex + "\n";
      const bool ok = fchmod(fd, 0600) == 0 && write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
      close(fd);
      if (!ok) throw std::runtime_error("cannot write key file " + *out + ": " + std::strerror(errno));
      std::cout << "wrote session key to " << *out << "\n";
    }
    *exit_code = 0;
  });
}

}  // namespace haptex::cli
