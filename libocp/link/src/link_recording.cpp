// The link recording's text form (docs/link-recording.md), read and written in one place.
#include "ocp/link_recording.hpp"
#include "ocp/escaped_excerpt.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <optional>
#include <sstream>
#include <system_error>

namespace ocp {
namespace {

Error recording_error(std::string detail) {
  return Error{std::make_error_code(std::errc::invalid_argument), std::move(detail)};
}

// Whitespace-separated words of one line.
std::vector<std::string_view> recording_words(std::string_view line) {
  std::vector<std::string_view> words;
  while (true) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string_view::npos) break;
    line.remove_prefix(first);
    const auto end = line.find_first_of(" \t\r");
    words.push_back(line.substr(0, end));
    if (end == std::string_view::npos) break;
    line.remove_prefix(end);
  }
  return words;
}

std::optional<LinkRoute> recording_route(std::string_view word) {
  if (word == "to_streamer") return LinkRoute::to_streamer;
  if (word == "to_player") return LinkRoute::to_player;
  return std::nullopt;
}

std::optional<std::int64_t> recording_micros(std::string_view word) {
  std::int64_t value = 0;
  const auto [rest, status] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (status != std::errc{} || rest != word.data() + word.size() || value < 0 ||
      value > LinkRecording::max_delay_us * 1000) {
    return std::nullopt;
  }
  return value;
}

// Reads the lines after the header into `recording`; an empty string means the line was fine.
class RecordingReader {
 public:
  explicit RecordingReader(LinkRecording& recording) : recording_(recording) {}

  std::string line(const std::vector<std::string_view>& words) {
    if (!header_seen_) return header(words);
    if (words[0] == "clock") return clock(words);
    const auto route = recording_route(words[0]);
    if (!route) return "expected to_streamer, to_player or clock, got '" + escaped_excerpt(words[0]) + "'";
    return message(*route, words);
  }
  bool header_seen() const { return header_seen_; }

 private:
  std::string header(const std::vector<std::string_view>& words) {
    if (words.size() != 2 || words[0] != LinkRecording::magic) {
      return "expected the header '" + std::string(LinkRecording::magic) + " " +
             std::to_string(LinkRecording::format_version) + "' (is this a link recording?)";
    }
    if (words[1] != std::to_string(LinkRecording::format_version)) {
      return "unsupported link recording version " + std::string(words[1]) + " (this build reads " +
             std::to_string(LinkRecording::format_version) + ")";
    }
    header_seen_ = true;
    return {};
  }

  std::string clock(const std::vector<std::string_view>& words) {
    const auto route = words.size() == 3 ? recording_route(words[1]) : std::nullopt;
    if (!route) return "expected 'clock to_streamer|to_player measured|rtt_half'";
    if (words[2] == "measured") recording_.set_clock(*route, LinkRecording::Clock::measured);
    else if (words[2] == "rtt_half") recording_.set_clock(*route, LinkRecording::Clock::rtt_half);
    else return "unknown clock '" + escaped_excerpt(words[2]) + "' (measured or rtt_half)";
    return {};
  }

  std::string message(LinkRoute route, const std::vector<std::string_view>& words) {
    if (words.size() != 3) return "expected 'ROUTE SENT_US DELAY_US' or 'ROUTE SENT_US lost'";
    const auto sent = recording_micros(words[1]);
    if (!sent) return "expected a send time in whole microseconds, got '" + escaped_excerpt(words[1]) + "'";
    RecordedMessage recorded{Micros{*sent}, Micros{0}, words[2] == "lost"};
    if (!recorded.lost) {
      const auto delay = recording_micros(words[2]);
      if (!delay || *delay > LinkRecording::max_delay_us) {
        return "expected a delay in whole microseconds up to " + std::to_string(LinkRecording::max_delay_us) +
               ", or 'lost', got '" + escaped_excerpt(words[2]) + "'";
      }
      recorded.delay = Micros{*delay};
    }
    auto& messages = recording_.route(route);
    if (!messages.empty() && recorded.sent_at < messages.back().sent_at) {
      return "send time " + std::to_string(*sent) + " goes backwards (the previous " + std::string(words[0]) +
             " message was sent at " + std::to_string(messages.back().sent_at.count()) + ")";
    }
    if (++count_ > LinkRecording::max_messages) return "more than " + std::to_string(LinkRecording::max_messages) + " messages";
    messages.push_back(recorded);
    return {};
  }

  LinkRecording& recording_;
  bool header_seen_ = false;
  std::size_t count_ = 0;
};

}  // namespace

std::string_view recording_clock_name(LinkRecording::Clock clock) {
  return clock == LinkRecording::Clock::rtt_half ? "rtt_half" : "measured";
}

Result<LinkRecording> LinkRecording::parse(std::string_view text, const std::string& name) {
  LinkRecording recording;
  recording.name_ = name;
  RecordingReader reader(recording);
  std::size_t line_number = 0;
  while (!text.empty()) {
    const auto end = text.find('\n');
    const std::string_view raw = text.substr(0, end);
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
    ++line_number;
    const auto words = recording_words(raw.substr(0, raw.find('#')));   // '#' starts a comment
    if (words.empty()) continue;
    if (std::string problem = reader.line(words); !problem.empty()) {
      return recording_error(name + ":" + std::to_string(line_number) + ": " + problem);
    }
  }
  if (!reader.header_seen()) return recording_error(name + ": empty link recording (no header, no messages)");
  if (recording.routes_[0].empty() && recording.routes_[1].empty()) {
    return recording_error(name + ": empty link recording (no messages)");
  }
  return recording;
}

std::string LinkRecording::format(const std::vector<std::string>& comments) const {
  std::string out;
  for (const std::string& comment : comments) out += "# " + comment + "\n";
  out += std::string(magic) + " " + std::to_string(format_version) + "\n";
  for (const LinkRoute route : {LinkRoute::to_streamer, LinkRoute::to_player}) {
    out += "clock " + std::string(link_route_name(route)) + " " + std::string(recording_clock_name(clock(route))) + "\n";
  }
  for (const LinkRoute route : {LinkRoute::to_streamer, LinkRoute::to_player}) {
    const std::string prefix = std::string(link_route_name(route)) + " ";
    for (const RecordedMessage& message : this->route(route)) {
      out += prefix + std::to_string(message.sent_at.count()) + " " +
             (message.lost ? std::string("lost") : std::to_string(message.delay.count())) + "\n";
    }
  }
  return out;
}

}  // namespace ocp
