// The server over real sockets in one process: websocketpp clients speak the Foxglove protocol,
// raw TCP sockets misbehave (garbage, abrupt disconnects, never reading) and fetch static files.
// C++17, as the server: this file includes websocketpp (cmake/HaptexDependencies.cmake).
#include "services/viewer/foxglove_server.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <websocketpp/client.hpp>
#include <websocketpp/config/asio_no_tls_client.hpp>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "services/viewer/foxglove_messages.h"

namespace haptex::viewer {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;
using WebSocketClient = websocketpp::client<websocketpp::config::asio_client>;

bool WaitUntil(const std::function<bool()>& condition, std::chrono::milliseconds timeout = 10s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(2ms);
  }
  return true;
}

// A well-behaved Foxglove client on a thread of its own: it keeps what it receives.
class TestClient {
 public:
  explicit TestClient(std::uint16_t port, const std::string& subprotocol = std::string(kFoxgloveSubprotocol)) {
    client_.clear_access_channels(websocketpp::log::alevel::all);
    client_.clear_error_channels(websocketpp::log::elevel::all);
    client_.init_asio();
    client_.set_open_handler([this](websocketpp::connection_hdl) { Update([this] { open_ = true; }); });
    client_.set_fail_handler([this](websocketpp::connection_hdl) { Update([this] { closed_ = true; }); });
    client_.set_close_handler([this](websocketpp::connection_hdl) { Update([this] { closed_ = true; }); });
    client_.set_message_handler([this](websocketpp::connection_hdl, WebSocketClient::message_ptr message) {
      Update([&] {
        if (message->get_opcode() == websocketpp::frame::opcode::text) {
          texts_.push_back(message->get_payload());
        } else {
          binaries_.push_back(message->get_payload());
        }
      });
    });
    std::error_code error;
    auto connection = client_.get_connection("ws://127.0.0.1:" + std::to_string(port) + "/", error);
    if (error) throw std::runtime_error(error.message());
    if (!subprotocol.empty()) connection->add_subprotocol(subprotocol);
    handle_ = connection->get_handle();
    client_.connect(connection);
    thread_ = std::thread([this] { client_.run(); });
  }

  ~TestClient() {
    Post([this] {
      std::error_code error;
      client_.close(handle_, websocketpp::close::status::normal, "done", error);
    });
    if (!WaitFor([this] { return closed_; }, 3s)) client_.stop();
    thread_.join();
  }

  bool WaitOpen() {
    return WaitFor([this] { return open_ || closed_; }) && open_;
  }
  bool WaitClosed() {
    return WaitFor([this] { return closed_; });
  }

  void SendText(const std::string& text) { Send(text, websocketpp::frame::opcode::text); }
  void SendBinary(const std::string& bytes) { Send(bytes, websocketpp::frame::opcode::binary); }

  /// The next text message whose op is `op`; earlier ones of other ops are passed over.
  std::optional<json> NextWithOp(const std::string& op) {
    std::optional<json> found;
    WaitFor([&] {
      while (!texts_.empty() && !found) {
        json message = json::parse(texts_.front(), nullptr, false);
        texts_.pop_front();
        if (message.is_object() && message.value("op", "") == op) found = std::move(message);
      }
      return found.has_value();
    });
    return found;
  }

  /// Waits until `count` binary messages arrived, and returns them all.
  std::vector<std::string> WaitBinaries(std::size_t count, std::chrono::milliseconds timeout = 10s) {
    std::vector<std::string> copy;
    WaitFor([&] { return binaries_.size() >= count; }, timeout);
    std::lock_guard lock(mutex_);
    copy.assign(binaries_.begin(), binaries_.end());
    return copy;
  }

 private:
  template <typename Change>
  void Update(Change change) {
    std::lock_guard lock(mutex_);
    change();
    changed_.notify_all();
  }

  bool WaitFor(const std::function<bool()>& condition, std::chrono::milliseconds timeout = 10s) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, condition);
  }

  void Post(std::function<void()> work) { asio::post(client_.get_io_service(), std::move(work)); }

  void Send(const std::string& payload, websocketpp::frame::opcode::value opcode) {
    Post([this, payload, opcode] {
      std::error_code error;
      client_.send(handle_, payload, opcode, error);
    });
  }

  WebSocketClient client_;
  websocketpp::connection_hdl handle_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool open_ = false;
  bool closed_ = false;
  std::deque<std::string> texts_;
  std::deque<std::string> binaries_;
  std::thread thread_;
};

// A raw TCP connection, for what no polite client does.
class RawSocket {
 public:
  explicit RawSocket(std::uint16_t port) : socket_(io_) {
    socket_.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  }
  void Write(const std::string& bytes) { asio::write(socket_, asio::buffer(bytes)); }
  std::string ReadUntil(const std::string& delimiter) {
    const std::size_t end = asio::read_until(socket_, asio::dynamic_buffer(buffer_), delimiter);
    std::string head = buffer_.substr(0, end);
    buffer_.erase(0, end);
    return head;
  }
  std::string ReadToEnd() {
    std::error_code error;
    asio::read(socket_, asio::dynamic_buffer(buffer_), error);
    return std::move(buffer_);
  }
  /// The WebSocket opening handshake, done by hand; returns the server's response head.
  std::string Handshake(const std::string& subprotocol = std::string(kFoxgloveSubprotocol)) {
    Write(
        "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
        "Sec-WebSocket-Protocol: " +
        subprotocol + "\r\n\r\n");
    return ReadUntil("\r\n\r\n");
  }
  /// A client text frame: masked, as RFC 6455 requires of clients (short payloads only).
  void WriteTextFrame(const std::string& text) {
    const std::string mask = "\x11\x22\x33\x44";
    std::string frame = {'\x81', static_cast<char>(0x80 | text.size())};
    frame += mask;
    for (std::size_t i = 0; i < text.size(); ++i) frame.push_back(static_cast<char>(text[i] ^ mask[i % 4]));
    Write(frame);
  }
  void Close() { socket_.close(); }

 private:
  asio::io_context io_;
  asio::ip::tcp::socket socket_;
  std::string buffer_;
};

FoxgloveChannel TestChannel(const std::string& topic) { return {topic, "test.Type", "schema-of-" + topic}; }

std::string Subscribe(std::uint32_t subscription_id, std::uint32_t channel_id) {
  return json{{"op", "subscribe"}, {"subscriptions", {{{"id", subscription_id}, {"channelId", channel_id}}}}}.dump();
}

std::string PayloadOf(std::size_t size, int seed) {
  std::string payload(size, '\0');
  for (std::size_t i = 0; i < size; ++i)
    payload[i] = static_cast<char>((i * 31 + static_cast<std::size_t>(seed)) & 0xff);
  return payload;
}

TEST(FoxgloveServerTest, GreetsWithServerInfoAndAdvertisesEveryChannel) {
  FoxgloveServer server({});
  ASSERT_NE(server.port(), 0);
  const std::uint32_t cloth = server.AddChannel(TestChannel("/cloth"));
  const std::uint32_t scene = server.AddChannel(TestChannel("/scene"));
  EXPECT_NE(cloth, scene);

  TestClient client(server.port());
  ASSERT_TRUE(client.WaitOpen());
  const auto info = client.NextWithOp("serverInfo");
  ASSERT_TRUE(info);
  EXPECT_EQ((*info)["name"], "haptex");
  EXPECT_EQ((*info)["supportedEncodings"], json::array({"protobuf"}));
  const auto advertise = client.NextWithOp("advertise");
  ASSERT_TRUE(advertise);
  ASSERT_EQ((*advertise)["channels"].size(), 2U);
  EXPECT_EQ((*advertise)["channels"][0]["id"], cloth);
  EXPECT_EQ((*advertise)["channels"][0]["topic"], "/cloth");
  EXPECT_EQ(Base64Decode((*advertise)["channels"][1]["schema"].get<std::string>()), "schema-of-/scene");
  EXPECT_TRUE(WaitUntil([&] { return server.clients() == 1; }));
}

TEST(FoxgloveServerTest, AdvertisesAChannelAddedAfterTheClientConnected) {
  FoxgloveServer server({});
  TestClient client(server.port());
  ASSERT_TRUE(client.WaitOpen());
  ASSERT_TRUE(client.NextWithOp("serverInfo"));
  const std::uint32_t late = server.AddChannel(TestChannel("/late"));
  const auto advertise = client.NextWithOp("advertise");
  ASSERT_TRUE(advertise);
  ASSERT_EQ((*advertise)["channels"].size(), 1U);
  EXPECT_EQ((*advertise)["channels"][0]["id"], late);
  EXPECT_EQ((*advertise)["channels"][0]["topic"], "/late");
}

TEST(FoxgloveServerTest, ASubscriberReceivesTheExactBytesUntilItUnsubscribes) {
  FoxgloveServer server({});
  const std::uint32_t channel = server.AddChannel(TestChannel("/cloth"));
  const std::uint32_t other = server.AddChannel(TestChannel("/other"));
  EXPECT_FALSE(server.HasSubscribers(channel));
  TestClient client(server.port());
  ASSERT_TRUE(client.WaitOpen());
  client.SendText(Subscribe(42, channel));
  ASSERT_TRUE(WaitUntil([&] { return server.HasSubscribers(channel); }));
  EXPECT_FALSE(server.HasSubscribers(other));

  const std::string small = PayloadOf(10, 1);
  const std::string large = PayloadOf(100'000, 2);
  server.Publish(other, 5, "not subscribed");
  server.Publish(channel, 1'700'000'000'000'000'001ULL, small);
  server.Publish(channel, 2, large);
  server.Publish(channel, 3, "");
  const auto received = client.WaitBinaries(3);
  ASSERT_EQ(received.size(), 3U);
  EXPECT_EQ(received[0], MessageDataFrame(42, 1'700'000'000'000'000'001ULL, small));
  EXPECT_EQ(received[1], MessageDataFrame(42, 2, large));
  EXPECT_EQ(received[2], MessageDataFrame(42, 3, ""));
  EXPECT_EQ(server.counters().messages_sent, 3U);

  client.SendText(json{{"op", "unsubscribe"}, {"subscriptionIds", {42}}}.dump());
  ASSERT_TRUE(WaitUntil([&] { return !server.HasSubscribers(channel); }));
  server.Publish(channel, 4, small);
  EXPECT_EQ(server.counters().client_messages_bad, 0U);
}

TEST(FoxgloveServerTest, GarbageFromOneClientDoesNotDisturbAnothersStream) {
  FoxgloveServer server({});
  const std::uint32_t channel = server.AddChannel(TestChannel("/cloth"));
  TestClient good(server.port());
  ASSERT_TRUE(good.WaitOpen());
  good.SendText(Subscribe(1, channel));
  ASSERT_TRUE(WaitUntil([&] { return server.HasSubscribers(channel); }));

  TestClient bad(server.port());
  ASSERT_TRUE(bad.WaitOpen());
  const std::vector<std::string> garbage = {"not json",        "[1,2,3]",
                                            R"({"op":"fly"})", R"({"op":"subscribe"})",
                                            Subscribe(1, 999), R"({"op":"unsubscribe","subscriptionIds":[77]})"};
  for (const std::string& text : garbage) bad.SendText(text);
  bad.SendBinary(std::string("\x01\x00\x00\x00\x00junk", 9));
  bad.SendText(Subscribe(5, channel));
  bad.SendText(Subscribe(5, channel));  // the same subscription id again
  bad.SendText(Subscribe(6, channel));  // the same channel again
  const std::uint64_t expected_bad = garbage.size() + 3;
  ASSERT_TRUE(WaitUntil([&] { return server.counters().client_messages_bad == expected_bad; }));
  const auto status = bad.NextWithOp("status");
  ASSERT_TRUE(status);
  EXPECT_EQ((*status)["level"], 1);

  // Abrupt ends and odd visitors meanwhile: a socket that vanishes mid-subscription, one sending
  // bytes that are no WebSocket frame, one that is no HTTP, and the good client connecting twice.
  {
    RawSocket vanishing(server.port());
    EXPECT_NE(vanishing.Handshake().find("101"), std::string::npos);
    vanishing.WriteTextFrame(Subscribe(3, channel));
    RawSocket noise(server.port());
    noise.Handshake();
    noise.Write(std::string(64, '\xff'));
    RawSocket not_http(server.port());
    not_http.Write("\x16\x03\x01 definitely not HTTP\r\n\r\n");
    ASSERT_TRUE(WaitUntil([&] { return server.counters().clients_connected == 4; }));
  }
  TestClient twice(server.port());
  ASSERT_TRUE(twice.WaitOpen());
  twice.SendText(Subscribe(1, channel));

  constexpr int kMessages = 50;
  for (int i = 0; i < kMessages; ++i) server.Publish(channel, static_cast<std::uint64_t>(i), PayloadOf(1000, i));
  const auto received = good.WaitBinaries(kMessages);
  ASSERT_EQ(received.size(), static_cast<std::size_t>(kMessages));
  for (int i = 0; i < kMessages; ++i) {
    EXPECT_EQ(received[static_cast<std::size_t>(i)],
              MessageDataFrame(1, static_cast<std::uint64_t>(i), PayloadOf(1000, i)));
  }
  EXPECT_TRUE(WaitUntil([&] { return server.clients() == 3; }));  // good, bad, twice
  EXPECT_EQ(server.counters().messages_dropped_slow_client, 0U);
}

TEST(FoxgloveServerTest, RefusesAClientWithoutTheFoxgloveSubprotocol) {
  FoxgloveServer server({});
  TestClient stranger(server.port(), "");
  EXPECT_FALSE(stranger.WaitOpen());
  TestClient wrong(server.port(), "chat");
  EXPECT_FALSE(wrong.WaitOpen());
  EXPECT_EQ(server.counters().clients_refused, 2U);
  EXPECT_EQ(server.clients(), 0U);
}

TEST(FoxgloveServerTest, AClientThatDoesNotReadMissesMessagesAndPublishGoesOn) {
  FoxgloveServer::Options options;
  options.max_queued_bytes_per_client = 1 << 20;
  FoxgloveServer server(options);
  const std::uint32_t channel = server.AddChannel(TestChannel("/cloth"));
  RawSocket sleeper(server.port());
  sleeper.Handshake();
  sleeper.WriteTextFrame(Subscribe(9, channel));
  ASSERT_TRUE(WaitUntil([&] { return server.HasSubscribers(channel); }));
  TestClient reader(server.port());
  ASSERT_TRUE(reader.WaitOpen());
  reader.SendText(Subscribe(1, channel));
  ASSERT_TRUE(WaitUntil([&] {  // until the reader's subscription is in
    server.Publish(channel, 0, "probe");
    return !reader.WaitBinaries(1, 0ms).empty();
  }));

  // 40 MB: more than the sleeper's socket buffers and its 1 MB queue hold.
  constexpr int kMessages = 400;
  const std::string payload = PayloadOf(100'000, 7);
  for (int i = 1; i <= kMessages; ++i) {
    server.Publish(channel, static_cast<std::uint64_t>(i), payload);
    std::this_thread::sleep_for(2ms);
  }
  EXPECT_TRUE(WaitUntil([&] { return server.counters().messages_dropped_slow_client > 0; }));
  // The reader keeps its stream: in order, and it gets what comes after the flood.
  constexpr std::uint64_t kLast = kMessages + 1;
  ASSERT_TRUE(WaitUntil([&] {
    server.Publish(channel, kLast, "after the flood");
    const auto received = reader.WaitBinaries(1, 0ms);
    return ParseMessageDataFrame(received.back())->log_time_ns == kLast;
  }));
  std::uint64_t previous_time = 0;
  for (const std::string& frame : reader.WaitBinaries(0)) {
    const auto message = ParseMessageDataFrame(frame);
    ASSERT_TRUE(message);
    EXPECT_EQ(message->subscription_id, 1U);
    EXPECT_GE(message->log_time_ns, previous_time);
    previous_time = message->log_time_ns;
  }
  EXPECT_EQ(server.clients(), 2U);
}

TEST(FoxgloveServerTest, ServesStaticFilesAndRefusesTraversal) {
  namespace fs = std::filesystem;
  const fs::path base = fs::temp_directory_path() / "haptex_foxglove_server_http";
  fs::remove_all(base);
  fs::create_directories(base / "site");
  fs::create_directories(base / "three");
  std::ofstream(base / "site/index.html") << "<html>viewer</html>";
  std::ofstream(base / "three/three.module.js") << "export const REVISION = '170';";
  std::ofstream(base / "secret.txt") << "secret";
  FoxgloveServer::Options options;
  options.web_root = (base / "site").string();
  options.three_root = (base / "three").string();
  FoxgloveServer server(options);

  auto get = [&](const std::string& target) {
    RawSocket socket(server.port());
    socket.Write("GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
    return socket.ReadToEnd();
  };
  const std::string index = get("/");
  EXPECT_NE(index.find("HTTP/1.1 200"), std::string::npos) << index;
  EXPECT_NE(index.find("Content-Type: text/html; charset=utf-8"), std::string::npos) << index;
  EXPECT_NE(index.find("<html>viewer</html>"), std::string::npos);
  const std::string three = get("/three/three.module.js");
  EXPECT_NE(three.find("Content-Type: text/javascript"), std::string::npos) << three;
  EXPECT_NE(three.find("REVISION"), std::string::npos);
  for (const std::string target : {"/../secret.txt", "/%2e%2e/secret.txt", "/three/../../secret.txt", "/missing.js"}) {
    const std::string response = get(target);
    EXPECT_NE(response.find("HTTP/1.1 404"), std::string::npos) << target << ": " << response;
    EXPECT_EQ(response.find("secret\n"), std::string::npos);
  }
  const std::string post = [&] {
    RawSocket socket(server.port());
    socket.Write("POST / HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\nConnection: close\r\n\r\n");
    return socket.ReadToEnd();
  }();
  EXPECT_NE(post.find("HTTP/1.1 405"), std::string::npos) << post;
  EXPECT_EQ(server.counters().http_requests, 7U);
  EXPECT_EQ(server.counters().http_not_found, 5U);
  fs::remove_all(base);
}

TEST(FoxgloveServerTest, ThrowsWhenItCannotBind) {
  FoxgloveServer first({});
  FoxgloveServer::Options options;
  options.port = first.port();
  try {
    FoxgloveServer second(options);
    FAIL() << "bound a port that is in use";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(std::to_string(first.port())), std::string::npos) << error.what();
  }
  options.bind_address = "not an address";
  EXPECT_THROW(FoxgloveServer{options}, std::runtime_error);
}

TEST(FoxgloveServerTest, PublishingToNobodyOrAnUnknownChannelIsHarmless) {
  FoxgloveServer server({});
  server.Publish(12345, 1, "nobody");
  const std::uint32_t channel = server.AddChannel(TestChannel("/cloth"));
  server.Publish(channel, 1, "nobody listens");
  EXPECT_EQ(server.counters().messages_sent, 0U);
  EXPECT_EQ(server.counters().messages_dropped_slow_client, 0U);
}

}  // namespace
}  // namespace haptex::viewer
