#pragma once
// A Foxglove WebSocket server (protocol v1, subprotocol foxglove.websocket.v1) that also serves the
// viewer's static files over plain HTTP on the same port. Browsers and Foxglove Studio connect,
// receive serverInfo and the advertisement of every channel, subscribe, and get each published
// message as a binary frame. The server runs on a thread of its own; its callers never wait for a
// client: a client that reads too slowly misses messages instead.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "libs/codec/file_descriptor_set.h"
#include "services/viewer/foxglove_channel.h"

namespace haptex::viewer {

class FoxgloveServer {
 public:
  struct Options {
    std::string bind_address = "127.0.0.1";
    std::uint16_t port = 0;  // 0: any free port
    std::string web_root;    // the viewer page: "/" is <web_root>/index.html; empty: no page
    std::string three_root;  // three.js's build folder: "/three/x.js" is <three_root>/x.js
    std::string name = "haptex";
    std::size_t max_queued_bytes_per_client = 16 << 20;
  };

  struct Counters {
    std::uint64_t clients_connected = 0;
    std::uint64_t clients_disconnected = 0;
    std::uint64_t clients_refused = 0;  // WebSocket handshakes without the Foxglove subprotocol
    std::uint64_t messages_sent = 0;
    std::uint64_t messages_dropped_slow_client = 0;  // per client; also when the server's queue is full
    std::uint64_t client_messages_bad = 0;           // ignored: bad JSON, unknown op or channel, binary, ...
    std::uint64_t http_requests = 0;
    std::uint64_t http_not_found = 0;  // answered with an error status (404, 405, 500)
  };

  /// Binds and starts the server's thread. Throws std::runtime_error naming the address if it
  /// cannot bind.
  explicit FoxgloveServer(const Options& options);
  /// Closes every connection and joins the thread.
  ~FoxgloveServer();
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  /// The bound port.
  std::uint16_t port() const;

  /// Thread-safe. From now on a GET of exactly `path` ("/session.json") answers `body`, before any
  /// static file: what the server's owner makes at run time (the session, a run's recording).
  void SetDocument(const std::string& path, std::string body, const std::string& content_type);

  /// Thread-safe. Returns the channel's id; connected clients get its advertisement.
  std::uint32_t AddChannel(const FoxgloveChannel& channel);

  /// Thread-safe, never blocks on a client and never throws: sends to every client subscribed to
  /// the channel; a client whose queued bytes exceed the limit misses this message (counted). An
  /// unknown channel id is ignored.
  void Publish(std::uint32_t channel_id, std::uint64_t log_time_ns, std::string_view payload);

  /// Whether any client is subscribed to the channel: a caller may skip building its message.
  bool HasSubscribers(std::uint32_t channel_id) const;

  /// Connected WebSocket clients.
  std::size_t clients() const;

  Counters counters() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace haptex::viewer
