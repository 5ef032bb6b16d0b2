#pragma once
// What the two reference clients of `ocp_bench loop --compare` (TimerClient, BareClient) share:
// reading the pairs out of the Streamer's byte stream with the libocp codec, and the response
// they answer with — a VehicleResponseMessage carrying only the pair, framed.
#include <string>
#include <string_view>

#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"

namespace ocp::bench {

// Feeds `input` to `decoder` and calls on_pair(pair) for each control message that decodes.
template <typename OnPair>
void for_each_control_pair(FrameDecoder& decoder, std::string_view input, OnPair&& on_pair) {
  decoder.put_all(input, [&on_pair](std::string_view payload) {
    if (auto message = decode_control_message(payload)) on_pair(message->ack);
    return true;
  });
}

// Encodes and frames the response for `pair` into `frame` (`payload` is scratch); false when
// it cannot be framed (it always can: a bare response is a few dozen bytes).
inline bool frame_response(const AckPair& pair, std::string& payload, std::string& frame) {
  VehicleResponseMessage response;
  response.ack = pair;
  payload.clear();
  encode_vehicle_response(response, payload);
  frame.clear();
  return static_cast<bool>(append_frame(payload, frame));
}

}  // namespace ocp::bench
