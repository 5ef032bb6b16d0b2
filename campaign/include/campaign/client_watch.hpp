#pragma once
// What a campaign checks of an external vehicle client (ocp_campaign run --client), from the
// Streamer's side of the one event stream, beside the Oracle (which judges the simulator):
//   * client.echo: every echo is byte-exact (the ack_time and ack_time_mac number tokens are
//     the decimal text the Streamer sent, so nothing went through a double) and current (the
//     pair was not superseded by a newer one more than `echo_current` before the echo, in
//     echoes that stay stale for `stale_for`: one stale echo is a client that was not scheduled);
//   * client.reconnect: after the Streamer closed the connection, a new one opens within
//     `reconnect_within` (the reference client's backoff tops out at 2 s).
// That the client stays alive is checked on its process (client_world.cpp), and stale pairs
// after a reconnect by the Oracle.
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "campaign/oracle.hpp"
#include "ocp/event_bus.hpp"

namespace ocp::campaign {

struct ClientBounds {
  Micros echo_current{500'000};        // real time on a loaded machine: generous
  Micros reconnect_within{5'000'000};
  Micros stale_for{250'000};           // stale echoes in a row for this long
};

class ClientWatch {
 public:
  explicit ClientWatch(ClientBounds bounds) : bounds_(bounds) {}
  void attach(World& world);
  // Call before the world stops. A close still waiting for its reconnect is a violation when
  // the bound has passed.
  void finish(World& world);
  bool ever_connected(const std::string& vehicle) const { return vehicles_.contains(vehicle) && vehicles_.at(vehicle).opened; }
  // At most 50 kept, one per kind and vehicle and connection; `count` has them all.
  const std::vector<Violation>& violations() const { return violations_; }
  std::uint64_t violation_count() const { return count_; }

 private:
  struct SentPair {
    std::uint64_t ack_time = 0;
    std::uint32_t mac = 0;
    SimTime first_sent{0};
  };
  struct Connection {
    std::deque<SentPair> sent;          // this connection's pairs, oldest first
    bool echo_reported = false;         // one client.echo per connection, then counted
    std::optional<SimTime> closed_at;   // the Streamer closed it; waiting for the next one
    std::optional<SimTime> stale_since; // the first of the stale echoes since the last current one
    bool opened = false;
  };
  void on_event(const Event& event);
  void on_frame(Connection& connection, const std::string& vehicle, SimTime now, const WireFrame& frame);
  void judge_echo(Connection& connection, const std::string& vehicle, SimTime now, const WireFrame& frame);
  std::string diagnose(const Connection& connection, std::deque<SentPair>::const_iterator near, std::uint64_t ack,
                       std::string_view mac_text) const;
  void report_echo(Connection& connection, const std::string& vehicle, SimTime now, std::string problem);
  void check_reconnect(SimTime now);
  void report(Check check, SimTime now, const std::string& vehicle, std::string detail);

  ClientBounds bounds_;
  SimTime origin_{0};
  std::map<std::string, Connection, std::less<>> vehicles_;
  std::vector<EventBus::Subscription> subscriptions_;
  std::vector<Violation> violations_;
  std::uint64_t count_ = 0;
};

}  // namespace ocp::campaign
