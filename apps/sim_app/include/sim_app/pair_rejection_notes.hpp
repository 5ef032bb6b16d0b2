#pragma once
// Why a vehicle's latency loop does not close, while it does not: the hint of each open
// InvalidMac episode (PairRejected, ocp/events.hpp), taken from the Streamers' event streams
// and dropped when the fault clears (a valid pair came back). The status lines of streamer_sim
// and player_sim and player_sim's web view show it.
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/event_bus.hpp"

namespace ocp::sim_app {

class PairRejectionNotes {
 public:
  // Follows one Streamer's bus (streamer.events()); call once per vehicle. Subscribing to the
  // Streamers rather than the World keeps the links' many events unbuilt.
  void follow(EventBus& streamer_events);

  // The open episode's hint for `vehicle`, or nullptr while its loop is closed.
  const std::string* hint(std::string_view vehicle) const;
  const std::map<std::string, std::string, std::less<>>& open() const { return hints_; }

 private:
  void on_event(const Event& event);

  std::map<std::string, std::string, std::less<>> hints_;   // vehicle → hint
  std::vector<EventBus::Subscription> subscriptions_;
};

}  // namespace ocp::sim_app
