// The oracle's view of the Player's :4001 port (oracle.hpp), in worlds with an operator client
// (world.operator_client). Read from SPEC §2 and §4 by the oracle itself:
//   * a broken client frame (malformed JSON, not an object, a field of the wrong type) closes
//     the connection at once, for that reason; an oversized one is drained and the connection
//     kept; no byte for the read timeout closes it, and nothing closes it earlier;
//   * one client at a time: a second connection is refused while one is open, and only then;
//   * a keep-alive (no active_vehicle, no client data) locks no source (§4.2 Decision);
//   * each VehicleOcpShared entry's sender_fault is the Player's own operator faults as it
//     reported them, and receiver_fault the vehicle faults carried by the last feedback message
//     the Player got from that Streamer (as the Streamer had reported them when it sent it);
//   * liveness: once the last misbehaviour is over, the client is connected again.
#include <rapidjson/document.h>

#include "oracle_state.hpp"

namespace ocp::campaign {

namespace {

constexpr std::size_t max_feedback_in_flight = 1u << 14;
// VehicleOcpShared is read after anything its lists depend on changed, and otherwise every
// this many frames: reading every frame would double a world's CPU.
constexpr std::uint64_t list_sample_period = 16;

struct ClientFrameReading {
  bool valid = true;
  bool keep_alive = true;                // carries no client data (§4.2 Decision)
  std::optional<PeerError> reason;       // invalid: the close reason SPEC names, when exact
  std::string what;
};

bool is_bad_frame_reason(const std::error_code& code) {
  for (PeerError e : {PeerError::malformed_json, PeerError::not_an_object, PeerError::missing_field,
                      PeerError::wrong_type, PeerError::out_of_range, PeerError::too_deep}) {
    if (code == make_error_code(e)) return true;
  }
  return false;
}

// ClientOcpShared (SPEC §4.2), every field optional. Whether a wrongly typed field inside a
// client_user_data entry is "wrong type" or "out of range" is the decoder's call: the oracle
// names the exact reason only where SPEC leaves no choice.
ClientFrameReading read_client_frame(std::string_view payload) {
  rapidjson::Document document;
  document.Parse<rapidjson::kParseIterativeFlag>(payload.data(), payload.size());
  if (document.HasParseError()) return {false, false, PeerError::malformed_json, "malformed JSON"};
  if (!document.IsObject()) return {false, false, PeerError::not_an_object, "a JSON value that is not an object"};
  ClientFrameReading reading;
  if (const auto active = document.FindMember("active_vehicle"); active != document.MemberEnd()) {
    if (!active->value.IsString() && !active->value.IsNull()) {
      return {false, false, PeerError::wrong_type, "active_vehicle neither a string nor null"};
    }
    reading.keep_alive = false;   // null included: a client that names it may mean to clear it
  }
  const auto data = document.FindMember("client_user_data");
  if (data == document.MemberEnd()) return reading;
  if (!data->value.IsObject()) return {false, false, std::nullopt, "client_user_data not an object"};
  for (const auto& entry : data->value.GetObject()) {
    if (!entry.value.IsObject()) return {false, false, std::nullopt, "a client_user_data entry not an object"};
    for (const auto& field : entry.value.GetObject()) {
      const std::string_view name(field.name.GetString(), field.name.GetStringLength());
      const bool bad = (name == "ocp_disable_gamepad" && !field.value.IsBool()) ||
                       (name == "ack_time_returned" && !field.value.IsUint64()) ||
                       (name == "ack_time_mac_returned" && !field.value.IsUint());
      if (bad) return {false, false, std::nullopt, "client_user_data." + std::string(name) + " of the wrong type"};
      reading.keep_alive = false;
    }
  }
  return reading;
}

// The scenario expectations a shrunk world states (shrink.cpp, regression_yaml).
scenario::ExpectationKind operator_close_between(SimTime from, SimTime until) {
  scenario::EventExpectation close;
  close.kind = scenario::NotableKind::connection_closed;
  close.wire = Wire::operator_;
  close.from = from;
  close.until = until;
  return close;
}

// The identifiers of a fault set in table order, each between `quote`s: "[A, B]" for a
// person, "["A", "B"]" for a scenario file's JSON.
std::string fault_list(FaultBits bits, std::string_view quote) {
  std::string list;
  for (std::size_t f = 0; f < fault_count; ++f) {
    if (!bits.has(static_cast<FaultId>(f))) continue;
    list += (list.empty() ? "" : ", ") + std::string(quote) + std::string(fault_identifier(static_cast<FaultId>(f))) +
            std::string(quote);
  }
  return "[" + list + "]";
}

std::string fault_list_text(FaultBits bits) { return fault_list(bits, ""); }

scenario::ExpectationKind fault_list_at(const std::string& vehicle, const char* field, FaultBits bits, SimTime at) {
  scenario::FeedbackExpectation feedback;
  feedback.vehicle = vehicle;
  feedback.checks.push_back({field, fault_list(bits, "\""), true});
  feedback.from = at;
  feedback.until = at;
  feedback.instant = true;
  return feedback;
}

// A list of fault identifiers as bits; nullopt when it is not a list of known identifiers.
std::optional<FaultBits> fault_list_bits(const rapidjson::Value& entry, const char* key) {
  const auto list = entry.FindMember(key);
  if (list == entry.MemberEnd() || !list->value.IsArray()) return std::nullopt;
  FaultBits bits;
  for (const auto& item : list->value.GetArray()) {
    if (!item.IsString()) return std::nullopt;
    const std::string_view name(item.GetString(), item.GetStringLength());
    bool known = false;
    for (std::size_t f = 0; f < fault_count && !known; ++f) {
      if (fault_identifier(static_cast<FaultId>(f)) == name) {
        bits.set(static_cast<FaultId>(f), true);
        known = true;
      }
    }
    if (!known) return std::nullopt;
  }
  return bits;
}

}  // namespace

void Oracle::on_operator_connection(SimTime now, const ConnectionEvent& connection) {
  OperatorPort& port = *operator_;
  const std::string peer(connection.peer);
  switch (connection.change) {
    case ConnectionChange::opened:
      if (port.open) {
        report(Check::operator_port, now, "",
               "a second operator connection (" + peer + ") was accepted while " + port.peer +
                   " was open (SPEC §4.2: one client at a time)");
      }
      port.open = true;
      port.peer = peer;
      port.opened = port.last_frame_in = now;
      port.pending.reset();
      port.silence_reported = false;
      return;
    case ConnectionChange::refused:
      if (!port.open) report(Check::operator_port, now, "", "connection " + peer + " was refused though no client was connected");
      return;
    case ConnectionChange::closed: break;
  }
  if (!port.open || peer != port.peer) return;
  const std::error_code code = connection.reason != nullptr ? connection.reason->code : std::error_code{};
  const std::string why = error_code_id(code);
  if (port.pending) {
    const OperatorPort::PendingClose pending = *port.pending;
    port.pending.reset();
    port.open = false;
    const bool right = (pending.expected ? code == make_error_code(*pending.expected) : is_bad_frame_reason(code));
    if (!right || now > pending.at + tolerances_.real_time_slack) {
      report(Check::operator_port, now, "",
             "the connection closed for " + why + " " + ms_text(now - pending.at) + " after a frame with " +
                 pending.what + (pending.expected ? " (SPEC §2: " + error_code_id(make_error_code(*pending.expected)) + ", at once)" : ""));
    }
    return;
  }
  check_operator_port(now);   // a close that comes later than the read timeout
  port.open = false;
  const Micros silence = now - port.last_frame_in;
  if (code == make_error_code(PeerError::read_timeout)) {
    if (silence + tolerances_.real_time_slack < port.read_timeout) {
      report(Check::operator_port, now, "",
             "closed for a read timeout after " + ms_text(silence) + " without a frame (timeout " +
                 ms_text(port.read_timeout) + ")");
    }
    return;
  }
  // The client's own doing (it hung up, mid-frame or not), the end of the run, a client that
  // stopped reading, and a nesting limit SPEC does not set: nothing for the oracle to judge.
  for (const std::error_code accepted :
       {make_error_code(PeerError::closed_by_peer), make_error_code(PeerError::truncated_frame),
        make_error_code(PeerError::not_reading), make_error_code(PeerError::too_deep),
        make_error_code(LocalError::shut_down)}) {
    if (code == accepted) return;
  }
  report(Check::operator_port, now, "",
         "the connection closed for " + why + " though no frame or silence explains it" +
             (connection.reason != nullptr ? ": " + connection.reason->detail : std::string()));
}

void Oracle::on_operator_frame(SimTime now, const WireFrame& frame) {
  OperatorPort& port = *operator_;
  check_operator_port(now);
  if (frame.direction == FrameDirection::in) {
    if (!port.open || frame.peer != port.peer) return;
    port.last_frame_in = now;
    if (frame.length_prefix > max_oracle_frame_payload) {
      if (!frame.drained) {
        report(Check::operator_port, now, "",
               "a " + std::to_string(frame.length_prefix) + "-byte client frame was read, not drained (SPEC §2)");
      }
      return;
    }
    const ClientFrameReading reading = read_client_frame(frame.payload);
    if (!reading.valid) {
      port.pending = OperatorPort::PendingClose{now, reading.reason, reading.what};
    } else if (!reading.keep_alive) {
      port.client_data_sent = true;
    }
    if (port.lock_to_judge) judge_tcp_lock(*port.lock_to_judge);
    return;
  }
  if (frame.kind != WireMessageKind::vehicle_ocp_shared) return;
  ++port.shared_frames;
  if (port.lists_changed || port.shared_frames % list_sample_period == 0) {
    port.lists_changed = false;
    check_feedback_lists(now, frame.payload);
  }
}

// What is due by now: the close after a broken frame (at once), and after silence.
void Oracle::check_operator_port(SimTime now) {
  OperatorPort& port = *operator_;
  if (!port.open) return;
  if (port.pending && now > port.pending->at + tolerances_.real_time_slack) {
    report(Check::operator_port, now, "",
           "a client frame with " + port.pending->what + " at " + ms_text(port.pending->at) +
               " did not close the connection (SPEC §2)",
           std::nullopt, false, operator_close_between(port.pending->at, port.pending->at + tolerances_.player_frame));
    port.pending.reset();
  }
  const Micros silence = now - port.last_frame_in;
  if (!port.silence_reported && port.read_timeout > Micros{0} &&
      silence > port.read_timeout + tolerances_.player_frame + tolerances_.real_time_slack) {
    port.silence_reported = true;
    report(Check::operator_port, now, "",
           "no client frame for " + ms_text(silence) + " and the connection is still open (read timeout " +
               ms_text(port.read_timeout) + ", SPEC §2)",
           std::nullopt, false,
           operator_close_between(port.last_frame_in, port.last_frame_in + port.read_timeout + tolerances_.player_frame));
  }
}

void Oracle::on_source_locked(SimTime now, const SourceLocked& locked) {
  if (locked.source == ClientSource::tcp) operator_->lock_to_judge = now;
}

void Oracle::judge_tcp_lock(SimTime now) {
  operator_->lock_to_judge.reset();
  if (operator_->client_data_sent) return;
  scenario::EventExpectation no_lock;
  no_lock.kind = scenario::NotableKind::source_locked;
  no_lock.never = true;
  no_lock.source = ClientSource::tcp;
  report(Check::operator_port, now, "",
         "the tcp source was locked though the operator client sent only keep-alives (SPEC §4.2)", std::nullopt,
         false, no_lock);
}

// Feedback messages to the Player, for the receiver_fault list it must show.
void Oracle::on_feedback_link(VehicleState& state, const LinkEvent& link) {
  switch (link.outcome) {
    case LinkOutcome::sent: state.feedback_in_flight.send(link.message_id, state.reported_vehicle, max_feedback_in_flight); return;
    case LinkOutcome::duplicated: state.feedback_in_flight.duplicate(link.message_id); return;
    case LinkOutcome::dropped: (void)state.feedback_in_flight.take(link.message_id); return;
    case LinkOutcome::delivered: break;
  }
  const std::optional<FaultBits> faults = state.feedback_in_flight.take(link.message_id);
  if (!faults) {
    state.player_receiver_known = false;   // not tied to a send the oracle saw
    return;
  }
  if (faults->bits != state.player_has_receiver.bits || !state.player_receiver_known) operator_->lists_changed = true;
  state.player_has_receiver = *faults;
  state.player_receiver_known = true;
}

void Oracle::check_feedback_lists(SimTime now, std::string_view payload) {
  rapidjson::Document document;
  document.Parse<rapidjson::kParseIterativeFlag>(payload.data(), payload.size());
  if (document.HasParseError() || !document.IsObject()) return;   // not this check's business
  const auto entries = document.FindMember("vehicle_feedback");
  if (entries == document.MemberEnd() || !entries->value.IsObject()) return;
  for (const auto& entry : entries->value.GetObject()) {
    const auto found = vehicles_.find(std::string_view(entry.name.GetString(), entry.name.GetStringLength()));
    if (found == vehicles_.end() || !entry.value.IsObject()) continue;
    VehicleState& state = *found->second;
    const std::optional<FaultBits> sender = fault_list_bits(entry.value, "sender_fault");
    const std::optional<FaultBits> receiver = fault_list_bits(entry.value, "receiver_fault");
    std::string problem;
    std::optional<scenario::ExpectationKind> regression;
    if (!sender || sender->bits != state.reported_operator.bits) {
      problem = "sender_fault " + (sender ? fault_list_text(*sender) : std::string("unreadable")) +
                ", the Player's faults " + fault_list_text(state.reported_operator);
      regression = fault_list_at(state.name, "sender_fault", state.reported_operator, now);
    } else if (state.player_receiver_known && (!receiver || receiver->bits != state.player_has_receiver.bits)) {
      problem = "receiver_fault " + (receiver ? fault_list_text(*receiver) : std::string("unreadable")) +
                ", the last feedback delivered carried " + fault_list_text(state.player_has_receiver);
      regression = fault_list_at(state.name, "receiver_fault", state.player_has_receiver, now);
    }
    if (problem.empty()) {
      state.feedback_mismatch = false;
    } else if (!state.feedback_mismatch) {
      state.feedback_mismatch = true;
      report(Check::operator_feedback, now, state.name, "VehicleOcpShared: " + problem, std::nullopt, false,
             std::move(regression));
    }
  }
}

// Once every disturbance is over (liveness_at_): the operator client is connected again.
void Oracle::check_operator_liveness(SimTime now) {
  OperatorPort& port = *operator_;
  if (port.liveness_done) return;
  port.liveness_done = true;
  if (port.misbehaving_at_end || port.open) return;
  report(Check::liveness, now, "",
         "the operator client is not connected " + ms_text(liveness_bound(scenario_)) + " after the last disturbance");
}

}  // namespace ocp::campaign
