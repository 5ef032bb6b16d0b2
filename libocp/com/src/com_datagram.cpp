// The com channel's datagrams (com_datagram.hpp): header, HMAC tag, fragments, the replay
// window and reassembly. Order of the checks on receipt, cheapest and stateless first: sizes,
// header fields, the tag (constant time), then the replay window and the session — so nothing
// without the key ever changes the opener's state.
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iterator>

#include "ocp/com_datagram.hpp"

namespace ocp::com {
namespace {

constexpr std::uint8_t magic0 = 'O';
constexpr std::uint8_t magic1 = 'C';

void put(std::string& out, std::size_t at, std::uint64_t value, std::size_t bytes) {
  for (std::size_t i = 0; i < bytes; ++i) out[at + i] = static_cast<char>((value >> (8 * i)) & 0xff);
}
std::uint64_t get(std::span<const std::uint8_t> in, std::size_t at, std::size_t bytes) {
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < bytes; ++i) value |= static_cast<std::uint64_t>(in[at + i]) << (8 * i);
  return value;
}

bool known_kind(std::uint8_t kind) { return kind >= 1 && kind <= static_cast<std::uint8_t>(LinkKind::pong); }

}  // namespace

using Tag = std::array<std::uint8_t, tag_bytes>;

Tag datagram_tag(const ComKey& key, const std::uint8_t* data, std::size_t length) {
  Tag tag{};
  unsigned int tag_length = 0;
  static const std::uint8_t empty_key = 0;   // HMAC() wants a non-null key even when empty
  if (HMAC(EVP_sha256(), key.empty() ? &empty_key : key.data(), static_cast<int>(key.size()), data, length,
           tag.data(), &tag_length) == nullptr || tag_length != tag_bytes) {
    std::fprintf(stderr, "fatal: OpenSSL HMAC-SHA256 failed\n");   // only if OpenSSL itself is broken
    std::abort();
  }
  return tag;
}

std::uint64_t datagram_field(std::span<const std::uint8_t> datagram, std::size_t at, std::size_t bytes) {
  return get(datagram, at, bytes);
}

std::string datagram_header(std::uint8_t kind, std::uint64_t session, std::uint64_t sequence, std::uint32_t message,
                            std::size_t fragment, std::size_t fragments, std::size_t body_length) {
  std::string header(header_bytes, '\0');
  header[0] = static_cast<char>(magic0);
  header[1] = static_cast<char>(magic1);
  header[2] = static_cast<char>(protocol_version);
  header[3] = static_cast<char>(kind);
  put(header, 4, session, 8);
  put(header, 12, sequence, 8);
  put(header, 20, message, 4);
  put(header, 24, fragment, 2);
  put(header, 26, fragments, 2);
  put(header, 28, body_length, 2);
  return header;
}

OpenerCounters& OpenerCounters::operator+=(const OpenerCounters& other) {
  accepted += other.accepted;
  messages += other.messages;
  truncated += other.truncated;
  oversized += other.oversized;
  bad_header += other.bad_header;
  bad_mac += other.bad_mac;
  replayed += other.replayed;
  wrong_direction += other.wrong_direction;
  malformed += other.malformed;
  messages_lost += other.messages_lost;
  sessions += other.sessions;
  return *this;
}

std::string_view drop_name(Drop drop) {
  switch (drop) {
    case Drop::none: return "none";
    case Drop::truncated: return "truncated";
    case Drop::oversized: return "oversized";
    case Drop::bad_header: return "bad header";
    case Drop::bad_mac: return "bad MAC";
    case Drop::replayed: return "replayed";
    case Drop::wrong_direction: return "wrong direction";
    case Drop::malformed: return "malformed";
  }
  return "unknown";
}

// ---- sending ----

DatagramSealer::DatagramSealer(ComKey key, std::uint64_t session) : key_(std::move(key)), session_(session) {}

bool DatagramSealer::seal(const LinkMessage& message, std::vector<std::string>& out) {
  const std::string body = encode_body(message);
  if (body.size() > max_message_bytes) return false;
  const std::size_t fragments = std::max<std::size_t>(1, (body.size() + max_body_bytes - 1) / max_body_bytes);
  const std::uint32_t message_number = next_message_++;
  for (std::size_t index = 0; index < fragments; ++index) {
    const std::size_t offset = index * max_body_bytes;
    const std::size_t length = std::min(max_body_bytes, body.size() - offset);
    std::string datagram = datagram_header(static_cast<std::uint8_t>(kind_of(message)), session_, next_sequence_++,
                                           message_number, index, fragments, length);
    datagram.append(body, offset, length);
    const Tag tag = datagram_tag(key_, reinterpret_cast<const std::uint8_t*>(datagram.data()), datagram.size());
    datagram.append(reinterpret_cast<const char*>(tag.data()), tag.size());
    out.push_back(std::move(datagram));
  }
  return true;
}

// ---- the replay window ----

bool ReplayWindow::is_fresh(std::uint64_t sequence) const {
  if (sequence == 0) return false;
  if (sequence > highest_) return true;
  if (highest_ - sequence >= replay_window) return false;
  return !seen_.test(sequence % replay_window);
}

bool ReplayWindow::check_and_mark(std::uint64_t sequence) {
  if (!is_fresh(sequence)) return false;
  if (sequence > highest_) {
    if (sequence - highest_ >= replay_window) {
      seen_.reset();
    } else {
      for (std::uint64_t skipped = highest_ + 1; skipped < sequence; ++skipped) seen_.reset(skipped % replay_window);
    }
    highest_ = sequence;
  }
  seen_.set(sequence % replay_window);
  return true;
}

void ReplayWindow::reset() {
  seen_.reset();
  highest_ = 0;
}

// ---- receiving ----

DatagramOpener::DatagramOpener(ComKey key, bool to_streamer) : key_(std::move(key)), to_streamer_(to_streamer) {}

DatagramOpener::Opened DatagramOpener::reject(Drop drop) {
  switch (drop) {
    case Drop::truncated: ++counters_.truncated; break;
    case Drop::oversized: ++counters_.oversized; break;
    case Drop::bad_header: ++counters_.bad_header; break;
    case Drop::bad_mac: ++counters_.bad_mac; break;
    case Drop::replayed: ++counters_.replayed; break;
    case Drop::wrong_direction: ++counters_.wrong_direction; break;
    case Drop::malformed: ++counters_.malformed; break;
    case Drop::none: break;
  }
  return Opened{drop, std::nullopt, false};
}

ReplayWindow& DatagramOpener::window_for(std::uint64_t session, bool& new_session) {
  auto found = std::find_if(sessions_.begin(), sessions_.end(), [&](const Session& s) { return s.id == session; });
  new_session = found == sessions_.end();
  if (!new_session && found + 1 == sessions_.end()) return found->window;   // the current one: the common case
  partials_.clear();   // their pieces were of another session
  Session moved;
  if (new_session) {
    moved.id = session;
    ++counters_.sessions;
    if (sessions_.size() == remembered_sessions) sessions_.erase(sessions_.begin());
  } else {
    moved = *found;
    sessions_.erase(found);
  }
  sessions_.push_back(moved);
  return sessions_.back().window;
}

DatagramOpener::Opened DatagramOpener::open(std::span<const std::uint8_t> datagram) {
  if (datagram.size() > max_datagram_bytes) return reject(Drop::oversized);
  if (datagram.size() < header_bytes + tag_bytes) return reject(Drop::truncated);
  const std::size_t body_length = get(datagram, 28, 2);
  if (datagram.size() < header_bytes + body_length + tag_bytes) return reject(Drop::truncated);
  if (datagram.size() > header_bytes + body_length + tag_bytes) return reject(Drop::oversized);
  const std::uint8_t kind_byte = datagram[3];
  const std::size_t index = get(datagram, 24, 2);
  const std::size_t fragments = get(datagram, 26, 2);
  if (datagram[0] != magic0 || datagram[1] != magic1 || datagram[2] != protocol_version || get(datagram, 30, 2) != 0 ||
      !known_kind(kind_byte) || fragments == 0 || fragments > max_fragments || index >= fragments ||
      body_length > max_body_bytes || (index + 1 < fragments && body_length != max_body_bytes)) {
    return reject(Drop::bad_header);
  }
  const Tag expected = datagram_tag(key_, datagram.data(), header_bytes + body_length);
  if (CRYPTO_memcmp(expected.data(), datagram.data() + header_bytes + body_length, tag_bytes) != 0) {
    return reject(Drop::bad_mac);
  }
  // Authenticated from here on.
  const auto kind = static_cast<LinkKind>(kind_byte);
  if (travels_to_streamer(kind) != to_streamer_) return reject(Drop::wrong_direction);
  bool new_session = false;
  if (!window_for(get(datagram, 4, 8), new_session).check_and_mark(get(datagram, 12, 8))) {
    return reject(Drop::replayed);
  }
  ++counters_.accepted;
  const std::string_view body(reinterpret_cast<const char*>(datagram.data()) + header_bytes, body_length);
  if (fragments == 1) return finish(kind, body, new_session);
  return add_fragment(kind, static_cast<std::uint32_t>(get(datagram, 20, 4)), static_cast<std::uint16_t>(index),
                      static_cast<std::uint16_t>(fragments), body, new_session);
}

DatagramOpener::Opened DatagramOpener::finish(LinkKind kind, std::string_view body, bool new_session) {
  auto message = decode_body(kind, body);
  if (!message) {
    Opened opened = reject(Drop::malformed);
    opened.new_session = new_session;
    return opened;
  }
  ++counters_.messages;
  return Opened{Drop::none, std::move(message), new_session};
}

DatagramOpener::Opened DatagramOpener::add_fragment(LinkKind kind, std::uint32_t message, std::uint16_t index,
                                                    std::uint16_t fragments, std::string_view body,
                                                    bool new_session) {
  auto partial = std::find_if(partials_.begin(), partials_.end(), [&](const Partial& p) { return p.message == message; });
  if (partial == partials_.end()) {
    if (partials_.size() == max_partial_messages) {
      // The oldest waits no longer: it lost a piece (or its pieces come too far apart).
      partials_.erase(partials_.begin());
      ++counters_.messages_lost;
    }
    Partial fresh;
    fresh.message = message;
    fresh.kind = kind;
    fresh.fragments = fragments;
    fresh.have.assign(fragments, false);
    fresh.bytes.resize(static_cast<std::size_t>(fragments) * max_body_bytes);
    partials_.push_back(std::move(fresh));
    partial = partials_.end() - 1;
  }
  if (partial->kind != kind || partial->fragments != fragments) {
    // The same sender said two different things about one message: drop the message.
    partials_.erase(partial);
    Opened opened = reject(Drop::malformed);
    opened.new_session = new_session;
    return opened;
  }
  if (!partial->have[index]) {
    partial->have[index] = true;
    ++partial->received;
    std::copy(body.begin(), body.end(), partial->bytes.begin() + static_cast<std::ptrdiff_t>(index * max_body_bytes));
    if (index + 1 == fragments) partial->last_length = body.size();
  }
  if (partial->received < fragments) return Opened{Drop::none, std::nullopt, new_session};
  std::string whole = std::move(partial->bytes);
  whole.resize((static_cast<std::size_t>(fragments) - 1) * max_body_bytes + partial->last_length);
  partials_.erase(partial);
  return finish(kind, whole, new_session);
}

}  // namespace ocp::com
