// libFuzzer target: the com channel's datagram codec (ocp/com_datagram.hpp) and its session
// ends (ocp/com_session.hpp). The first byte
// picks the body kind; the input is opened as a datagram by both sides' openers (with the
// fuzzer's key and with the insecure empty one, so sealed inputs reach reassembly and the body
// decoder) and decoded as a body. Properties: no crash; a decoded body re-encodes to a body
// that decodes again (round trip stability).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "ocp/com_datagram.hpp"
#include "ocp/com_session.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ocp::com;
  static DatagramOpener keyed_streamer(ComKey(32, 0x5a), true);
  static DatagramOpener keyed_player(ComKey(32, 0x5a), false);
  static DatagramOpener insecure_streamer(ComKey{}, true);
  static DatagramOpener insecure_player(ComKey{}, false);
  const std::span<const std::uint8_t> input(data, size);
  (void)keyed_streamer.open(input);
  (void)keyed_player.open(input);
  (void)insecure_streamer.open(input);
  (void)insecure_player.open(input);
  // Both ends of a session (issue #36): hellos, welcomes and data of unknown sessions.
  static const auto counting = [](std::uint8_t* bytes, std::size_t count) {
    static std::uint8_t next = 0;
    for (std::size_t i = 0; i < count; ++i) bytes[i] = next++;
  };
  static ComSessionEnd insecure_streamer_end(ComKey{}, true, counting);
  static ComSessionEnd insecure_player_end(ComKey{}, false, counting);
  (void)insecure_streamer_end.receive(input);
  (void)insecure_player_end.receive(input);
  if (size == 0) return 0;
  const auto kind = static_cast<LinkKind>(1 + data[0] % 5);
  const std::string_view body(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (const auto message = decode_body(kind, body)) {
    if (!decode_body(kind, encode_body(*message))) __builtin_trap();
    // And sealed, it opens again.
    DatagramSealer sealer(ComKey{}, 1);
    DatagramOpener opener(ComKey{}, travels_to_streamer(kind));
    std::vector<std::string> datagrams;
    if (sealer.seal(*message, datagrams)) {
      bool delivered = false;
      for (const auto& datagram : datagrams) {
        const auto opened = opener.open({reinterpret_cast<const std::uint8_t*>(datagram.data()), datagram.size()});
        if (opened.drop != Drop::none) __builtin_trap();
        delivered = delivered || opened.message.has_value();
      }
      if (!delivered) __builtin_trap();
    }
  }
  return 0;
}
