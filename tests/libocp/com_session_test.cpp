// The com channel's sessions (ocp/com_session.hpp, issue #36): a session's keys come from a
// handshake to which both ends add fresh randomness, so datagrams recorded from an earlier
// session never authenticate again: not after a Streamer restart (same key file), not after a
// Player restart, not after ten newer sessions, not as a flood beside a live session. Each
// attack: 0 datagrams accepted, no session adopted, and the live session undisturbed (a
// rejected datagram changes no state: a half-received message still completes).
#include <gtest/gtest.h>

#include <random>

#include "ocp/com_session.hpp"

namespace ocp::com {
namespace {

const ComKey long_term(32, 0x5a);

std::span<const std::uint8_t> as_bytes(const std::string& datagram) {
  return {reinterpret_cast<const std::uint8_t*>(datagram.data()), datagram.size()};
}

// A deterministic stand-in for the CSPRNG: each end its own stream.
ComSessionEnd::Random seeded(std::uint64_t seed) {
  auto generator = std::make_shared<std::mt19937_64>(seed);
  return [generator](std::uint8_t* bytes, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) bytes[i] = static_cast<std::uint8_t>((*generator)());
  };
}

OperatorControl control(std::uint64_t sequence) {
  OperatorControl message;
  message.sequence = sequence;
  return message;
}

// Handshake: hello → welcome → the first data datagram completes it at the Streamer.
struct Pair {
  ComSessionEnd player;
  ComSessionEnd& streamer;
  std::vector<std::string> sent_by_player;   // everything the Player put on the wire
  Pair(ComSessionEnd& streamer_end, std::uint64_t seed) : player(long_term, false, seeded(seed)), streamer(streamer_end) {}

  void handshake() {
    const std::string hello = player.hello(false);
    sent_by_player.push_back(hello);
    auto answered = streamer.receive(as_bytes(hello));
    ASSERT_TRUE(answered.reply);
    ASSERT_TRUE(player.receive(as_bytes(*answered.reply)).established);
  }
  // Sends `count` controls; returns how many the Streamer delivered.
  int drive(int count, std::uint64_t first = 1) {
    int delivered = 0;
    for (int i = 0; i < count; ++i) {
      std::vector<std::string> out;
      EXPECT_TRUE(player.seal(control(first + static_cast<std::uint64_t>(i)), out));
      for (const auto& datagram : out) {
        sent_by_player.push_back(datagram);
        delivered += streamer.receive(as_bytes(datagram)).message.has_value();
      }
    }
    return delivered;
  }
};

struct Replayed {
  std::uint64_t accepted = 0, established = 0, messages = 0;
};
Replayed replay(ComSessionEnd& target, const std::vector<std::string>& datagrams) {
  Replayed out;
  const std::uint64_t accepted_before = target.counters().accepted;
  for (const auto& datagram : datagrams) {
    const auto received = target.receive(as_bytes(datagram));
    out.established += received.established;
    out.messages += received.message.has_value();
  }
  out.accepted = target.counters().accepted - accepted_before;
  return out;
}

TEST(ComSession, TheHandshakeEstablishesOneSessionAndMessagesFlowBothWays) {
  ComSessionEnd streamer(long_term, true, seeded(1));
  Pair pair(streamer, 2);
  std::vector<std::string> out;
  EXPECT_FALSE(pair.player.seal(control(1), out)) << "nothing is sent before the handshake";
  pair.handshake();
  EXPECT_FALSE(streamer.established()) << "the Streamer adopts the session only on the first data datagram";
  EXPECT_EQ(pair.drive(50), 50);
  EXPECT_TRUE(streamer.established());
  EXPECT_EQ(streamer.session(), pair.player.session());
  out.clear();
  ASSERT_TRUE(streamer.seal(Pong{7, SimTime{0}}, out));
  EXPECT_TRUE(pair.player.receive(as_bytes(out[0])).message.has_value());
}

TEST(ComSession, TheTwoDirectionsAndEverySessionHaveTheirOwnKeys) {
  Nonce a{}, b{};
  a[0] = 1;
  const SessionKeys one = derive_session_keys(long_term, a, b);
  b[0] = 1;
  const SessionKeys two = derive_session_keys(long_term, a, b);
  EXPECT_NE(one.to_streamer, one.to_player);
  EXPECT_NE(one.to_streamer, two.to_streamer);
  EXPECT_NE(one.to_streamer, long_term);
  EXPECT_EQ(derive_session_keys(long_term, a, b).to_player, two.to_player);
}

// The recording of a whole Player session, replayed to a restarted Streamer with the same key
// (issue #36: all 558 were accepted and the peer moved to the attacker).
TEST(ComSession, ARecordedSessionReplayedAfterAStreamerRestartGetsNothingIn) {
  std::vector<std::string> recording;
  {
    ComSessionEnd first_run(long_term, true, seeded(1));
    Pair pair(first_run, 2);
    pair.handshake();
    ASSERT_EQ(pair.drive(558), 558);
    recording = pair.sent_by_player;
  }
  ComSessionEnd restarted(long_term, true, seeded(3));
  const Replayed replayed = replay(restarted, recording);
  EXPECT_EQ(replayed.accepted, 0u);
  EXPECT_EQ(replayed.established, 0u);
  EXPECT_EQ(replayed.messages, 0u);
  EXPECT_FALSE(restarted.established());
  // The recorded hello is answered (a welcome the attacker cannot use: its keys need the key
  // file); every data datagram then fails the pending session's key.
  EXPECT_EQ(restarted.session_counters().hellos, 1u);
  EXPECT_EQ(restarted.counters().bad_mac, 558u);
}

// After a Player restart the old session's datagrams are the new session's replays: nothing.
TEST(ComSession, TheOldSessionReplayedAfterAPlayerRestartGetsNothingIn) {
  ComSessionEnd streamer(long_term, true, seeded(1));
  Pair old_player(streamer, 2);
  old_player.handshake();
  ASSERT_EQ(old_player.drive(100), 100);
  Pair new_player(streamer, 4);
  new_player.handshake();
  ASSERT_EQ(new_player.drive(10), 10);
  const std::uint64_t live = streamer.session();
  const Replayed replayed = replay(streamer, old_player.sent_by_player);
  EXPECT_EQ(replayed.accepted, 0u);
  EXPECT_EQ(replayed.established, 0u);
  EXPECT_EQ(streamer.session(), live);
  EXPECT_EQ(new_player.drive(10, 11), 10);
}

// Eviction (issue #36: after 8 newer sessions the oldest window was forgotten and its replay
// accepted): after ten newer sessions the first session's recording still gets nothing in.
TEST(ComSession, ASessionTenSessionsOldGetsNothingIn) {
  ComSessionEnd streamer(long_term, true, seeded(1));
  Pair first(streamer, 100);
  first.handshake();
  ASSERT_EQ(first.drive(50), 50);
  for (std::uint64_t seed = 101; seed <= 110; ++seed) {
    Pair later(streamer, seed);
    later.handshake();
    ASSERT_EQ(later.drive(5), 5);
  }
  const Replayed replayed = replay(streamer, first.sent_by_player);
  EXPECT_EQ(replayed.accepted, 0u);
  EXPECT_EQ(replayed.established, 0u);
}

// A replay flood during a live session: rejected, and the live session is untouched: a message
// whose first piece came before the flood completes with its second piece after it (the old
// opener cleared partial messages for another session's datagrams before the replay check).
TEST(ComSession, AReplayFloodBesideALiveSessionChangesNothing) {
  ComSessionEnd streamer(long_term, true, seeded(1));
  Pair old_player(streamer, 2);
  old_player.handshake();
  ASSERT_EQ(old_player.drive(200), 200);
  ComSessionEnd player(long_term, false, seeded(5));
  auto welcome = streamer.receive(as_bytes(player.hello(false)));
  ASSERT_TRUE(player.receive(as_bytes(*welcome.reply)).established);
  std::vector<std::string> first;
  ASSERT_TRUE(player.seal(control(1), first));
  ASSERT_TRUE(streamer.receive(as_bytes(first[0])).established);
  // A Ping big enough for two pieces would do; an OperatorControl with large user data does.
  OperatorControl big = control(2);
  big.client_user_data = RawJson{"\"" + std::string(2000, 'x') + "\""};
  std::vector<std::string> pieces;
  ASSERT_TRUE(player.seal(big, pieces));
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_FALSE(streamer.receive(as_bytes(pieces[0])).message);
  std::vector<std::string> flood;
  for (int round = 0; round < 20; ++round) flood.insert(flood.end(), old_player.sent_by_player.begin(), old_player.sent_by_player.end());
  const Replayed replayed = replay(streamer, flood);
  EXPECT_EQ(replayed.accepted, 0u);
  EXPECT_EQ(replayed.established, 0u);
  EXPECT_EQ(streamer.session(), player.session());
  const auto completed = streamer.receive(as_bytes(pieces[1]));
  ASSERT_TRUE(completed.message) << "the flood cost the live session a message";
  EXPECT_EQ(std::get<OperatorControl>(*completed.message).sequence, 2u);
}

// A replayed hello is answered (with a fresh nonce, useless without the key) but moves nothing;
// a replayed welcome is not ours; handshake datagrams with a bit flipped are bad MACs.
TEST(ComSession, ReplayedHandshakesMoveNothing) {
  ComSessionEnd streamer(long_term, true, seeded(1));
  Pair pair(streamer, 2);
  const std::string hello = pair.player.hello(false);
  const auto answered = streamer.receive(as_bytes(hello));
  ASSERT_TRUE(pair.player.receive(as_bytes(*answered.reply)).established);
  ASSERT_EQ(pair.drive(10), 10);
  const std::uint64_t live = streamer.session();
  for (int i = 0; i < 10; ++i) {
    const auto again = streamer.receive(as_bytes(hello));
    EXPECT_FALSE(again.established);
  }
  EXPECT_EQ(streamer.session(), live);
  EXPECT_EQ(pair.player.receive(as_bytes(*answered.reply)).drop, Drop::replayed);
  std::string flipped = hello;
  flipped[40] ^= 1;
  EXPECT_EQ(streamer.receive(as_bytes(flipped)).drop, Drop::bad_mac);
  ComSessionEnd other_key(ComKey(32, 0x11), true, seeded(9));
  EXPECT_EQ(other_key.receive(as_bytes(hello)).drop, Drop::bad_mac);
  EXPECT_EQ(pair.drive(10, 11), 10);
}

}  // namespace
}  // namespace ocp::com
