#include "launch/run_mcap.h"

#include <google/protobuf/descriptor.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "libs/codec/envelope_channel.h"
#include "libs/codec/file_descriptor_set.h"
#include "libs/codec/message_topic.h"
#include "libs/mcap/mcap_reader.h"
#include "libs/mcap/mcap_writer.h"

namespace haptex::launch {
namespace {

namespace pb = google::protobuf;

const std::string kEncoding(codec::kChannelEncoding);

}  // namespace

RunMcapCounts WriteRunMcap(const std::vector<Recording>& recordings, std::ostream& out) {
  struct Entry {
    std::int64_t send_time_ns;
    const v1::Envelope* envelope;
    const pb::FieldDescriptor* body;
  };
  const pb::OneofDescriptor& oneof = codec::EnvelopeBodyOneof();
  const pb::Reflection* reflection = v1::Envelope::GetReflection();
  std::vector<Entry> entries;
  RunMcapCounts tally;
  for (const Recording& r : recordings) {
    for (const v1::Envelope& e : r.envelopes) {
      const pb::FieldDescriptor* body = reflection->GetOneofFieldDescriptor(e, &oneof);
      if (body == nullptr) {
        ++tally.without_body;
        continue;
      }
      entries.push_back({e.send_time_ns(), &e, body});
    }
  }
  // one time line across the services; stable keeps each recording's own order on ties
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.send_time_ns < b.send_time_ns; });

  mcap::McapWriter writer(out);
  std::map<const pb::Descriptor*, std::uint16_t> schemas;
  std::map<std::string, std::uint16_t> channels;  // by topic
  for (const Entry& entry : entries) {
    const pb::Descriptor* type = entry.body->message_type();
    auto schema = schemas.find(type);
    if (schema == schemas.end()) {
      schema =
          schemas.emplace(type, writer.AddSchema(type->full_name(), kEncoding, codec::FileDescriptorSetOf(type))).first;
    }
    const std::string topic = codec::MessageTopic(entry.envelope->sender(), entry.body->name());
    auto channel = channels.find(topic);
    if (channel == channels.end()) {
      channel = channels.emplace(topic, writer.AddChannel(schema->second, topic, kEncoding)).first;
    }
    mcap::Message m;
    m.channel_id = channel->second;
    m.sequence = static_cast<std::uint32_t>(entry.envelope->sequence());
    // steady clocks start at boot: never negative in a real recording
    m.log_time = static_cast<std::uint64_t>(std::max<std::int64_t>(entry.send_time_ns, 0));
    m.publish_time = m.log_time;
    m.data = reflection->GetMessage(*entry.envelope, entry.body).SerializeAsString();
    writer.AddMessage(m);
    ++tally.messages;
    ++tally.channels[topic];
  }
  writer.Finish();
  return tally;
}

std::string MakeRunMcap(const std::vector<Recording>& recordings, RunMcapCounts* counts) {
  std::ostringstream out;
  RunMcapCounts tally = WriteRunMcap(recordings, out);
  if (counts != nullptr) *counts = std::move(tally);
  return out.str();
}

RunMcapCounts WriteRunMcap(const std::vector<Recording>& recordings, const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path);
  RunMcapCounts counts;
  try {
    counts = WriteRunMcap(recordings, out);
    out.close();
  } catch (const mcap::McapError& e) {
    throw std::runtime_error("cannot write " + path + ": " + e.what());
  }
  if (!out) throw std::runtime_error("cannot write " + path);
  const auto slash = path.find_last_of('/');
  counts.file = slash == std::string::npos ? path : path.substr(slash + 1);
  return counts;
}

std::vector<Recording> RecordingsFromMcap(const std::string& path) {
  const mcap::McapFile file = mcap::ReadMcapFile(path);
  auto not_haptex = [&](const std::string& why) {
    return std::runtime_error(path + ": not a haptex run's MCAP: " + why);
  };

  // each channel: its sender and the Envelope's body field, checked against its schema
  std::map<std::uint16_t, codec::EnvelopeChannel> sources;
  for (const mcap::Channel& c : file.channels) {
    const mcap::Schema* schema = file.FindSchema(c.schema_id);
    std::string why;
    codec::EnvelopeChannel s = codec::EnvelopeChannelOf(c.topic, c.message_encoding, schema ? schema->name : "",
                                                        schema ? schema->encoding : "", &why);
    if (s.body == nullptr) throw not_haptex("channel " + c.topic + ": " + why);
    sources[c.id] = std::move(s);
  }

  std::map<std::string, Recording> by_sender;
  const pb::Reflection* reflection = v1::Envelope::GetReflection();
  for (const mcap::Message& m : file.messages) {
    const codec::EnvelopeChannel& s = sources.at(m.channel_id);  // the reader checked every message's channel
    Recording& r = by_sender[s.sender];
    if (r.path.empty()) r.path = path + " " + codec::MessageTopic(s.sender, "*");
    v1::Envelope e;
    e.set_sender(s.sender);
    e.set_sequence(m.sequence);
    e.set_send_time_ns(
        static_cast<std::int64_t>(std::min<std::uint64_t>(m.log_time, std::numeric_limits<std::int64_t>::max())));
    if (reflection->MutableMessage(&e, s.body)->ParseFromString(m.data)) {
      r.envelopes.push_back(std::move(e));
    } else {
      ++r.unparsable;
    }
  }
  std::vector<Recording> out;
  for (auto& [sender, r] : by_sender) out.push_back(std::move(r));
  return out;
}

}  // namespace haptex::launch
