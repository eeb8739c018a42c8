#include "services/viewer/foxglove_server.h"

// websocketpp 0.8.2 over standalone Asio: this file builds as C++17 (cmake/HaptexDependencies.cmake).
#include <spdlog/spdlog.h>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <fstream>
#include <future>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "services/viewer/foxglove_messages.h"
#include "services/viewer/static_files.h"

namespace haptex::viewer {
namespace {

using WebSocketServer = websocketpp::server<websocketpp::config::asio>;
using ConnectionHandle = websocketpp::connection_hdl;

// Clients send only small JSON requests; anything larger is garbage.
constexpr std::size_t kMaxClientMessageBytes = 64 << 10;
constexpr std::size_t kMaxHttpRequestBodyBytes = 64 << 10;
constexpr std::size_t kMaxStaticFileBytes = 64 << 20;
// Clients get this long to answer the close handshake before the server thread is stopped.
constexpr auto kShutdownGrace = std::chrono::seconds(2);

struct AtomicCounters {
  std::atomic<std::uint64_t> clients_connected{0};
  std::atomic<std::uint64_t> clients_disconnected{0};
  std::atomic<std::uint64_t> clients_refused{0};
  std::atomic<std::uint64_t> messages_sent{0};
  std::atomic<std::uint64_t> messages_dropped_slow_client{0};
  std::atomic<std::uint64_t> client_messages_bad{0};
  std::atomic<std::uint64_t> http_requests{0};
  std::atomic<std::uint64_t> http_not_found{0};
};

std::string NewSessionId() { return std::to_string(std::chrono::system_clock::now().time_since_epoch().count()); }

std::optional<std::string> ReadWholeFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return std::nullopt;
  std::string content;
  char buffer[1 << 16];
  while (file.read(buffer, sizeof(buffer)) || file.gcount() > 0) {
    content.append(buffer, static_cast<std::size_t>(file.gcount()));
    if (content.size() > kMaxStaticFileBytes) return std::nullopt;
  }
  if (file.bad()) return std::nullopt;
  return content;
}

}  // namespace

class FoxgloveServer::Impl {
 public:
  explicit Impl(const Options& options);
  ~Impl();

  std::uint16_t port() const { return port_; }
  std::uint32_t AddChannel(const FoxgloveChannel& channel);
  void SetDocument(const std::string& path, std::string body, const std::string& content_type) {
    auto document = std::make_shared<const Document>(Document{std::move(body), content_type});
    const std::lock_guard lock(documents_mutex_);
    documents_[path] = std::move(document);
  }
  void Publish(std::uint32_t channel_id, std::uint64_t log_time_ns, std::string_view payload);
  bool HasSubscribers(std::uint32_t channel_id) const;
  std::size_t clients() const { return client_count_.load(); }
  Counters counters() const;

 private:
  // What the server thread knows of one WebSocket client.
  struct Client {
    std::unordered_map<std::uint32_t, std::uint32_t> channel_of_subscription;
    std::unordered_map<std::uint32_t, std::uint32_t> subscription_of_channel;
  };

  // The handlers and everything below them run on the server thread only.
  bool OnValidate(ConnectionHandle connection);
  void OnOpen(ConnectionHandle connection);
  void OnClose(ConnectionHandle connection);
  void OnMessage(ConnectionHandle connection, const WebSocketServer::message_ptr& message);
  void OnHttp(ConnectionHandle connection);
  void Subscribe(ConnectionHandle connection, Client& client, const SubscribeRequest& request);
  void Unsubscribe(ConnectionHandle connection, Client& client, const UnsubscribeRequest& request);
  void RejectRequest(ConnectionHandle connection, const std::string& reason);
  void SendText(ConnectionHandle connection, const std::string& text);
  void Advertise(std::uint32_t channel_id);
  void Deliver(std::uint32_t channel_id, std::uint64_t log_time_ns, const std::string& payload);
  void CloseAll();
  void ChangeSubscriberCount(std::uint32_t channel_id, int change);
  void Run();

  const Options options_;
  const StaticFileRoots roots_;
  const std::string session_id_;
  // Above this many bytes posted to the server thread and not yet sent, Publish drops: a stalled
  // server thread must not grow memory without bound.
  const std::size_t max_pending_publish_bytes_;
  WebSocketServer server_;
  std::uint16_t port_ = 0;

  struct Document {
    std::string body, content_type;
  };
  std::mutex documents_mutex_;  // guards documents_
  std::map<std::string, std::shared_ptr<const Document>> documents_;

  mutable std::mutex mutex_;  // guards channels_, next_channel_id_ and subscriber_counts_
  std::map<std::uint32_t, FoxgloveChannel> channels_;
  std::uint32_t next_channel_id_ = 1;
  std::unordered_map<std::uint32_t, std::size_t> subscriber_counts_;

  // Server thread only.
  std::map<ConnectionHandle, Client, std::owner_less<ConnectionHandle>> clients_;
  std::uint32_t last_advertised_channel_id_ = 0;

  std::atomic<std::size_t> client_count_{0};
  std::atomic<std::size_t> pending_publish_bytes_{0};
  AtomicCounters counters_;

  std::promise<void> stopped_;
  std::future<void> stopped_future_ = stopped_.get_future();  // taken before the thread may set it
  std::thread thread_;
};

FoxgloveServer::Impl::Impl(const Options& options)
    : options_(options),
      roots_{options.web_root, options.three_root},
      session_id_(NewSessionId()),
      max_pending_publish_bytes_(std::max<std::size_t>(options.max_queued_bytes_per_client * 4, 64 << 20)) {
  server_.clear_access_channels(websocketpp::log::alevel::all);
  server_.clear_error_channels(websocketpp::log::elevel::all);
  server_.set_max_message_size(kMaxClientMessageBytes);
  server_.set_max_http_body_size(kMaxHttpRequestBodyBytes);
  server_.set_validate_handler([this](ConnectionHandle connection) { return OnValidate(std::move(connection)); });
  server_.set_open_handler([this](ConnectionHandle connection) { OnOpen(std::move(connection)); });
  server_.set_close_handler([this](ConnectionHandle connection) { OnClose(std::move(connection)); });
  server_.set_message_handler([this](ConnectionHandle connection, WebSocketServer::message_ptr message) {
    OnMessage(std::move(connection), message);
  });
  server_.set_http_handler([this](ConnectionHandle connection) { OnHttp(std::move(connection)); });

  const std::string where = options.bind_address + ":" + std::to_string(options.port);
  std::error_code error;
  server_.init_asio(error);
  const asio::ip::address address = asio::ip::make_address(options.bind_address, error);
  if (error) throw std::runtime_error("FoxgloveServer: bad bind address '" + options.bind_address + "'");
  server_.set_reuse_addr(true);
  server_.listen(asio::ip::tcp::endpoint(address, options.port), error);
  if (!error) server_.start_accept(error);
  if (error) throw std::runtime_error("FoxgloveServer: cannot listen on " + where + ": " + error.message());
  asio::error_code local_error;
  port_ = server_.get_local_endpoint(local_error).port();
  if (local_error) {
    throw std::runtime_error("FoxgloveServer: no local port on " + where + ": " + local_error.message());
  }
  thread_ = std::thread([this] { Run(); });
  spdlog::info("foxglove server: ws://{}:{} (web root '{}')", options.bind_address, port_, options.web_root);
}

FoxgloveServer::Impl::~Impl() {
  asio::post(server_.get_io_service(), [this] { CloseAll(); });
  if (stopped_future_.wait_for(kShutdownGrace) != std::future_status::ready) server_.stop();
  thread_.join();
}

void FoxgloveServer::Impl::Run() {
  // A handler that throws must not end the server: log it and go on serving.
  for (;;) {
    try {
      server_.run();
      break;
    } catch (const std::exception& error) {
      spdlog::error("foxglove server: {}", error.what());
    }
  }
  stopped_.set_value();
}

std::uint32_t FoxgloveServer::Impl::AddChannel(const FoxgloveChannel& channel) {
  std::lock_guard lock(mutex_);
  const std::uint32_t id = next_channel_id_++;
  channels_.emplace(id, channel);
  // Posted under the lock, so advertisements reach the server thread in the order of the ids.
  asio::post(server_.get_io_service(), [this, id] { Advertise(id); });
  return id;
}

void FoxgloveServer::Impl::Publish(std::uint32_t channel_id, std::uint64_t log_time_ns, std::string_view payload) {
  if (!HasSubscribers(channel_id)) return;
  if (pending_publish_bytes_.load() + payload.size() > max_pending_publish_bytes_) {
    counters_.messages_dropped_slow_client.fetch_add(1);
    return;
  }
  try {
    auto shared_payload = std::make_shared<const std::string>(payload);
    pending_publish_bytes_.fetch_add(payload.size());
    asio::post(server_.get_io_service(), [this, channel_id, log_time_ns, shared_payload] {
      pending_publish_bytes_.fetch_sub(shared_payload->size());
      Deliver(channel_id, log_time_ns, *shared_payload);
    });
  } catch (const std::exception& error) {
    counters_.messages_dropped_slow_client.fetch_add(1);
    spdlog::warn("foxglove server: dropped a message of channel {}: {}", channel_id, error.what());
  }
}

bool FoxgloveServer::Impl::HasSubscribers(std::uint32_t channel_id) const {
  std::lock_guard lock(mutex_);
  const auto count = subscriber_counts_.find(channel_id);
  return count != subscriber_counts_.end() && count->second > 0;
}

FoxgloveServer::Counters FoxgloveServer::Impl::counters() const {
  Counters counters;
  counters.clients_connected = counters_.clients_connected.load();
  counters.clients_disconnected = counters_.clients_disconnected.load();
  counters.clients_refused = counters_.clients_refused.load();
  counters.messages_sent = counters_.messages_sent.load();
  counters.messages_dropped_slow_client = counters_.messages_dropped_slow_client.load();
  counters.client_messages_bad = counters_.client_messages_bad.load();
  counters.http_requests = counters_.http_requests.load();
  counters.http_not_found = counters_.http_not_found.load();
  return counters;
}

bool FoxgloveServer::Impl::OnValidate(ConnectionHandle connection) {
  const WebSocketServer::connection_ptr con = server_.get_con_from_hdl(std::move(connection));
  const auto& requested = con->get_requested_subprotocols();
  if (std::find(requested.begin(), requested.end(), kFoxgloveSubprotocol) == requested.end()) {
    counters_.clients_refused.fetch_add(1);
    spdlog::warn("foxglove server: refused {}: no subprotocol {}", con->get_remote_endpoint(), kFoxgloveSubprotocol);
    return false;
  }
  con->select_subprotocol(std::string(kFoxgloveSubprotocol));
  return true;
}

void FoxgloveServer::Impl::OnOpen(ConnectionHandle connection) {
  clients_.emplace(connection, Client{});
  client_count_.store(clients_.size());
  counters_.clients_connected.fetch_add(1);
  std::vector<AdvertisedChannel> advertised;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, channel] : channels_) {
      if (id <= last_advertised_channel_id_) advertised.push_back({id, channel});
    }
  }
  SendText(connection, ServerInfoJson(options_.name, session_id_));
  if (!advertised.empty()) SendText(connection, AdvertiseJson(advertised));
}

void FoxgloveServer::Impl::OnClose(ConnectionHandle connection) {
  const auto client = clients_.find(connection);
  if (client == clients_.end()) return;
  for (const auto& [channel_id, subscription_id] : client->second.subscription_of_channel) {
    ChangeSubscriberCount(channel_id, -1);
  }
  clients_.erase(client);
  client_count_.store(clients_.size());
  counters_.clients_disconnected.fetch_add(1);
}

void FoxgloveServer::Impl::OnMessage(ConnectionHandle connection, const WebSocketServer::message_ptr& message) {
  const auto client = clients_.find(connection);
  if (client == clients_.end()) return;
  if (message->get_opcode() != websocketpp::frame::opcode::text) {
    RejectRequest(connection, "binary messages are not supported (no clientPublish)");
    return;
  }
  const ClientRequest request = ParseClientRequest(message->get_payload());
  if (const auto* subscribe = std::get_if<SubscribeRequest>(&request)) {
    Subscribe(connection, client->second, *subscribe);
  } else if (const auto* unsubscribe = std::get_if<UnsubscribeRequest>(&request)) {
    Unsubscribe(connection, client->second, *unsubscribe);
  } else {
    RejectRequest(connection, std::get<BadClientMessage>(request).reason);
  }
}

void FoxgloveServer::Impl::Subscribe(ConnectionHandle connection, Client& client, const SubscribeRequest& request) {
  for (const Subscription& subscription : request.subscriptions) {
    bool known = false;
    {
      std::lock_guard lock(mutex_);
      known = channels_.count(subscription.channel_id) > 0 && subscription.channel_id <= last_advertised_channel_id_;
    }
    if (!known) {
      RejectRequest(connection, "subscribe: unknown channel " + std::to_string(subscription.channel_id));
    } else if (client.channel_of_subscription.count(subscription.id) > 0) {
      RejectRequest(connection, "subscribe: subscription id " + std::to_string(subscription.id) + " is in use");
    } else if (client.subscription_of_channel.count(subscription.channel_id) > 0) {
      RejectRequest(connection, "subscribe: already subscribed to channel " + std::to_string(subscription.channel_id));
    } else {
      client.channel_of_subscription.emplace(subscription.id, subscription.channel_id);
      client.subscription_of_channel.emplace(subscription.channel_id, subscription.id);
      ChangeSubscriberCount(subscription.channel_id, +1);
    }
  }
}

void FoxgloveServer::Impl::Unsubscribe(ConnectionHandle connection, Client& client, const UnsubscribeRequest& request) {
  for (const std::uint32_t subscription_id : request.subscription_ids) {
    const auto subscription = client.channel_of_subscription.find(subscription_id);
    if (subscription == client.channel_of_subscription.end()) {
      RejectRequest(connection, "unsubscribe: unknown subscription " + std::to_string(subscription_id));
      continue;
    }
    const std::uint32_t channel_id = subscription->second;
    client.channel_of_subscription.erase(subscription);
    client.subscription_of_channel.erase(channel_id);
    ChangeSubscriberCount(channel_id, -1);
  }
}

void FoxgloveServer::Impl::ChangeSubscriberCount(std::uint32_t channel_id, int change) {
  std::lock_guard lock(mutex_);
  std::size_t& count = subscriber_counts_[channel_id];
  count = change > 0 ? count + 1 : (count > 0 ? count - 1 : 0);
}

void FoxgloveServer::Impl::RejectRequest(ConnectionHandle connection, const std::string& reason) {
  counters_.client_messages_bad.fetch_add(1);
  spdlog::debug("foxglove server: ignored a client message: {}", reason);
  SendText(std::move(connection), StatusJson(StatusLevel::kWarning, reason));
}

void FoxgloveServer::Impl::SendText(ConnectionHandle connection, const std::string& text) {
  std::error_code error;
  const WebSocketServer::connection_ptr con = server_.get_con_from_hdl(std::move(connection), error);
  if (error || con->get_state() != websocketpp::session::state::open) return;
  // A client that does not read is not sent ever more status messages.
  if (con->get_buffered_amount() > options_.max_queued_bytes_per_client) return;
  error = con->send(text, websocketpp::frame::opcode::text);
  if (error) spdlog::debug("foxglove server: send failed: {}", error.message());
}

void FoxgloveServer::Impl::Advertise(std::uint32_t channel_id) {
  std::vector<AdvertisedChannel> advertised;
  {
    std::lock_guard lock(mutex_);
    last_advertised_channel_id_ = std::max(last_advertised_channel_id_, channel_id);
    const auto channel = channels_.find(channel_id);
    if (channel == channels_.end()) return;
    advertised.push_back({channel_id, channel->second});
  }
  const std::string text = AdvertiseJson(advertised);
  for (const auto& [connection, client] : clients_) SendText(connection, text);
}

void FoxgloveServer::Impl::Deliver(std::uint32_t channel_id, std::uint64_t log_time_ns, const std::string& payload) {
  const std::size_t frame_bytes = kMessageDataHeaderBytes + payload.size();
  for (const auto& [connection, client] : clients_) {
    const auto subscription = client.subscription_of_channel.find(channel_id);
    if (subscription == client.subscription_of_channel.end()) continue;
    std::error_code error;
    const WebSocketServer::connection_ptr con = server_.get_con_from_hdl(connection, error);
    if (error || con->get_state() != websocketpp::session::state::open) continue;
    const std::size_t queued = con->get_buffered_amount();
    if (queued > 0 && queued + frame_bytes > options_.max_queued_bytes_per_client) {
      counters_.messages_dropped_slow_client.fetch_add(1);
      continue;
    }
    const WebSocketServer::message_ptr message = con->get_message(websocketpp::frame::opcode::binary, frame_bytes);
    message->append_payload(MessageDataHeader(subscription->second, log_time_ns));
    message->append_payload(payload);
    error = con->send(message);
    if (error) {
      counters_.messages_dropped_slow_client.fetch_add(1);
    } else {
      counters_.messages_sent.fetch_add(1);
    }
  }
}

void FoxgloveServer::Impl::OnHttp(ConnectionHandle connection) {
  counters_.http_requests.fetch_add(1);
  const WebSocketServer::connection_ptr con = server_.get_con_from_hdl(std::move(connection));
  con->append_header("X-Content-Type-Options", "nosniff");
  con->append_header("Cache-Control", "no-cache");
  const std::string& method = con->get_request().get_method();
  if (method != "GET") {
    counters_.http_not_found.fetch_add(1);
    con->set_status(websocketpp::http::status_code::method_not_allowed);
    con->append_header("Allow", "GET");
    return;
  }
  std::shared_ptr<const Document> document;
  {
    const std::lock_guard lock(documents_mutex_);
    const std::string& resource = con->get_resource();
    const auto it = documents_.find(resource.substr(0, resource.find('?')));
    if (it != documents_.end()) document = it->second;
  }
  if (document) {
    con->set_status(websocketpp::http::status_code::ok);
    con->append_header("Content-Type", document->content_type);
    con->set_body(document->body);
    return;
  }
  const std::optional<StaticFile> file = ResolveStaticFile(roots_, con->get_resource());
  std::optional<std::string> content;
  if (file) content = ReadWholeFile(file->path);
  if (!content) {
    counters_.http_not_found.fetch_add(1);
    con->set_status(websocketpp::http::status_code::not_found);
    con->append_header("Content-Type", "text/plain; charset=utf-8");
    con->set_body("not found\n");
    return;
  }
  con->set_status(websocketpp::http::status_code::ok);
  con->append_header("Content-Type", file->content_type);
  con->set_body(*content);
}

void FoxgloveServer::Impl::CloseAll() {
  std::error_code error;
  server_.stop_listening(error);
  for (const auto& [connection, client] : clients_) {
    server_.close(connection, websocketpp::close::status::going_away, "server stopping", error);
  }
}

FoxgloveServer::FoxgloveServer(const Options& options) : impl_(std::make_unique<Impl>(options)) {}
FoxgloveServer::~FoxgloveServer() = default;
std::uint16_t FoxgloveServer::port() const { return impl_->port(); }
std::uint32_t FoxgloveServer::AddChannel(const FoxgloveChannel& channel) { return impl_->AddChannel(channel); }
void FoxgloveServer::SetDocument(const std::string& path, std::string body, const std::string& content_type) {
  impl_->SetDocument(path, std::move(body), content_type);
}
void FoxgloveServer::Publish(std::uint32_t channel_id, std::uint64_t log_time_ns, std::string_view payload) {
  impl_->Publish(channel_id, log_time_ns, payload);
}
bool FoxgloveServer::HasSubscribers(std::uint32_t channel_id) const { return impl_->HasSubscribers(channel_id); }
std::size_t FoxgloveServer::clients() const { return impl_->clients(); }
FoxgloveServer::Counters FoxgloveServer::counters() const { return impl_->counters(); }

}  // namespace haptex::viewer
