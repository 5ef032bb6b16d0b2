// The operator client stand-in (operator_client.hpp).
#include "operator_client.hpp"

#include "ocp/json_codec.hpp"
#include "ocp/pipe.hpp"

namespace ocp::scenario {
namespace {

// A keep-alive: no active_vehicle, no client data (SPEC §4.2): locks no source.
constexpr std::string_view operator_keep_alive_payload = "{}";
// One byte over the 16 KiB payload limit, still a JSON object: only its size is wrong.
constexpr std::size_t operator_oversized_payload_bytes = max_payload_bytes + 1;

std::string operator_frame_of(std::string_view payload) {
  std::string frame;
  append_length_prefix(static_cast<std::uint32_t>(payload.size()), frame);
  frame.append(payload);
  return frame;
}

std::string operator_oversized_payload() {
  std::string payload = "{\"pad\":\"";
  payload.append(operator_oversized_payload_bytes - payload.size() - 2, 'x');
  payload += "\"}";
  return payload;
}

}  // namespace

OperatorClient::OperatorClient(World& world, const OperatorClientSetting& setting)
    : world_(world), setting_(setting), keep_alive_(world.executor(), setting.keep_alive_period, [this](SimTime) {
        on_keep_alive_tick();
      }) {}

OperatorClient::~OperatorClient() { stop(); }

void OperatorClient::start() {
  running_ = true;
  connect();
  keep_alive_.start(world_.executor().now() + setting_.keep_alive_period);
}

void OperatorClient::stop() {
  running_ = false;
  keep_alive_.stop();
  world_.executor().cancel(reconnect_timer_);
  reconnect_timer_ = 0;
  alive_ = std::make_shared<bool>(true);   // handlers of the old streams see a dead token
  if (stream_) stream_->close();
  stream_.reset();
  for (const auto& end : second_connections_) end->close();
  second_connections_.clear();
}

std::shared_ptr<ByteStream> OperatorClient::new_connection(const std::string& name) {
  PipeOptions options;
  options.name_a = name;
  options.name_b = "pipe:player:4001";
  PipeEnds ends = make_pipe(world_.executor(), options);
  world_.player().accept_client_connection(std::move(ends.b));
  return std::move(ends.a);
}

void OperatorClient::connect() {
  ++connections_;
  decoder_ = FrameDecoder();
  stream_ = new_connection("pipe:operator-client");
  std::weak_ptr<bool> alive = alive_;
  stream_->set_handlers(ByteStreamHandlers{
      .on_bytes = [this, alive](std::string_view bytes) {
        if (!alive.expired()) on_bytes(bytes);
      },
      .on_closed = [this, alive](const std::string&) {
        if (!alive.expired()) on_connection_lost();
      },
  });
}

// Reads every frame as a client would; what they say is on the event stream already.
void OperatorClient::on_bytes(std::string_view bytes) {
  decoder_.put_all(bytes, [this](std::string_view) {
    ++frames_read_;
    return true;
  });
}

void OperatorClient::on_connection_lost() {
  alive_ = std::make_shared<bool>(true);
  stream_.reset();
  if (!running_ || reconnect_timer_ != 0) return;
  reconnect_timer_ = world_.executor().call_after(setting_.reconnect_backoff, [this] {
    reconnect_timer_ = 0;
    if (running_ && !stream_) connect();
  });
}

void OperatorClient::on_keep_alive_tick() {
  if (!stream_ || !stream_->is_open() || misbehave_.silent) return;
  const std::string frame = next_frame();
  stream_->write(frame);
  if (misbehave_.bad_message == BadClientMessage::eof_mid_frame && !misbehave_.malformed_json &&
      !misbehave_.oversized_frames) {
    // Half a frame, then the client hangs up: the Player sees the stream end inside it.
    stream_->close();
    on_connection_lost();
  }
}

// One misbehaviour a frame, in this order: malformed JSON, oversized, the bad message.
std::string OperatorClient::next_frame() const {
  if (misbehave_.malformed_json) return operator_frame_of("{\"active_vehicle\": ");
  if (misbehave_.oversized_frames) return operator_frame_of(operator_oversized_payload());
  switch (misbehave_.bad_message) {
    case BadClientMessage::none: break;
    case BadClientMessage::not_an_object: return operator_frame_of("[]");
    case BadClientMessage::wrong_type: return operator_frame_of("{\"active_vehicle\": 5}");
    case BadClientMessage::eof_mid_frame: {
      const std::string whole = operator_frame_of("{\"active_vehicle\": null}");
      return whole.substr(0, whole.size() / 2);
    }
  }
  return operator_frame_of(operator_keep_alive_payload);
}

void OperatorClient::open_second_connection() {
  std::shared_ptr<ByteStream> end = new_connection("pipe:second-operator-client");
  // Nothing to read: the Player refuses it at once (its close is seen by nobody here).
  end->set_handlers(ByteStreamHandlers{.on_bytes = [](std::string_view) {}, .on_closed = [](const std::string&) {}});
  second_connections_.push_back(std::move(end));
}

bool OperatorClient::send_client_data(const ClientOcpShared& message) {
  if (!stream_ || !stream_->is_open() || misbehave_.silent) return false;
  std::string payload;
  encode_client_ocp_shared(message, payload);
  stream_->write(operator_frame_of(payload));
  return true;
}

}  // namespace ocp::scenario
