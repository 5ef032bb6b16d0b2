#pragma once
// Shared pieces of the endpoint tests: a real-time executor on an io_context, a log sink that
// keeps lines for assertions, and an echoing vehicle client built on LoopbackClient.
#include <boost/asio/io_context.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "loopback_client.hpp"
#include "ocp/asio_executor.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/log.hpp"

namespace ocp::testing {

// Keeps every log line ("WARN streamer:vehicle: …") so tests can check what a person would read.
struct CapturedLog {
  std::vector<std::string> lines;
  LogSink sink() {
    return [this](const LogRecord& record) {
      lines.push_back(std::string(log_level_name(record.level)) + " " + std::string(record.component) +
                      ": " + std::string(record.message));
    };
  }
  bool contains(const std::string& needle) const {
    for (const auto& line : lines) {
      if (line.find(needle) != std::string::npos) return true;
    }
    return false;
  }
};

// A vehicle client that answers every control message at once with its ack pair.
class EchoingVehicle {
 public:
  explicit EchoingVehicle(boost::asio::io_context& io) : client_(io) {
    client_.on_payload = [this](const std::string& payload) {
      auto message = decode_control_message(payload);
      if (!message) {
        ++undecodable_;
        return;
      }
      messages_.push_back(*message);
      if (!echo_) return;
      VehicleResponseMessage response;
      response.ack = message->ack;
      if (user_data_) response.vehicle_user_data = VehicleUserData{std::nullopt, RawJson{*user_data_}};
      std::string json;
      encode_vehicle_response(response, json);
      client_.send_payload(json);
    };
  }

  bool connect(std::uint16_t port) { return client_.connect(port); }
  void set_echo(bool echo) { echo_ = echo; }
  void set_user_data(std::string json) { user_data_ = std::move(json); }

  LoopbackClient& client() { return client_; }
  const std::vector<OcpControlMessage>& messages() const { return messages_; }
  std::size_t undecodable() const { return undecodable_; }

 private:
  LoopbackClient client_;
  bool echo_ = true;
  std::optional<std::string> user_data_;
  std::vector<OcpControlMessage> messages_;
  std::size_t undecodable_ = 0;
};

}  // namespace ocp::testing
