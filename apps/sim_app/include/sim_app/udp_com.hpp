#pragma once
// The com channel over UDP (issue #22): the socket side of ocp/com_datagram.hpp, for
// `streamer_sim --com-listen` and `player_sim --vehicle NAME=udp://HOST:PORT`.
//
//   ComOptions        --com-key FILE, --com-insecure, --com-allow-remote, checked once
//   UdpComEndpoint    one UDP socket: seals what its side sends, opens what arrives, hands
//                     whole LinkMessages to the receiver. The Streamer's end listens and answers
//                     whichever address the last authenticated datagram came from (NAT
//                     rebinding); the Player's end sends to the Streamer's address and drops
//                     datagrams from anyone else (unknown peer).
//
// Dropped datagrams are counted per reason and logged once per episode (RepeatedWarning); a
// datagram MAC'd with another key is said as "key does not match" — the key never is.
#include <boost/asio/ip/udp.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "ocp/asio/executor.hpp"
#include "ocp/com_datagram.hpp"
#include "ocp/com_session.hpp"
#include "ocp/error.hpp"
#include "ocp/executor.hpp"
#include "ocp/link.hpp"
#include "ocp/log.hpp"
#include "ocp/log_limiter.hpp"

namespace CLI {
class App;
}

namespace ocp::sim_app {

struct ComOptions {
  std::string key_file;
  bool insecure = false;
  bool allow_remote = false;
  com::ComKey key;   // read from key_file by check_com_options; never logged
};
void add_com_options(CLI::App& app, ComOptions& options);

// HOST:PORT (HOST a name, an IPv4 address or [IPv6]); PORT 1..65535 (0 allowed when
// `allow_any_port`, for a listener). Resolved now.
Result<boost::asio::ip::udp::endpoint> resolve_udp_endpoint(const std::string& text, bool allow_any_port);

// Reads the key (or refuses: no key without --com-insecure; --com-insecure only when every
// address in `endpoints` is loopback; a key file that is missing, unreadable, shorter than
// com::min_key_bytes or longer than com::max_key_bytes; a listener on a non-loopback address
// without --com-allow-remote). The error text is for the user and never contains key bytes.
Status check_com_options(ComOptions& options, const boost::asio::ip::udp::endpoint& endpoint, bool listener);

struct UdpComCounters {
  std::uint64_t datagrams_sent = 0;
  std::uint64_t send_errors = 0;       // the socket refused a datagram (buffer full, no route)
  std::uint64_t messages_not_sent = 0; // larger than com::max_message_bytes
  std::uint64_t unknown_peer = 0;      // Player's end: from an address other than the Streamer's
  std::uint64_t peer_changes = 0;      // Streamer's end: a completed handshake from a new address
  std::uint64_t messages_before_session = 0;   // not sent: no session established yet
  std::uint64_t hellos_sent = 0;
};

// The com channel over UDP as a Link (ocp/link.hpp): the second implementation beside the
// simulated LinkDirection. The apps keep a LinkDirection in front of it (its receiver is this
// endpoint), so the impairments still apply at the sender before a message leaves the host.
class UdpComEndpoint final : public Link {
 public:
  // `streamer_side`: this end is the Streamer's (listens; accepts OperatorControl and Ping).
  UdpComEndpoint(AsioExecutor& executor, bool streamer_side, com::ComKey key, Logger logger);
  ~UdpComEndpoint() override;
  UdpComEndpoint(const UdpComEndpoint&) = delete;
  UdpComEndpoint& operator=(const UdpComEndpoint&) = delete;

  // Streamer's end: bind `local` (port 0: a free one).
  [[nodiscard]] Status listen(const boost::asio::ip::udp::endpoint& local);
  // Player's end: a socket on a free port, sending to `peer`.
  [[nodiscard]] Status connect(const boost::asio::ip::udp::endpoint& peer);
  void set_receiver(Receiver receiver) override { receiver_ = std::move(receiver); }
  // Seals and sends; nothing while the Streamer's end has not heard from a Player yet.
  void send(LinkMessage message) override;
  void stop();

  std::uint16_t local_port() const;
  com::OpenerCounters opener_counters() const { return session_.counters(); }
  const com::SessionCounters& session_counters() const { return session_.session_counters(); }
  const UdpComCounters& counters() const { return counters_; }
  // "com udp 127.0.0.1:5000 ⇄ 127.0.0.1:40000 | in … | out … | dropped …", for the status line.
  std::string describe() const;

 private:
  void receive();
  void on_datagram(std::size_t size);
  void warn_drop(com::Drop drop);
  void summarise();

  AsioExecutor& executor_;
  bool streamer_side_;
  Logger logger_;
  boost::asio::ip::udp::socket socket_;
  com::ComSessionEnd session_;   // the handshake and the current session's keys (com_session.hpp)
  Receiver receiver_;
  std::optional<boost::asio::ip::udp::endpoint> peer_;
  boost::asio::ip::udp::endpoint sender_;
  std::array<std::uint8_t, 2048> buffer_{};   // > max_datagram_bytes: a longer one shows as oversized
  std::vector<std::string> outgoing_;
  RepeatedWarning wrong_key_;
  RepeatedWarning junk_;
  RepeatedWarning unknown_peer_;
  // The Streamer's peer moving: logged in full once per episode, so two Players with the same
  // key (each datagram moves the peer back and forth) cannot flood the log.
  RepeatedWarning peer_moves_;
  PeriodicTimer summary_timer_;
  // Player's end: a hello every `hello_period` until a welcome answers, and a new handshake
  // after `silence_before_rehandshake` without an authentic datagram (the Streamer restarted).
  PeriodicTimer hello_timer_;
  SimTime last_authentic_{0};
  static constexpr Micros hello_period{250'000};
  static constexpr Micros silence_before_rehandshake{1'000'000};
  void on_hello_timer(SimTime now);
  void send_raw(const std::string& datagram, const boost::asio::ip::udp::endpoint& to);
  UdpComCounters counters_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace ocp::sim_app
