#pragma once
// The web view wire protocol (docs/webview.md): WebSocket text messages, both directions,
//   {"name": "<message name>", "data": <any JSON>}
// Browser → Player: ocp_client_user_data (ClientOcpShared without the pair, SPEC §4.2).
// Player → browser: ocp_vehicle_user_data (VehicleOcpShared, SPEC §4.1, every Player frame),
//                   ocp_webview_status (the client-data source lock, whether the :4001 client's
//                   VehicleOcpShared is too large to send, whether a locked tcp source lost
//                   its client, why loops do not close; on connect and on change),
//                   ocp_webview_error (why a message of this page was dropped; first of a kind).
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/error.hpp"
#include "ocp/messages.hpp"

namespace ocp {
struct ClientFrameTooLarge;   // player/player_core.hpp
}

namespace ocp::webview {

inline constexpr std::string_view vehicle_data_name = "ocp_vehicle_user_data";
inline constexpr std::string_view client_data_name = "ocp_client_user_data";
inline constexpr std::string_view status_name = "ocp_webview_status";
inline constexpr std::string_view error_name = "ocp_webview_error";

// Largest inbound WebSocket message (browser → Player) taken in; bigger ones are drained and
// dropped. A ClientOcpShared must fit a 16 KiB control frame anyway (SPEC §2).
inline constexpr std::size_t max_message_bytes = 64 * 1024;

struct InboundMessage {
  std::string name;
  std::string data_json;   // the "data" value re-serialized (integers stay exact)
};

// Parses the envelope. Errors (malformed JSON, not an object, "name" missing or not a string,
// "data" missing) carry a detail for the log.
[[nodiscard]] Result<InboundMessage> parse_envelope(std::string_view text);

// {"name":"<name>","data":<data_json>}; data_json must already be valid JSON.
std::string make_envelope(std::string_view name, std::string_view data_json);

// SPEC §4.2 Decisions: a call that names nothing (no active_vehicle, no entry) must not lock the
// source (a page that only keeps itself alive is still listen-only); one that names a vehicle,
// even with a bare entry ({"truck-1": {}}), is client data: the Player injects its pair.
bool is_keep_alive(const ClientOcpShared& data);

// What a page needs to show the source-locking banner (SPEC §4.3).
struct Status {
  std::optional<std::string> locked_source;   // "tcp" | "webview" | "plugin"; null = self-echo
  bool client_data_stopped = false;           // a source conflict stopped client data
  std::optional<std::string> active_vehicle;  // the vehicle that gets gamepad input now
  std::vector<std::string> vehicles;
  std::size_t webview_clients = 0;
  // The :4001 TCP client's VehicleOcpShared is over the frame limit, so that client receives
  // nothing (SPEC §2; PlayerCore::client_frame_too_large). The web view itself still gets it.
  struct ClientFrameTooLarge {
    std::size_t bytes = 0;      // the latest VehicleOcpShared
    std::size_t limit = 0;      // 16 384
    std::size_t vehicles = 0;   // vehicle entries in it
    bool operator==(const ClientFrameTooLarge&) const = default;
  };
  std::optional<ClientFrameTooLarge> client_frame_too_large;   // not in the JSON while it fits
  // SPEC §4.3 Decision: the locked tcp client left, nobody returns pairs; the text to show
  // (tcp_lock_without_client_text). Not in the JSON otherwise.
  std::optional<std::string> tcp_lock_without_client;
  // vehicle → why its returned pairs are rejected (the Streamer's PairRejected hint), while
  // they are; always in the JSON, {} when every loop closes.
  std::map<std::string, std::string> loop_not_closed;
  bool operator==(const Status&) const = default;
};
std::string encode_status(const Status& status);    // the "data" object
// For a page and the log: "VehicleOcpShared too large: 19574 B > 16384 B, not sent to the
// operator TCP client, … Reduce the vehicles (20), their vehicle_user_data or cameras."
std::string describe(const Status::ClientFrameTooLarge& too_large);
// The Player's view of it (PlayerCore::client_frame_too_large), as the status carries it.
Status::ClientFrameTooLarge status_of(const ocp::ClientFrameTooLarge& too_large);

std::string encode_error(std::string_view kind, std::string_view detail);   // the "data" object

}  // namespace ocp::webview
