#pragma once
// The reference vehicle client (SPEC §3, §10): protocol logic over any ByteStream, with time
// from the Executor, so the same code runs over TCP in real time and over an in-memory pipe
// inside a virtual-time world.
//
//   VehicleClient client(executor, config, logger);
//   client.attach(stream);            // an established connection (pipe end or TCP stream)
//
// What it does on the wire:
//   * decodes each frame with the libocp codec;
//   * after each control message echoes its ack pair AT ONCE, inside the same on_bytes call
//     (no timer, no queue), so it adds as little as possible to the measured latency: once a
//     valid control message has been seen, the pair is echoed as soon as the frame is
//     tokenized, before the rest is decoded and validated (a message that then fails
//     validation still closes the connection, its pair already answered);
//   * also sends a response whenever `response_period` passed without one, so the Streamer's
//     2 s read timeout never fires while the client is alive, even if control pauses;
//   * every response carries vehicle_user_data: pos from the vehicle model and user_data
//     {speed_mps, heading_deg, drive_state, safety_reasons, sequence, timestamp_ms, …},
//     always well under 16 KiB (checked);
//   * a bad frame from the server closes the connection and reports why.
// Besides the wire, a model timer runs the safety layer and the vehicle model at
// `model_step`; the response path never waits for them.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "ocp/byte_stream.hpp"
#include "ocp/executor.hpp"
#include "ocp/flap_summariser.hpp"
#include "ocp/frame.hpp"
#include "ocp/framing_diagnosis.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/liveness_token.hpp"
#include "ocp/log.hpp"
#include "ocp/messages.hpp"
#include "vehicle_client/misbehaviour.hpp"
#include "vehicle_client/safety_layer.hpp"
#include "vehicle_client/vehicle_model.hpp"

namespace ocp {

struct VehicleClientConfig {
  SafetyConfig safety;                      // watchdog, actuator limits, interlock deadband
  VehicleParams vehicle;                    // bicycle model parameters
  Position start{57.7089, 11.9746};         // start lat/lon (Gothenburg)
  double start_heading_deg = 0.0;           // compass heading at start
  Micros response_period{10'000};           // longest gap between two responses
  // On an AsioExecutor a keep-alive may go out up to this much after response_period
  // (Executor::call_at_or_later): the checks of one executor's clients then share a wake-up
  // instead of one each just after its own echo (~20 µs of CPU each on a VM; issue #41). A
  // VirtualExecutor keeps response_period exactly. SPEC §3.3 asks only that a keep-alive wait
  // for response_period.
  Micros keepalive_slack{1'000};
  Micros model_step{10'000};                // safety + model integration step
  // 0: the model timer ticks at attach + k·model_step. > 0: at the multiples of model_grid on
  // the executor's timeline (the first at or after attach + model_step), so the clients that
  // one process hosts on one executor share their model ticks' instants: on a VM each distinct
  // timer instant is a wake-up costing ~20 µs of CPU (docs/benchmarks.md, issue #41 part 3).
  // Nothing on the wire depends on the phase; the model still integrates in model_step steps.
  Micros model_grid{0};
  // No control message for this long after attach (or since the last one) → close: "no data
  // from the server" (not a byte arrived: a stopped or hung server, whatever it is), "not an
  // OCP server" (bytes arrived that are not OCP framing) or "server stopped sending".
  Micros server_silence_limit{2'000'000};
  std::size_t user_data_limit_bytes = 4096; // hard cap on encoded user_data (<< 16 KiB)
  Misbehaviour misbehave;
};
std::optional<std::string> validate(const VehicleClientConfig& config);

// Why a connection ended (the string given to on_disconnected says the same in words).
enum class DisconnectKind : std::uint8_t {
  none,
  peer_closed,        // the server closed or the transport failed
  protocol_error,     // a frame the codec rejected after a valid control message was seen
  not_an_ocp_server,  // bad frame length or non-OCP data before any valid control message
  server_silent,      // control messages stopped for server_silence_limit, or none came
                      // within it of attaching (no byte at all, or only part of a frame)
  misbehaved,         // a misbehaviour hung up on purpose (bad-response eof-mid-frame)
};
std::string_view disconnect_kind_name(DisconnectKind kind);

struct VehicleClientStats {
  std::uint64_t connections = 0;               // attach() calls
  std::uint64_t control_messages_received = 0;
  std::uint64_t responses_sent = 0;            // all response frames written
  std::uint64_t echo_responses_sent = 0;       // …of which sent right after a control message
  std::uint64_t keepalive_responses_sent = 0;  // …of which sent because response_period passed
  std::uint64_t oversized_frames_dropped = 0;  // inbound frames > 16 KiB (drained, kept going)
  std::uint64_t bytes_received = 0;
  std::uint64_t bytes_sent = 0;
  std::size_t largest_response_bytes = 0;      // payload bytes of the largest response
  std::optional<AckPair> last_ack;             // latest pair received from the Streamer
  std::optional<SimTime> last_control_time;
  std::uint64_t last_latency_ms = 0;           // telemetry.latency of the latest message
  bool last_telemetry_fault = false;
  std::string last_fault_reason;               // for display only; never drives decisions
  DisconnectKind last_disconnect_kind = DisconnectKind::none;
  std::string last_disconnect_reason;
};

class VehicleClient {
 public:
  VehicleClient(Executor& executor, VehicleClientConfig config, Logger logger);
  ~VehicleClient();
  VehicleClient(const VehicleClient&) = delete;
  VehicleClient& operator=(const VehicleClient&) = delete;

  // Takes over an established connection; any previous one is detached first. The safety
  // layer is reset (drive disabled until the operator enables again) and the model timer runs
  // from now on (also after a disconnect, so the vehicle brakes to a stop).
  void attach(std::shared_ptr<ByteStream> stream);
  // Closes the current connection locally; on_disconnected is not called.
  void detach();
  // Switches the deliberate protocol violations (misbehaviour.hpp) at run time: they apply
  // from the next response on (a scenario turns one on and off on its timeline).
  void set_misbehaviour(const Misbehaviour& misbehave) { config_.misbehave = misbehave; }
  bool connected() const;
  // Called when the peer closes or the client closes because of bad data / silence.
  void set_on_disconnected(std::function<void(const std::string& reason)> callback);

  const VehicleClientStats& stats() const { return stats_; }
  const SafetyOutput& safety() const;
  const VehicleState& vehicle() const;
  const VehicleClientConfig& config() const { return config_; }
  // The user_data JSON sent in responses right now (for tests and the status line).
  const std::string& user_data_json() const;

 private:
  enum class ResponseCause { echo, keepalive };
  void on_bytes(std::string_view bytes);
  void on_closed(const std::string& reason);
  [[nodiscard]] bool check_first_header(std::string_view bytes);
  void handle_payload(std::string_view payload);
  void echo(const AckPair& pair);   // the response that carries a control message's pair back
  void handle_control_message(const OcpControlMessage& message);
  void close_with(DisconnectKind kind, const std::string& reason);
  void write_bad_response(BadResponse kind);
  void release_connection();
  void finish_disconnect(DisconnectKind kind, const std::string& reason);
  void send_response(ResponseCause cause);
  void arm_keepalive(SimTime deadline);
  void on_keepalive(bool deferred);
  void arm_silence_check(SimTime deadline);
  void on_silence_check();
  void on_model_tick(SimTime deadline);
  SimTime first_model_tick(SimTime attached) const;   // config_.model_grid
  // Encodes user_data for the current model sample (at construction and every model step);
  // every response until the next sample reuses the text as is.
  void refresh_user_data();

  Executor& executor_;
  VehicleClientConfig config_;
  Logger logger_;
  SafetyLayer safety_;
  KinematicBicycle model_;
  PeriodicTimer model_timer_;
  // Callbacks handed to streams and the executor hold a weak copy: once the client is gone
  // they do nothing, whoever outlives whom.
  LivenessToken liveness_;  // socket handlers and timers watch it: no-ops once this is destroyed
  std::shared_ptr<ByteStream> stream_;
  std::uint64_t connection_id_ = 0;            // bumped on every (de)attach: stale callbacks no-op
  FrameDecoder decoder_;
  ControlMessageDecoder control_decoder_;      // its own tape: the echo goes out between its two steps
  // A first frame over the payload limit: the peer is no OCP server (check_first_header).
  static constexpr auto first_frame_implausible_from = static_cast<std::uint32_t>(max_payload_bytes + 1);
  FramingSniffer sniffer_{first_frame_implausible_from};
  std::function<void(const std::string&)> on_disconnected_;
  VehicleClientStats stats_;
  FlapSummariser fault_flaps_{"Streamer-reported fault"};  // the log line, not the decisions
  bool seen_valid_control_ = false;
  std::uint64_t bytes_at_attach_ = 0;          // stats_.bytes_received when this connection began
  std::optional<AckPair> echo_pair_;           // the pair responses carry
  std::optional<SimTime> last_response_time_;
  Executor::TimerId keepalive_timer_ = 0;
  Executor::TimerId silence_timer_ = 0;
  std::uint64_t user_data_sequence_ = 0;
  VehicleResponseMessage response_;            // prepared response; only the pair changes per echo
  std::string payload_buffer_;                 // reused for encoding responses
  std::string frame_buffer_;
};

}  // namespace ocp
