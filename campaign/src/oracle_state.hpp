#pragma once
// The oracle's per-vehicle and per-link-direction state (oracle.cpp, oracle_faults.cpp).
#include <deque>
#include <optional>
#include <unordered_map>

#include "campaign/oracle.hpp"
#include "campaign/world_facts.hpp"
#include "copies_in_flight.hpp"

namespace ocp::campaign {

// Faults as a bit set of the oracle's own (the cores' FaultSet is theirs).
struct FaultBits {
  std::uint32_t bits = 0;
  void set(FaultId id, bool on) {
    const std::uint32_t bit = 1u << static_cast<unsigned>(id);
    bits = on ? (bits | bit) : (bits & ~bit);
  }
  bool has(FaultId id) const { return (bits & (1u << static_cast<unsigned>(id))) != 0; }
  bool empty() const { return bits == 0; }
};

// SPEC §3.2 Decision, restated here rather than taken from the cores.
inline bool oracle_control_path(FaultId id) {
  return id == FaultId::NoControlMessage || id == FaultId::HighLatency || id == FaultId::InvalidMac ||
         id == FaultId::OperatorStationHasError || id == FaultId::ControlThreadChannelSlow;
}

inline constexpr std::uint32_t max_oracle_frame_payload = 16 * 1024;   // SPEC §2

inline std::string ms_text(Micros value) { return std::to_string(value.count() / 1000) + " ms"; }

struct IssuedPair {
  SimTime issued{0};
  std::uint64_t ack_time = 0;
  std::uint32_t mac = 0;
  bool echoed_with_mac = false;   // the vehicle sent it back byte-exact
};

struct CameraWatch {
  std::string name;
  Micros frame_period{0};
  std::vector<Window> stalls;
  std::vector<bool> certain;   // no other window of this camera ends inside it
};

// One link direction, message by message (copies counted, copies_in_flight.hpp).
struct Oracle::LinkTally {
  std::uint64_t sent = 0, delivered = 0, dropped = 0, duplicated = 0;
  CopiesInFlight<> in_flight;
  std::uint64_t last_sent = 0;
  bool duplicates_possible = false;
};

struct Oracle::VehicleState {
  std::string name;
  const VehicleSpec* spec = nullptr;
  FaultBits reported_vehicle, reported_operator;
  bool connected = false;
  bool had_close = false;
  SimTime connection_opened{0};
  std::optional<SimTime> last_control_delivered, last_feedback_delivered;
  std::deque<IssuedPair> issued;            // in issue order, bounded
  std::optional<SimTime> newest_accepted;   // issue time of the newest pair a sample implies
  std::optional<std::uint64_t> last_latency_ms;
  std::vector<Window> control_stalls, frame_stalls;
  std::vector<CameraWatch> cameras;
  bool liveness_done = false;
  bool misbehaving_at_end = false;          // the timeline leaves a misbehaviour on
  Impairments start_to_streamer, start_to_player, now_to_streamer, now_to_player;
  LinkTally links[2];                       // by LinkRoute
  bool conservation_broken[2] = {false, false};
  // What the Player's feedback entry must say (oracle_operator.cpp): the vehicle faults each
  // feedback message in flight carried when the Streamer sent it, and those of the one the
  // Player got last.
  CopiesInFlight<FaultBits> feedback_in_flight;   // bounded
  FaultBits player_has_receiver;
  bool player_receiver_known = true;   // false: a delivery the oracle could not tie to a send
  bool feedback_mismatch = false;      // reported; said again only after the lists match once
};

// The Player's :4001 port as the oracle sees it (oracle_operator.cpp).
struct Oracle::OperatorPort {
  Micros read_timeout{0};
  bool open = false;
  std::string peer;                    // of the open connection
  SimTime opened{0}, last_frame_in{0};
  // A broken frame read: the Player must close the connection at once, for this.
  struct PendingClose {
    SimTime at{0};
    std::optional<PeerError> expected;   // when the oracle can name the exact reason
    std::string what;
  };
  std::optional<PendingClose> pending;
  bool silence_reported = false;
  bool client_data_sent = false;       // a frame that is not a keep-alive (§4.2 Decision)
  // The Player publishes a lock while it reads the frame that caused it, before that frame's
  // WireFrame: judged when the frame is seen (or at once, if the next frame is not it).
  std::optional<SimTime> lock_to_judge;
  bool misbehaving_at_end = false;     // the timeline leaves a misbehaviour on
  bool liveness_done = false;
  std::uint64_t shared_frames = 0;
  bool lists_changed = true;           // since the last VehicleOcpShared was read
};

}  // namespace ocp::campaign
