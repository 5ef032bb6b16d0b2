#include "conformance/observations.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

namespace ocp::conformance {

namespace {

// The log index at which each response's connection window opens (see the header): per
// connection, the first echo of a pair sent on it, else its first control frame. Responses
// before that index are "before control". Connections start at each `opened` entry.
std::vector<bool> in_window(const std::vector<WireLogEntry>& entries) {
  std::vector<bool> windowed(entries.size(), false);
  std::size_t begin = 0;
  while (begin < entries.size()) {
    std::size_t end = begin + 1;
    while (end < entries.size() && entries[end].kind != WireEntryKind::opened) ++end;
    std::set<std::pair<std::uint64_t, std::uint32_t>> sent_here;
    std::optional<std::size_t> first_control, first_echo;
    for (std::size_t i = begin; i < end && !first_echo; ++i) {
      const WireLogEntry& e = entries[i];
      if (e.kind == WireEntryKind::out && e.ack) {
        if (!first_control) first_control = i;
        sent_here.emplace(e.ack->ack_time, e.ack->ack_time_mac);
      } else if (e.kind == WireEntryKind::in && e.ack && first_control &&
                 sent_here.count({e.ack->ack_time, e.ack->ack_time_mac}) > 0) {
        first_echo = i;
      }
    }
    const std::size_t opens = first_echo ? *first_echo : first_control ? *first_control : end;
    for (std::size_t i = opens; i < end; ++i) windowed[i] = true;
    begin = end;
  }
  return windowed;
}

}  // namespace

Observations Observations::from(const std::vector<WireLogEntry>& entries, std::int64_t since_us) {
  Observations observed;
  const std::vector<bool> windowed = in_window(entries);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const WireLogEntry& e = entries[i];
    if (e.time_us < since_us) continue;
    switch (e.kind) {
      case WireEntryKind::out:
        if (e.ack) observed.sent.push_back(SentPair{e.time_us, *e.ack});
        break;
      case WireEntryKind::in: {
        const Response response{e.time_us, e.ack, e.drained, e.length_prefix, e.text};
        observed.all_responses.push_back(response);
        (windowed[i] ? observed.responses : observed.before_control).push_back(response);
        break;
      }
      case WireEntryKind::opened:
        observed.opened_us.push_back(e.time_us);
        break;
      case WireEntryKind::closed:
        observed.close_codes.push_back(e.close_code);
        observed.closed_us.push_back(e.time_us);
        break;
      case WireEntryKind::refused:
      case WireEntryKind::note:
        break;
    }
  }
  return observed;
}

std::int64_t Observations::find_sent(const AckPair& ack) const {
  for (std::size_t i = sent.size(); i-- > 0;) {
    if (sent[i].ack == ack) return static_cast<std::int64_t>(i);
  }
  return -1;
}

std::int64_t Observations::latest_sent_before(std::int64_t time_us) const {
  // `sent` is in time order.
  auto it = std::upper_bound(sent.begin(), sent.end(), time_us,
                             [](std::int64_t t, const SentPair& s) { return t < s.time_us; });
  return static_cast<std::int64_t>(it - sent.begin()) - 1;
}

std::size_t Observations::responses_with_pair() const {
  return static_cast<std::size_t>(std::count_if(responses.begin(), responses.end(),
                                                [](const Response& response) { return response.ack.has_value(); }));
}

bool Observations::closed_by_peer_error() const {
  return std::any_of(close_codes.begin(), close_codes.end(),
                     [](const std::string& code) { return code.rfind("peer.", 0) == 0; });
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = p / 100.0 * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const auto hi = static_cast<std::size_t>(std::ceil(rank));
  return values[lo] + (values[hi] - values[lo]) * (rank - static_cast<double>(lo));
}

}  // namespace ocp::conformance
