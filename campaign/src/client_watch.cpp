// ClientWatch (client_watch.hpp): the external client's side of a campaign world.
#include "campaign/client_watch.hpp"

#include <rapidjson/document.h>

#include <algorithm>
#include <charconv>
#include <optional>

#include "ocp/pair_diagnosis.hpp"

#include "world/world.hpp"

namespace ocp::campaign {

namespace {

constexpr std::size_t client_watch_kept = 50;
constexpr std::size_t client_watch_pairs = 1u << 14;   // 160 s of 10 ms control messages

// The raw text of a number member (the document was parsed with numbers as strings), or "".
std::string_view raw_number(const rapidjson::Document& document, const char* name) {
  if (!document.IsObject()) return {};
  const auto member = document.FindMember(name);
  if (member == document.MemberEnd() || !member->value.IsString()) return {};
  return {member->value.GetString(), member->value.GetStringLength()};
}

std::string millis(Micros span) { return std::to_string(span.count() / 1000) + " ms"; }

template <class Integer>
std::optional<Integer> integer_of(std::string_view text) {
  Integer value{};
  const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
  if (parsed.ec != std::errc{} || parsed.ptr != text.data() + text.size()) return std::nullopt;
  return value;
}

constexpr std::ptrdiff_t pairs_to_compare = 16;   // on each side of where the echo would sit

}  // namespace

void ClientWatch::attach(World& world) {
  origin_ = world.executor().now();
  subscriptions_.push_back(world.events().subscribe([this](const Event& event) { on_event(event); }));
}

void ClientWatch::report(Check check, SimTime now, const std::string& vehicle, std::string detail) {
  ++count_;
  if (violations_.size() < client_watch_kept) violations_.push_back({check, now, vehicle, std::move(detail), std::nullopt, false, std::nullopt});
}

void ClientWatch::on_event(const Event& event) {
  const SimTime now = event.time - origin_;
  check_reconnect(now);
  if (event.component.kind != ComponentKind::streamer) return;
  const std::string vehicle(event.component.name);
  if (const auto* frame = std::get_if<WireFrame>(&event.body); frame && frame->wire == Wire::vehicle) {
    on_frame(vehicles_[vehicle], vehicle, now, *frame);
  } else if (const auto* change = std::get_if<ConnectionEvent>(&event.body); change && change->wire == Wire::vehicle) {
    Connection& connection = vehicles_[vehicle];
    if (change->change == ConnectionChange::closed) {
      connection.closed_at = now;
    } else if (change->change == ConnectionChange::opened) {
      connection = Connection{};   // a new connection: new pairs, a new episode
      connection.opened = true;
    }
  }
}

void ClientWatch::check_reconnect(SimTime now) {
  for (auto& [vehicle, connection] : vehicles_) {
    if (!connection.closed_at || now - *connection.closed_at <= bounds_.reconnect_within) continue;
    report(Check::client_reconnect, now, vehicle,
           "the Streamer closed the connection at " + millis(*connection.closed_at) + " and no new one opened within " +
               millis(bounds_.reconnect_within));
    connection.closed_at.reset();
  }
}

void ClientWatch::finish(World& world) {
  check_reconnect(world.executor().now() - origin_);
  subscriptions_.clear();
}

void ClientWatch::on_frame(Connection& connection, const std::string& vehicle, SimTime now, const WireFrame& frame) {
  if (frame.direction == FrameDirection::out && frame.kind == WireMessageKind::control && frame.ack) {
    if (!connection.sent.empty() && connection.sent.back().ack_time == frame.ack->ack_time) return;
    if (connection.sent.size() >= client_watch_pairs) connection.sent.pop_front();
    connection.sent.push_back({frame.ack->ack_time, frame.ack->ack_time_mac, now});
    return;
  }
  if (frame.direction == FrameDirection::in && frame.kind == WireMessageKind::vehicle_response && !connection.sent.empty()) {
    judge_echo(connection, vehicle, now, frame);
  }
}

// One echo: its tokens against the pair this connection sent with that ack_time.
void ClientWatch::judge_echo(Connection& connection, const std::string& vehicle, SimTime now, const WireFrame& frame) {
  rapidjson::Document document;
  document.Parse<rapidjson::kParseNumbersAsStringsFlag>(frame.payload.data(), frame.payload.size());
  const std::string_view ack_text = raw_number(document, "ack_time");
  if (ack_text.empty()) return;   // not an echo (the Streamer judges malformed responses)
  const std::string_view mac_text = raw_number(document, "ack_time_mac");
  const std::optional<std::uint64_t> ack = integer_of<std::uint64_t>(ack_text);
  std::string problem;
  // Pairs are issued in increasing ack_time order.
  const std::uint64_t key = ack.value_or(0);
  auto found = std::lower_bound(connection.sent.begin(), connection.sent.end(), key,
                                [](const SentPair& pair, std::uint64_t value) { return pair.ack_time < value; });
  const bool issued = ack && found != connection.sent.end() && found->ack_time == *ack;
  if (!ack) {
    problem = "ack_time came back as " + std::string(ack_text) +
              ", not as the integer the Streamer sent: rounded through a double? Keep the number's text, or parse it "
              "as an unsigned 64-bit integer";
  } else if (*ack < connection.sent.front().ack_time) {
    return;   // older than this connection: the Oracle's stale-pair check
  } else if (!issued || mac_text != std::to_string(found->mac)) {
    problem = "echoed a pair this connection was never sent: " + diagnose(connection, found, *ack, mac_text);
  } else if (const auto next = std::next(found); next != connection.sent.end() && now - next->first_sent > bounds_.echo_current) {
    // Stale. Once is a client that was not scheduled for a while: on waking, its keep-alive
    // timer may fire before it reads what came meanwhile (Node runs timers before I/O). Only
    // stale echoes for stale_for in a row are a client that does not take the newest pair.
    if (!connection.stale_since) connection.stale_since = now;
    if (now - *connection.stale_since >= bounds_.stale_for) {
      problem = "echoed the pair sent at " + millis(found->first_sent) + ", superseded " + millis(now - next->first_sent) +
                " before the echo (bound " + millis(bounds_.echo_current) + "), and only stale pairs for " +
                millis(now - *connection.stale_since);
    }
  } else {
    connection.stale_since.reset();
  }
  if (problem.empty()) return;
  report_echo(connection, vehicle, now, std::move(problem));
}

// The cause, by the one rule for altered pairs (ocp/pair_diagnosis.hpp), against the pairs
// sent around where the echo would sit.
std::string ClientWatch::diagnose(const Connection& connection, std::deque<SentPair>::const_iterator near,
                                  std::uint64_t ack, std::string_view mac_text) const {
  const std::optional<std::uint32_t> mac = integer_of<std::uint32_t>(mac_text);
  if (!mac) {
    return "ack_time " + std::to_string(ack) +
           (mac_text.empty() ? std::string(" without an ack_time_mac") : " with ack_time_mac " + std::string(mac_text) + ", not a 32-bit integer");
  }
  const auto at = near - connection.sent.begin();
  const auto size = static_cast<std::ptrdiff_t>(connection.sent.size());
  std::vector<AckPair> around;
  for (auto i = std::max<std::ptrdiff_t>(0, at - pairs_to_compare); i < std::min(size, at + pairs_to_compare); ++i) {
    const SentPair& pair = connection.sent[static_cast<std::size_t>(i)];
    around.push_back({pair.ack_time, pair.mac});
  }
  const AckPair echoed{ack, *mac};
  return describe_rejected_pair(echoed, judge_altered_pair(echoed, around));
}

void ClientWatch::report_echo(Connection& connection, const std::string& vehicle, SimTime now, std::string problem) {
  if (connection.echo_reported) {
    ++count_;
    return;
  }
  connection.echo_reported = true;
  report(Check::client_echo, now, vehicle, problem);
}

}  // namespace ocp::campaign
