#pragma once
// Reads a whole MCAP file (https://mcap.dev/spec) and checks it: the magic at both ends, every
// record's length, the chunk, data section and summary CRCs (where the writer gave them), that
// messages name known channels and channels known schemas, and that the summary's statistics and
// chunk indexes agree with the data. Anything else throws McapError saying what and at which byte;
// no length is trusted before it is checked against what is left. Chunks must be uncompressed
// (the only kind haptex writes).

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "libs/mcap/mcap_error.h"
#include "libs/mcap/mcap_records.h"

namespace haptex::mcap {

struct Statistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t chunk_count = 0;
  std::uint64_t message_start_time = 0, message_end_time = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

struct McapFile {
  std::string profile;
  std::string library;
  std::vector<Schema> schemas;    // by id
  std::vector<Channel> channels;  // by id
  std::vector<Message> messages;  // by log time (in file order where equal)
  std::size_t chunks = 0;
  bool has_summary = false;
  std::optional<Statistics> statistics;  // from the summary
  std::size_t chunk_indexes = 0;         // Chunk Index records in the summary

  const Channel* FindChannel(std::uint16_t id) const;
  const Schema* FindSchema(std::uint16_t id) const;
};

/// The file's content. Throws McapError.
McapFile ReadMcap(std::string_view bytes);

/// Reads the file at `path`. Throws McapError (a missing or unreadable file too).
McapFile ReadMcapFile(const std::string& path);

}  // namespace haptex::mcap
