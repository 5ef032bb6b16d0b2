// The web view endpoint: listener, admission (slots, reclaiming waiting connections), refusal
// episodes, origins, Player hook-up, broadcast and message dispatch.
#include <algorithm>
#include <cctype>
#include <utility>

#include <fmt/format.h>

#include "ocp/json_codec.hpp"
#include "player/player_core.hpp"
#include "sim_app/pair_rejection_notes.hpp"
#include "webview_hub.hpp"

namespace ocp {
namespace {

Error listen_error(const boost::system::error_code& error, const std::string& address) {
  if (error == boost::asio::error::address_in_use) {
    return Error{std::make_error_code(std::errc::address_in_use), "another socket listens on " + address};
  }
  return Error{std::error_code(error.value(), std::system_category()),
               "web view cannot listen on " + address + ": " + error.message()};
}

bool is_scheme_character(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '+' || c == '-' || c == '.';
}

bool is_host_character(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '.' || c == '_';
}

std::string lower_case(std::string_view text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower;
}

std::string_view refusal_summary(Refusal kind) {
  switch (kind) {
    case Refusal::origin: return "requests from a foreign Origin refused (403)";
    case Refusal::host: return "requests for a foreign Host refused (421)";
    case Refusal::busy: return "connections refused: no free slot (503)";
    case Refusal::reclaimed: return "connections waiting for a request closed to make room";
    case Refusal::timeout: return "connections closed: request not complete in time";
    case Refusal::header_too_large: return "requests with headers over 8 KiB refused (431)";
    case Refusal::bad_request: return "requests not understood (400)";
    case Refusal::websocket_full: return "WebSocket clients refused: too many connected (503)";
    case Refusal::path: return "paths refused (403)";
  }
  return "refusals";
}

}  // namespace

Result<std::string> parse_webview_origin(std::string_view text) {
  const auto bad = [&](std::string_view why) -> Error {
    return Error{std::make_error_code(std::errc::invalid_argument),
                 fmt::format("expected an origin scheme://host[:port] ({}), got '{}'", why, text)};
  };
  const std::size_t separator = text.find("://");
  if (separator == std::string_view::npos) return bad("no '://'");
  const std::string scheme = lower_case(text.substr(0, separator));
  if (scheme.empty() || !std::isalpha(static_cast<unsigned char>(scheme.front())) ||
      !std::all_of(scheme.begin(), scheme.end(), is_scheme_character)) {
    return bad("the scheme is letters, digits, '+', '-', '.'");
  }
  std::string_view authority = text.substr(separator + 3);
  if (authority.find_first_of("/?#") != std::string_view::npos) return bad("no path, query or fragment, not even '/'");
  if (authority.find('@') != std::string_view::npos) return bad("no user info");
  std::string host;
  std::string_view port_text;
  bool has_port = false;
  if (!authority.empty() && authority.front() == '[') {   // an IPv6 literal
    const std::size_t close = authority.find(']');
    if (close == std::string_view::npos || close == 1) return bad("an unclosed or empty IPv6 literal");
    const std::string_view literal = authority.substr(1, close - 1);
    if (!std::all_of(literal.begin(), literal.end(),
                     [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0 || c == ':' || c == '.'; })) {
      return bad("an IPv6 literal is hex digits, ':' and '.'");
    }
    host = "[" + lower_case(literal) + "]";
    const std::string_view rest = authority.substr(close + 1);
    if (!rest.empty()) {
      if (rest.front() != ':') return bad("only ':port' may follow the host");
      has_port = true;
      port_text = rest.substr(1);
    }
  } else {
    const std::size_t colon = authority.find(':');
    host = lower_case(authority.substr(0, colon));
    if (colon != std::string_view::npos) {
      has_port = true;
      port_text = authority.substr(colon + 1);
    }
    if (host.empty()) return bad("no host");
    if (!std::all_of(host.begin(), host.end(), is_host_character)) {
      return bad("the host is letters, digits, '-', '.', '_' or an [IPv6] literal");
    }
  }
  std::string normalised = scheme + "://" + host;
  if (has_port) {
    if (port_text.empty() || port_text.size() > 5 ||
        !std::all_of(port_text.begin(), port_text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return bad("the port is a number 1..65535");
    }
    const unsigned long port = std::stoul(std::string(port_text));
    if (port == 0 || port > 65535) return bad("the port is a number 1..65535");
    const bool default_port = ((scheme == "http" || scheme == "ws") && port == 80) ||
                              ((scheme == "https" || scheme == "wss") && port == 443);
    if (!default_port) normalised += ":" + std::to_string(port);
  }
  return normalised;
}

RefusalLog::RefusalLog(Executor& executor, Logger logger, Micros gap)
    : executor_(executor), logger_(std::move(logger)), gap_(gap) {}

// The executor may be gone by now (the Hub can outlive it inside the io_context's handlers):
// stop() has flushed, and a timer still queued finds `alive_` expired.
RefusalLog::~RefusalLog() = default;

void RefusalLog::note(Refusal kind, std::string detail) {
  Episode& episode = episodes_[static_cast<std::size_t>(kind)];
  const SimTime now = executor_.now();
  if (episode.count == 0) {
    episode.started = now;
    logger_.warn("web view: {} (more of these are counted and reported once they stop for {} s)", detail,
                 std::chrono::duration<double>(gap_).count());
  }
  ++episode.count;
  episode.last = now;
  episode.last_detail = std::move(detail);
  if (!episode.timer) check_end(kind);
}

void RefusalLog::check_end(Refusal kind) {
  Episode& episode = episodes_[static_cast<std::size_t>(kind)];
  episode.timer.reset();
  if (episode.count == 0) return;
  if (executor_.now() - episode.last >= gap_) {
    end(kind);
    return;
  }
  episode.timer = executor_.call_at(episode.last + gap_, [this, kind, alive = std::weak_ptr<int>(alive_)] {
    if (alive.lock()) check_end(kind);
  });
}

void RefusalLog::end(Refusal kind) {
  Episode& episode = episodes_[static_cast<std::size_t>(kind)];
  if (episode.count > 1) {
    logger_.warn("web view: {} {} in {:.1f} s; the last: {}", episode.count, refusal_summary(kind),
                 std::chrono::duration<double>(episode.last - episode.started).count(), episode.last_detail);
  }
  episode.count = 0;
  episode.last_detail.clear();
}

void RefusalLog::flush() {
  for (std::size_t kind = 0; kind < refusal_kind_count; ++kind) {
    Episode& episode = episodes_[kind];
    if (episode.timer) executor_.cancel(*episode.timer);
    episode.timer.reset();
    if (episode.count > 0) end(static_cast<Refusal>(kind));
  }
}

ConnectionSlot::ConnectionSlot(WebviewServer::Hub& hub, std::string address)
    : hub_(&hub), address_(std::move(address)), http_(true) {
  ++hub_->http_connections;
  ++hub_->connections_per_address[address_];
}

ConnectionSlot::ConnectionSlot(ConnectionSlot&& other) noexcept
    : hub_(std::exchange(other.hub_, nullptr)), address_(std::move(other.address_)), http_(other.http_) {}

ConnectionSlot& ConnectionSlot::operator=(ConnectionSlot&& other) noexcept {
  if (this != &other) {
    release();
    hub_ = std::exchange(other.hub_, nullptr);
    address_ = std::move(other.address_);
    http_ = other.http_;
  }
  return *this;
}

void ConnectionSlot::leave_http() {
  if (hub_ && http_) --hub_->http_connections;
  http_ = false;
}

void ConnectionSlot::release() {
  if (!hub_) return;
  leave_http();
  const auto found = hub_->connections_per_address.find(address_);
  if (found != hub_->connections_per_address.end() && --found->second == 0) hub_->connections_per_address.erase(found);
  hub_ = nullptr;
}

WebviewServer::Hub::Hub(AsioExecutor& executor_in, WebviewOptions options_in, Logger logger_in)
    : executor(executor_in),
      options(std::move(options_in)),
      logger(std::move(logger_in)),
      limits(options.limits),
      acceptor(executor_in.io()),
      refusals(executor_in, logger, std::chrono::duration_cast<Micros>(limits.refusal_episode_gap)) {}

void WebviewServer::Hub::accept_next() {
  acceptor.async_accept([hub = shared_from_this()](boost::system::error_code error, tcp::socket socket) {
    if (hub->stopped || error == boost::asio::error::operation_aborted) return;
    if (!error) hub->admit(std::move(socket));
    hub->accept_next();
  });
}

void WebviewServer::Hub::admit(tcp::socket socket) {
  boost::system::error_code error;
  const auto remote = socket.remote_endpoint(error);
  if (error) return;   // already gone
  const std::string remote_address = remote.address().to_string();
  if (!make_room(remote_address)) {
    ++stats.connections_refused;
    const bool address_full = connections_of(remote_address) >= limits.max_connections_per_address;
    refusals.note(Refusal::busy,
                  fmt::format("connection from {}:{} refused with 503: {}", remote_address, remote.port(),
                              address_full ? fmt::format("{} connections from that address already open",
                                                         limits.max_connections_per_address)
                                           : fmt::format("{} HTTP connections already open", limits.max_http_connections)));
    send_and_close(std::move(socket), refusal_response(http::status::service_unavailable,
                                                       "too many connections; try again later\n"));
    return;
  }
  const std::uint64_t id = next_http_id++;
  auto session = std::make_shared<HttpSession>(shared_from_this(), std::move(socket), ConnectionSlot(*this, remote_address), id);
  http_sessions[id] = session;
  session->start();
}

std::size_t WebviewServer::Hub::connections_of(const std::string& remote_address) const {
  const auto found = connections_per_address.find(remote_address);
  return found == connections_per_address.end() ? 0 : found->second;
}

// Why reclaim rather than only refuse. The per-address limit keeps one remote host from taking
// every slot, so pages from other hosts are still served while it holds its quota. But every
// local client — the operator's browser, curl, and a local slowloris alike — comes from
// 127.0.0.1, so on loopback the per-address limit protects nobody: once a slowloris holds the
// address's quota, the operator's own page load would be refused with it. The timeouts bound
// how long a slowloris keeps a slot (header_timeout), not how soon it takes the slot back, and
// more slots only raise the number of connections it needs. What a slowloris cannot fake is
// speed: a real client sends its whole request the moment it connects. So when a limit is
// reached, the connection that has waited longest for its request — a slowloris or an idle
// keep-alive connection — is closed and the newcomer takes its place (as nginx reuses its
// idle connections when it runs out). The newcomer is then the youngest: to push it out
// before its request is in, an attacker must open as many connections as the limit within
// that request's few milliseconds. Waiting for a grace period before reclaiming
// (stalled_after > 0) is weaker than it looks: an attacker that reconnects faster than
// limit / stalled_after keeps every connection younger than the grace, and then a real client
// finds nothing to reclaim (measured: 300 reconnecting slowloris connections against a 2 s
// grace got 2 of 3 page loads refused). An idle keep-alive connection closed this way costs
// its browser one reconnect.
bool WebviewServer::Hub::make_room(const std::string& remote_address) {
  for (;;) {
    const bool address_full = connections_of(remote_address) >= limits.max_connections_per_address;
    const bool all_full = http_connections >= limits.max_http_connections;
    if (!address_full && !all_full) return true;
    // The longest wait for a request: of the same address when its quota is the limit reached.
    const SimTime stalled_before = executor.now() - std::chrono::duration_cast<Micros>(limits.stalled_after);
    std::shared_ptr<HttpSession> victim;
    for (const auto& [id, weak] : http_sessions) {
      auto session = weak.lock();
      if (!session || !session->waiting_since() || *session->waiting_since() > stalled_before) continue;
      if (address_full && session->remote_address() != remote_address) continue;
      if (!victim || *session->waiting_since() < *victim->waiting_since()) victim = std::move(session);
    }
    if (!victim) return false;
    ++stats.connections_reclaimed;
    refusals.note(Refusal::reclaimed,
                  fmt::format("closed the connection of {} (request incomplete for {:.1f} s) to make room for {}",
                              victim->peer(),
                              std::chrono::duration<double>(executor.now() - *victim->waiting_since()).count(),
                              remote_address));
    victim->reclaim();
  }
}

webview::Status WebviewServer::Hub::current_status() const {
  webview::Status status;
  status.webview_clients = sessions.size();
  if (!player) return status;
  if (const auto source = player->locked_source()) status.locked_source = std::string(client_source_name(*source));
  status.client_data_stopped = player->client_data_stopped();
  status.active_vehicle = player->active_vehicle();
  status.vehicles = player->vehicles();
  if (const auto& too_large = player->client_frame_too_large()) status.client_frame_too_large = webview::status_of(*too_large);
  if (player->tcp_lock_without_client()) status.tcp_lock_without_client = std::string(tcp_lock_without_client_text);
  if (loop_notes != nullptr) {
    for (const auto& [vehicle, hint] : loop_notes->open()) status.loop_not_closed.emplace(vehicle, hint);
  }
  return status;
}

std::shared_ptr<const std::string> WebviewServer::Hub::status_message() const {
  return std::make_shared<const std::string>(
      webview::make_envelope(webview::status_name, webview::encode_status(current_status())));
}

void WebviewServer::Hub::on_frame(const VehicleOcpShared& shared) {
  if (stopped || sessions.empty()) return;   // nobody listens: do not even encode
  encode_vehicle_ocp_shared(shared, json_buffer);
  broadcast(std::make_shared<const std::string>(webview::make_envelope(webview::vehicle_data_name, json_buffer)));
  ++stats.frames_published;
  // The lock state changes rarely; pages hear about it the frame it changes.
  webview::Status status = current_status();
  if (!last_status || *last_status != status) {
    last_status = status;
    broadcast(status_message());
  }
}

void WebviewServer::Hub::broadcast(const std::shared_ptr<const std::string>& message) {
  // send() may close a session, which erases it from `sessions`: iterate over a copy.
  const auto targets = sessions;
  for (const auto& [id, weak] : targets) {
    if (auto session = weak.lock()) session->send(message);
  }
}

void WebviewServer::Hub::on_message(WebsocketSession& session, std::string_view text) {
  ++stats.messages_received;
  auto message = webview::parse_envelope(text);
  if (!message) {
    session.drop(webview::DropKind::malformed, message.error().message());
    return;
  }
  if (message->name != webview::client_data_name) {
    session.drop(webview::DropKind::unknown_name,
                 "'" + message->name.substr(0, 64) + "' (the Player takes " + std::string(webview::client_data_name) + ")");
    return;
  }
  auto data = decode_client_ocp_shared(message->data_json);
  if (!data) {
    session.drop(webview::DropKind::malformed, std::string(webview::client_data_name) + ": " + data.error().message());
    return;
  }
  if (webview::is_keep_alive(*data)) {
    ++stats.keep_alives;   // SPEC §4.2 Decision: never locks the source
    return;
  }
  if (!player) return;
  ++stats.client_data_forwarded;
  player->handle_client_data(ClientSource::webview, *data);
}

WebviewServer::WebviewServer(AsioExecutor& executor, WebviewOptions options, Logger logger)
    : hub_(std::make_shared<Hub>(executor, std::move(options), std::move(logger))) {}

WebviewServer::~WebviewServer() { stop(); }

Status WebviewServer::listen() {
  Hub& hub = *hub_;
  std::error_code fs_error;
  if (!std::filesystem::is_directory(hub.options.root, fs_error)) {
    return Error{std::make_error_code(std::errc::no_such_file_or_directory),
                 "web view root '" + hub.options.root.string() + "' is not a folder"};
  }
  hub.root = hub.options.root;
  hub.allowed_origins.clear();
  for (const std::string& origin : hub.options.allowed_origins) {
    auto parsed = parse_webview_origin(origin);
    if (!parsed) return Error{parsed.error().code, "web view allowed origin: " + parsed.error().detail};
    hub.allowed_origins.push_back(std::move(*parsed));
  }
  const auto ip = hub.options.allow_remote ? boost::asio::ip::address_v4::any() : boost::asio::ip::address_v4::loopback();
  const std::string wanted = ip.to_string() + ":" + std::to_string(hub.options.port);
  const tcp::endpoint endpoint(ip, hub.options.port);
  boost::system::error_code error;
  hub.acceptor.open(endpoint.protocol(), error);
  if (!error) hub.acceptor.set_option(tcp::acceptor::reuse_address(true), error);
  if (!error) hub.acceptor.bind(endpoint, error);
  if (!error) hub.acceptor.listen(boost::asio::socket_base::max_listen_connections, error);
  if (error) {
    boost::system::error_code ignored;
    hub.acceptor.close(ignored);
    return listen_error(error, wanted);
  }
  hub.bound_host = ip.to_string();
  hub.bound_port = hub.acceptor.local_endpoint().port();
  hub.address = hub.bound_host + ":" + std::to_string(hub.bound_port);
  hub.stopped = false;
  hub.logger.info("web view on http://{}/ (WebSocket /ws, files from {})", hub.address, hub.root.string());
  if (!hub.allowed_origins.empty()) {
    std::string origins;
    for (const std::string& origin : hub.allowed_origins) origins += (origins.empty() ? "" : ", ") + origin;
    hub.logger.info("web view: pages from {} may use it too", origins);
  }
  hub.accept_next();
  return Ok{};
}

void WebviewServer::attach(PlayerCore& player) {
  hub_->player = &player;
  // PlayerCore has no way to remove a listener: the weak pointer makes a late call harmless.
  player.add_shared_listener([weak = std::weak_ptr<Hub>(hub_)](const VehicleOcpShared& shared) {
    if (auto hub = weak.lock()) hub->on_frame(shared);
  });
}

void WebviewServer::show_loop_notes(const sim_app::PairRejectionNotes* notes) { hub_->loop_notes = notes; }

void WebviewServer::stop() {
  Hub& hub = *hub_;
  if (hub.stopped) return;
  hub.stopped = true;
  hub.player = nullptr;
  hub.loop_notes = nullptr;
  if (hub.acceptor.is_open()) {
    boost::system::error_code ignored;
    hub.acceptor.close(ignored);
    hub.logger.info("web view on http://{}/ closed", hub.address);
  }
  const auto sessions = hub.sessions;
  for (const auto& [id, weak] : sessions) {
    if (auto session = weak.lock()) session->close("the Player is shutting down");
  }
  const auto http_sessions = hub.http_sessions;
  for (const auto& [id, weak] : http_sessions) {
    if (auto session = weak.lock()) session->reclaim();
  }
  hub.refusals.flush();
}

std::uint16_t WebviewServer::port() const {
  boost::system::error_code error;
  if (!hub_->acceptor.is_open()) return 0;
  const auto endpoint = hub_->acceptor.local_endpoint(error);
  return error ? 0 : endpoint.port();
}

std::string WebviewServer::address() const { return hub_->acceptor.is_open() ? hub_->address : std::string(); }
std::size_t WebviewServer::websocket_clients() const { return hub_->sessions.size(); }
std::size_t WebviewServer::http_connections() const { return hub_->http_connections; }
const WebviewStats& WebviewServer::stats() const { return hub_->stats; }

}  // namespace ocp
