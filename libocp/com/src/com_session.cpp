// The com channel's sessions (com_session.hpp): the handshake, HKDF, and one sealer and opener
// per session.
#include "ocp/com_session.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/kdf.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace ocp::com {
namespace {

constexpr std::uint8_t hello_kind = 6;
constexpr std::uint8_t welcome_kind = 7;

ComKey hkdf(const ComKey& long_term, const Nonce& player, const Nonce& streamer, const std::string& info) {
  std::array<std::uint8_t, 2 * nonce_bytes> salt{};
  std::copy(player.begin(), player.end(), salt.begin());
  std::copy(streamer.begin(), streamer.end(), salt.begin() + nonce_bytes);
  ComKey out(32);
  EVP_PKEY_CTX* context = EVP_PKEY_CTX_new_id(EVP_PKEY_HKDF, nullptr);
  static const std::uint8_t empty_key = 0;   // --com-insecure: an empty key (it authenticates nothing)
  std::size_t length = out.size();
  const bool ok = context != nullptr && EVP_PKEY_derive_init(context) > 0 &&
                  EVP_PKEY_CTX_set_hkdf_md(context, EVP_sha256()) > 0 &&
                  EVP_PKEY_CTX_set1_hkdf_salt(context, salt.data(), static_cast<int>(salt.size())) > 0 &&
                  EVP_PKEY_CTX_set1_hkdf_key(context, long_term.empty() ? &empty_key : long_term.data(),
                                             static_cast<int>(long_term.empty() ? 1 : long_term.size())) > 0 &&
                  EVP_PKEY_CTX_add1_hkdf_info(context, reinterpret_cast<const unsigned char*>(info.data()),
                                              static_cast<int>(info.size())) > 0 &&
                  EVP_PKEY_derive(context, out.data(), &length) > 0 && length == out.size();
  EVP_PKEY_CTX_free(context);
  if (!ok) {
    std::fprintf(stderr, "fatal: OpenSSL HKDF-SHA256 failed\n");   // only if OpenSSL itself is broken
    std::abort();
  }
  return out;
}

std::string seal_handshake(const ComKey& long_term, std::uint8_t kind, std::uint64_t session, const std::uint8_t* body,
                           std::size_t length) {
  std::string datagram = datagram_header(kind, session, 0, 0, 0, 1, length);
  datagram.append(reinterpret_cast<const char*>(body), length);
  const auto tag = datagram_tag(long_term, reinterpret_cast<const std::uint8_t*>(datagram.data()), datagram.size());
  datagram.append(reinterpret_cast<const char*>(tag.data()), tag.size());
  return datagram;
}

}  // namespace

struct ComSessionEnd::Session {
  std::uint64_t id;
  DatagramSealer sealer;
  std::unique_ptr<DatagramOpener> opener;
};

SessionKeys derive_session_keys(const ComKey& long_term, const Nonce& player, const Nonce& streamer) {
  return {hkdf(long_term, player, streamer, "ocp com v2 to_streamer"),
          hkdf(long_term, player, streamer, "ocp com v2 to_player")};
}

std::string seal_hello(const ComKey& long_term, std::uint64_t session, const Nonce& player) {
  return seal_handshake(long_term, hello_kind, session, player.data(), player.size());
}

std::string seal_welcome(const ComKey& long_term, std::uint64_t session, const Nonce& player, const Nonce& streamer) {
  std::array<std::uint8_t, 2 * nonce_bytes> body{};
  std::copy(player.begin(), player.end(), body.begin());
  std::copy(streamer.begin(), streamer.end(), body.begin() + nonce_bytes);
  return seal_handshake(long_term, welcome_kind, session, body.data(), body.size());
}

ComSessionEnd::ComSessionEnd(ComKey long_term, bool streamer_side, Random random)
    : long_term_(std::move(long_term)), streamer_side_(streamer_side), random_(std::move(random)) {}

ComSessionEnd::~ComSessionEnd() = default;

std::uint64_t ComSessionEnd::session() const { return current_ ? current_->id : 0; }

std::string ComSessionEnd::hello(bool fresh) {
  if (fresh || !pending_hello_) {
    PendingHello next;
    random_(reinterpret_cast<std::uint8_t*>(&next.session), sizeof next.session);
    if (next.session == 0 || next.session == session()) next.session ^= 0x9e3779b97f4a7c15ULL;
    random_(next.player.data(), next.player.size());
    pending_hello_ = next;
  }
  return seal_hello(long_term_, pending_hello_->session, pending_hello_->player);
}

ComSessionEnd::Received ComSessionEnd::reject(Drop drop) {
  switch (drop) {
    case Drop::truncated: ++own_.truncated; break;
    case Drop::oversized: ++own_.oversized; break;
    case Drop::bad_header: ++own_.bad_header; break;
    case Drop::bad_mac: ++own_.bad_mac; break;
    case Drop::replayed: ++own_.replayed; break;
    case Drop::wrong_direction: ++own_.wrong_direction; break;
    case Drop::malformed: ++own_.malformed; break;
    case Drop::none: break;
  }
  return Received{drop, std::nullopt, false, std::nullopt};
}

void ComSessionEnd::adopt(std::uint64_t session, const SessionKeys& keys, std::unique_ptr<DatagramOpener> opener) {
  if (current_) earlier_ += current_->opener->counters();
  const ComKey& sending = streamer_side_ ? keys.to_player : keys.to_streamer;
  current_ = std::make_unique<Session>(Session{session, DatagramSealer(sending, session), std::move(opener)});
  ++session_counters_.handshakes;
}

ComSessionEnd::Received ComSessionEnd::handshake(std::span<const std::uint8_t> datagram) {
  const bool hello = datagram[3] == hello_kind;
  const std::size_t body_length = hello ? nonce_bytes : 2 * nonce_bytes;
  if (datagram.size() < header_bytes + body_length + tag_bytes) return reject(Drop::truncated);
  if (datagram.size() > header_bytes + body_length + tag_bytes) return reject(Drop::oversized);
  if (datagram_field(datagram, 28, 2) != body_length || datagram_field(datagram, 12, 8) != 0 || datagram_field(datagram, 20, 4) != 0 ||
      datagram_field(datagram, 24, 2) != 0 || datagram_field(datagram, 26, 2) != 1 || datagram_field(datagram, 30, 2) != 0) {
    return reject(Drop::bad_header);
  }
  const auto expected = datagram_tag(long_term_, datagram.data(), header_bytes + body_length);
  if (CRYPTO_memcmp(expected.data(), datagram.data() + header_bytes + body_length, tag_bytes) != 0) {
    return reject(Drop::bad_mac);
  }
  // Authentic (but perhaps replayed: only the nonces tell).
  if (hello != streamer_side_) return reject(Drop::wrong_direction);
  const std::uint64_t session = datagram_field(datagram, 4, 8);
  Nonce player{};
  std::copy_n(datagram.begin() + header_bytes, nonce_bytes, player.begin());
  if (hello) {
    ++session_counters_.hellos;
    // A retried hello gets the same answer; a new one a fresh nonce (the oldest pending goes).
    auto found = std::find_if(pending_.begin(), pending_.end(),
                              [&](const Pending& p) { return p.session == session && p.player == player; });
    if (found == pending_.end()) {
      if (pending_.size() == max_pending) pending_.erase(pending_.begin());
      Pending fresh;
      fresh.session = session;
      fresh.player = player;
      random_(fresh.streamer.data(), fresh.streamer.size());
      fresh.keys = derive_session_keys(long_term_, fresh.player, fresh.streamer);
      pending_.push_back(std::move(fresh));
      found = pending_.end() - 1;
    }
    Received received;
    received.reply = seal_welcome(long_term_, session, found->player, found->streamer);
    return received;
  }
  // A welcome: only the answer to our own pending hello counts.
  if (!pending_hello_ || pending_hello_->session != session || pending_hello_->player != player) {
    ++session_counters_.stale_handshake;
    return reject(Drop::replayed);
  }
  ++session_counters_.welcomes;
  Nonce streamer{};
  std::copy_n(datagram.begin() + header_bytes + nonce_bytes, nonce_bytes, streamer.begin());
  const SessionKeys keys = derive_session_keys(long_term_, player, streamer);
  adopt(session, keys, std::make_unique<DatagramOpener>(keys.to_player, false));
  pending_hello_.reset();
  Received received;
  received.established = true;
  return received;
}

ComSessionEnd::Received ComSessionEnd::receive(std::span<const std::uint8_t> datagram) {
  if (datagram.size() > max_datagram_bytes) return reject(Drop::oversized);
  if (datagram.size() < header_bytes + tag_bytes) return reject(Drop::truncated);
  if (datagram[0] != 'O' || datagram[1] != 'C' || datagram[2] != protocol_version) return reject(Drop::bad_header);
  if (datagram[3] == hello_kind || datagram[3] == welcome_kind) return handshake(datagram);
  const std::uint64_t session = datagram_field(datagram, 4, 8);
  if (current_ && current_->id == session) {
    auto opened = current_->opener->open(datagram);
    return Received{opened.drop, std::move(opened.message), false, std::nullopt};
  }
  if (streamer_side_) {
    // The first datagram under a pending session's key completes its handshake. It is tried on
    // an opener of its own: if it fails, that opener is thrown away and nothing has changed.
    const auto pending = std::find_if(pending_.begin(), pending_.end(), [&](const Pending& p) { return p.session == session; });
    if (pending != pending_.end()) {
      auto opener = std::make_unique<DatagramOpener>(pending->keys.to_streamer, true);
      auto opened = opener->open(datagram);
      if (opened.drop == Drop::bad_mac || opened.drop == Drop::truncated || opened.drop == Drop::oversized ||
          opened.drop == Drop::bad_header || opened.drop == Drop::wrong_direction) {
        return reject(opened.drop);
      }
      const SessionKeys keys = pending->keys;
      pending_.erase(pending);
      adopt(session, keys, std::move(opener));
      return Received{opened.drop, std::move(opened.message), true, std::nullopt};
    }
  }
  ++session_counters_.unknown_session;
  return reject(Drop::bad_mac);   // keys of no session we have: as good as another key
}

bool ComSessionEnd::seal(const LinkMessage& message, std::vector<std::string>& out) {
  if (!current_) return false;
  return current_->sealer.seal(message, out);
}

OpenerCounters ComSessionEnd::counters() const {
  OpenerCounters total = earlier_;
  total += own_;
  if (current_) total += current_->opener->counters();
  total.sessions = session_counters_.handshakes;
  return total;
}

}  // namespace ocp::com
