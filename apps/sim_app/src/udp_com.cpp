// The com channel over UDP: the socket side (sim_app/udp_com.hpp).
#include "sim_app/udp_com.hpp"

#include <openssl/rand.h>

#include <CLI/CLI.hpp>
#include <boost/asio/ip/udp.hpp>
#include <fmt/format.h>

#include "ocp/bounded_file.hpp"

#include <sys/stat.h>

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <iterator>
#include <system_error>

namespace ocp::sim_app {
namespace {

using boost::asio::ip::udp;

Error usage(const std::string& what) { return Error{std::make_error_code(std::errc::invalid_argument), what}; }

std::string endpoint_text(const udp::endpoint& endpoint) {
  const auto address = endpoint.address();
  return (address.is_v6() ? "[" + address.to_string() + "]" : address.to_string()) + ":" +
         std::to_string(endpoint.port());
}

// Fresh randomness for the handshake's nonces and session ids (a CSPRNG: they are what makes
// every session's keys new).
void random_bytes(std::uint8_t* bytes, std::size_t count) {
  if (RAND_bytes(bytes, static_cast<int>(count)) != 1) {
    std::fprintf(stderr, "fatal: OpenSSL RAND_bytes failed\n");
    std::abort();
  }
}

// As ssh does for its keys: a key others can read is no secret, but refusing it would break
// setups that keep the file on a shared mount; so a warning, once, at start.
void warn_if_others_can_read(const std::string& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0 || (status.st_mode & 077) == 0) return;
  std::cerr << fmt::format("warning: --com-key {}: the key file is readable by others (mode {:04o}); "
                           "chmod 600 {} so that only its owner can read it\n",
                           path, status.st_mode & 07777, path);
}

}  // namespace

void add_com_options(CLI::App& app, ComOptions& options) {
  app.add_option("--com-key", options.key_file,
                 "FILE: the com channel's pre-shared key (16..1024 bytes, e.g. head -c 32 /dev/urandom > FILE), "
                 "the same file on both hosts; every datagram is authenticated with HMAC-SHA256")
      ->group("Com channel over UDP");
  app.add_flag("--com-insecure", options.insecure,
               "run the UDP com channel without a key (loopback addresses only; anyone on this host could inject)")
      ->group("Com channel over UDP");
  app.add_flag("--com-allow-remote", options.allow_remote,
               "--com-listen may bind a non-loopback address (off: 127.0.0.1 or ::1 only)")
      ->group("Com channel over UDP");
}

Result<udp::endpoint> resolve_udp_endpoint(const std::string& text, bool allow_any_port) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) return usage("'" + text + "': expected HOST:PORT, e.g. 127.0.0.1:5000");
  std::string host = text.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const std::string port_text = text.substr(colon + 1);
  unsigned port = 0;
  const auto [end, error] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (port_text.empty() || error != std::errc{} || end != port_text.data() + port_text.size() || port > 65535 ||
      (port == 0 && !allow_any_port)) {
    return usage("'" + text + "': expected a port number " + (allow_any_port ? "0" : "1") + "..65535, got '" +
                 port_text + "'");
  }
  boost::asio::io_context io;
  udp::resolver resolver(io);
  boost::system::error_code failed;
  const auto results = resolver.resolve(udp::v4(), host, port_text, udp::resolver::numeric_service, failed);
  if (!failed && !results.empty()) return results.begin()->endpoint();
  const auto results6 = resolver.resolve(host, port_text, udp::resolver::numeric_service, failed);
  if (failed || results6.empty()) return usage("'" + text + "': cannot resolve '" + host + "'");
  return results6.begin()->endpoint();
}

Status check_com_options(ComOptions& options, const udp::endpoint& endpoint, bool listener) {
  const bool loopback = endpoint.address().is_loopback();
  if (listener && !loopback && !options.allow_remote) {
    return usage("--com-listen " + endpoint_text(endpoint) +
                 ": not a loopback address; binding one is an explicit opt-in: add --com-allow-remote");
  }
  if (options.insecure && !options.key_file.empty()) return usage("--com-insecure and --com-key: give one of them");
  if (options.insecure) {
    if (!loopback) {
      return usage("--com-insecure is for loopback only, and " + endpoint_text(endpoint) +
                   " is not; give the same --com-key FILE on both hosts");
    }
    options.key.clear();
    return Ok{};
  }
  if (options.key_file.empty()) {
    return usage("the UDP com channel needs --com-key FILE (the same file on both hosts; make one with "
                 "`head -c 32 /dev/urandom > FILE`), or --com-insecure on loopback");
  }
  // Bounded and non-blocking (a FIFO or /dev/zero is refused, not waited on), with the
  // system's reason (missing, permission denied, a folder).
  const auto text = read_bounded_file(options.key_file, file_kinds::key);
  if (!text) return usage("--com-key " + text.error().detail);
  if (text->size() < com::min_key_bytes || text->size() > com::max_key_bytes) {
    return usage(fmt::format("--com-key {}: a key is {}..{} bytes, this file has {} (make one with "
                             "`head -c 32 /dev/urandom > FILE`)",
                             options.key_file, com::min_key_bytes, com::max_key_bytes, text->size()));
  }
  warn_if_others_can_read(options.key_file);
  options.key.assign(text->begin(), text->end());
  return Ok{};
}

UdpComEndpoint::UdpComEndpoint(AsioExecutor& executor, bool streamer_side, com::ComKey key, Logger logger)
    : executor_(executor),
      streamer_side_(streamer_side),
      logger_(std::move(logger)),
      socket_(executor.io()),
      session_(std::move(key), streamer_side, random_bytes),
      summary_timer_(executor, RepeatedWarning::default_period, [this](SimTime) { summarise(); }),
      hello_timer_(executor, hello_period, [this](SimTime now) { on_hello_timer(now); }) {}

UdpComEndpoint::~UdpComEndpoint() {
  *alive_ = false;
  stop();
}

Status UdpComEndpoint::listen(const udp::endpoint& local) {
  boost::system::error_code failed;
  socket_.open(local.protocol(), failed);
  if (!failed) socket_.bind(local, failed);
  if (failed) {
    if (socket_.is_open()) socket_.close();
    return Error{std::make_error_code(std::errc::address_in_use),
                 "com channel: cannot bind UDP " + endpoint_text(local) + ": " + failed.message()};
  }
  socket_.non_blocking(true, failed);
  logger_.info("com channel: listening on UDP {} ({} datagrams of at most {} bytes)", endpoint_text(socket_.local_endpoint()),
               "HMAC-SHA256", com::max_datagram_bytes);
  receive();
  summary_timer_.start(executor_.now() + summary_timer_.period());
  return Ok{};
}

Status UdpComEndpoint::connect(const udp::endpoint& peer) {
  boost::system::error_code failed;
  socket_.open(peer.protocol(), failed);
  if (!failed) socket_.bind(udp::endpoint(peer.protocol(), 0), failed);
  if (failed) return Error{std::make_error_code(std::errc::io_error), "com channel: cannot open a UDP socket: " + failed.message()};
  socket_.non_blocking(true, failed);
  peer_ = peer;
  logger_.info("com channel: UDP to the Streamer at {} from port {}", endpoint_text(peer), socket_.local_endpoint().port());
  receive();
  summary_timer_.start(executor_.now() + summary_timer_.period());
  on_hello_timer(executor_.now());
  hello_timer_.start(executor_.now() + hello_period);
  return Ok{};
}

void UdpComEndpoint::on_hello_timer(SimTime now) {
  if (!peer_ || !socket_.is_open()) return;
  bool fresh = false;
  if (session_.established() && !session_.handshake_pending()) {
    if (now - last_authentic_ < silence_before_rehandshake) return;
    fresh = true;   // heard nothing authentic for a while: a new session (the old one goes on meanwhile)
    logger_.info("com channel: nothing from the Streamer for {}; starting a new session", format_span(now - last_authentic_));
  }
  send_raw(session_.hello(fresh), *peer_);
  ++counters_.hellos_sent;
}

void UdpComEndpoint::send_raw(const std::string& datagram, const udp::endpoint& to) {
  boost::system::error_code failed;
  socket_.send_to(boost::asio::buffer(datagram), to, 0, failed);
  // A full socket buffer or an unreachable peer loses the datagram, as the network would.
  if (failed) ++counters_.send_errors; else ++counters_.datagrams_sent;
}

void UdpComEndpoint::stop() {
  summary_timer_.stop();
  hello_timer_.stop();
  if (socket_.is_open()) {
    boost::system::error_code ignored;
    socket_.close(ignored);
  }
}

std::uint16_t UdpComEndpoint::local_port() const {
  boost::system::error_code failed;
  const auto local = socket_.local_endpoint(failed);
  return failed ? 0 : local.port();
}

void UdpComEndpoint::send(LinkMessage message) {
  if (!peer_ || !socket_.is_open()) return;
  outgoing_.clear();
  if (!session_.established()) {
    ++counters_.messages_before_session;   // as lost as on a link that is not up yet
    return;
  }
  if (!session_.seal(message, outgoing_)) {
    ++counters_.messages_not_sent;
    return;
  }
  for (const auto& datagram : outgoing_) send_raw(datagram, *peer_);
}

void UdpComEndpoint::receive() {
  socket_.async_receive_from(boost::asio::buffer(buffer_), sender_,
                             [this, alive = alive_](const boost::system::error_code& failed, std::size_t size) {
                               if (!*alive || failed == boost::asio::error::operation_aborted || !socket_.is_open()) return;
                               // Other errors (an ICMP "port unreachable" while the peer is
                               // down) are the network's: keep receiving.
                               if (!failed) on_datagram(size);
                               receive();
                             });
}

void UdpComEndpoint::on_datagram(std::size_t size) {
  const SimTime now = executor_.now();
  if (!streamer_side_ && peer_ && sender_ != *peer_) {
    ++counters_.unknown_peer;
    if (unknown_peer_.occurred(now)) {
      logger_.warn("com channel: dropping datagrams from {}, which is not the Streamer ({})", endpoint_text(sender_),
                   endpoint_text(*peer_));
    }
    return;
  }
  auto received = session_.receive({buffer_.data(), size});
  if (received.reply) send_raw(*received.reply, sender_);   // a welcome: it moves nothing
  if (received.drop != com::Drop::none) {
    warn_drop(received.drop);
    return;
  }
  last_authentic_ = now;
  if (received.established) {
    logger_.info("com channel: session {:016x} established with the {} (handshake completed){}", session_.session(),
                 streamer_side_ ? "Player" : "Streamer",
                 session_.session_counters().handshakes > 1 ? ", replacing the previous session" : "");
  }
  // Only a completed handshake moves the Streamer's peer: the sender knew the key and answered
  // this run's fresh nonce, which no recording of an earlier session can.
  if (streamer_side_ && received.established && (!peer_ || *peer_ != sender_)) {
    // The first Player, a restarted one, or the same one from a new port (a NAT that rebound).
    if (peer_) ++counters_.peer_changes;
    if (!peer_ || peer_moves_.occurred(now)) {
      logger_.info("com channel: the Player is at {}{}", endpoint_text(sender_),
                   peer_ ? " (was " + endpoint_text(*peer_) + ")" : std::string());
    }
    peer_ = sender_;
  }
  if (received.message && receiver_) receiver_(std::move(*received.message));
}

void UdpComEndpoint::warn_drop(com::Drop drop) {
  const SimTime now = executor_.now();
  if (drop == com::Drop::bad_mac) {
    if (wrong_key_.occurred(now)) {
      logger_.warn("com channel: a datagram from {} failed authentication: the key does not match (or it was "
                   "altered); dropped, and so is every such datagram until they stop", endpoint_text(sender_));
    }
    return;
  }
  if (junk_.occurred(now)) {
    logger_.warn("com channel: dropped a datagram from {}: {}; further drops are counted", endpoint_text(sender_),
                 com::drop_name(drop));
  }
}

void UdpComEndpoint::summarise() {
  const SimTime now = executor_.now();
  if (auto summary = wrong_key_.summary(now)) {
    logger_.warn("com channel: key does not match: {}{}", summary->text("datagrams dropped"),
                 summary->episode_ended ? " (they stopped)" : "");
  }
  if (auto summary = junk_.summary(now)) {
    logger_.warn("com channel: invalid datagrams: {}{}", summary->text("dropped"),
                 summary->episode_ended ? " (they stopped)" : "");
  }
  if (auto summary = peer_moves_.summary(now)) {
    logger_.warn("com channel: the Player's address changed again: {} (two Players with the same key?)",
                 summary->text("times"));
  }
  if (auto summary = unknown_peer_.summary(now)) {
    logger_.warn("com channel: datagrams from unknown peers: {}", summary->text("dropped"));
  }
}

std::string UdpComEndpoint::describe() const {
  const auto in = session_.counters();
  return fmt::format("com udp :{} ⇄ {} | in {} msgs | out {} datagrams | dropped: {} bad MAC, {} replayed, {} other, "
                     "{} unknown peer, {} frames lost",
                     local_port(), peer_ ? endpoint_text(*peer_) : std::string("no peer yet"), in.messages,
                     counters_.datagrams_sent, in.bad_mac, in.replayed,
                     in.dropped() - in.bad_mac - in.replayed, counters_.unknown_peer, in.messages_lost);
}

}  // namespace ocp::sim_app
