#pragma once
// The oracle's rule for a locked tcp source without a client (SPEC §4.3 Decision, §5.7):
// after the locked TCP client leaves, the Player returns no pair until a new TCP client takes
// over ("source tcp locked, no client connected: no pair is returned"). Seen from the event
// stream: once the last control message a Streamer received was one the Player sent while
// the locked client was gone, that Streamer's InvalidMac is active at its next tick. A Player
// that kept returning the departed client's last pair shows only a growing latency instead.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "campaign/world_facts.hpp"
#include "copies_in_flight.hpp"
#include "ocp/events.hpp"
#include "scenario/model.hpp"

namespace ocp::campaign {

class SourceLockWatch {
 public:
  using Report = std::function<void(SimTime now, const std::string& vehicle, std::string detail)>;
  SourceLockWatch(const scenario::Scenario& scenario, Report report);

  // Every event of the world, with its time from the world's start.
  void on_event(const Event& event, SimTime now);

 private:
  struct VehicleTrack {
    CopiesInFlight<> pairless_in_flight;   // control messages sent with no client
    bool last_delivered_pairless = false;
    SimTime last_delivered_at{0};
    bool invalid_mac = false;
    bool reported = false;   // once an episode
    std::vector<Window> control_stalls;
  };
  VehicleTrack& track(std::string_view vehicle);
  void on_operator_connection(const ConnectionEvent& connection, SimTime now);
  void on_control_link(const std::string& vehicle, const LinkEvent& link, SimTime now);
  void on_tick(const std::string& vehicle, SimTime now);

  const scenario::Scenario& scenario_;
  Report report_;
  bool tcp_locked_ = false;
  bool stopped_ = false;                 // a source conflict stopped all client data
  std::optional<std::string> client_;    // the open :4001 connection's peer
  std::optional<SimTime> left_at_;       // the locked client left and no other connected since
  std::map<std::string, VehicleTrack, std::less<>> vehicles_;
};

}  // namespace ocp::campaign
