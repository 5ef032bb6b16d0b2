#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/frame.hpp"

namespace ocp {
namespace {

struct Decoded {
  std::vector<std::string> frames;
  std::vector<std::uint32_t> dropped_lengths;
  std::vector<int> order;  // 0 = frame, 1 = dropped, in arrival order
  bool operator==(const Decoded&) const = default;
};

// Pushes `input` through `decoder` until it needs more, collecting every event.
void feed(FrameDecoder& decoder, std::string_view input, Decoded& decoded) {
  while (true) {
    FrameEvent event;
    const std::size_t consumed = decoder.put(input, event);
    ASSERT_LE(consumed, input.size());
    input.remove_prefix(consumed);
    if (event.kind == FrameEvent::Kind::need_more) {
      ASSERT_TRUE(input.empty()) << "need_more must consume everything";
      return;
    }
    if (event.kind == FrameEvent::Kind::frame) {
      decoded.frames.emplace_back(event.payload);
      decoded.order.push_back(0);
    } else {
      decoded.dropped_lengths.push_back(event.declared_length);
      decoded.order.push_back(1);
    }
  }
}

std::string frame(std::string_view payload) {
  std::string out;
  EXPECT_TRUE(append_frame(payload, out).ok());
  return out;
}

std::string header(std::uint32_t length) {
  return std::string{static_cast<char>(length & 0xFF), static_cast<char>((length >> 8) & 0xFF),
                     static_cast<char>((length >> 16) & 0xFF),
                     static_cast<char>((length >> 24) & 0xFF)};
}

std::string three_frame_stream() {
  return frame(R"({"ack_time":1,"ack_time_mac":2})") + frame("") + frame(R"({"x":[1,2,3]})");
}

const Decoded expected_three_frames{
    {R"({"ack_time":1,"ack_time_mac":2})", "", R"({"x":[1,2,3]})"}, {}, {0, 0, 0}};

TEST(Frame, AppendFrameWritesALittleEndianLengthPrefix) {
  std::string out = "keep";
  ASSERT_TRUE(append_frame("abc", out).ok());
  EXPECT_EQ(out, std::string("keep\x03\x00\x00\x00" "abc", 11));
  const std::string big(0x0102, 'x');
  out.clear();
  ASSERT_TRUE(append_frame(big, out).ok());
  EXPECT_EQ(out.substr(0, 4), std::string("\x02\x01\x00\x00", 4));
}

TEST(Frame, LengthPrefixIsWrittenAndReadLittleEndian) {
  std::string out = "keep";
  append_length_prefix(0x04030201u, out);
  EXPECT_EQ(out, "keep" + header(0x04030201u));
  append_length_prefix(0xFFFFFFFFu, out);  // no limit: a bare header may declare anything
  EXPECT_EQ(out.substr(8), header(0xFFFFFFFFu));
  EXPECT_EQ(read_length_prefix(header(0x04030201u) + "payload"), 0x04030201u);
  EXPECT_EQ(read_length_prefix(header(0xFFFFFFFFu)), 0xFFFFFFFFu);
  EXPECT_EQ(read_length_prefix(header(20000).substr(0, 3)), std::nullopt);
  EXPECT_EQ(read_length_prefix(""), std::nullopt);
}

TEST(Frame, PutAllHandsOnEveryEventInArrivalOrder) {
  FrameDecoder decoder(8);
  const std::string stream = frame("a") + header(9) + std::string(9, 'x') + frame("") + frame("bc");
  Decoded decoded;
  for (std::size_t at = 0; at < stream.size(); at += 5) {  // in pieces, split anywhere
    decoder.put_all(
        std::string_view(stream).substr(at, 5),
        [&](std::string_view payload) {
          decoded.frames.emplace_back(payload);
          decoded.order.push_back(0);
          return true;
        },
        [&](std::uint32_t declared_length) {
          decoded.dropped_lengths.push_back(declared_length);
          decoded.order.push_back(1);
          return true;
        });
  }
  EXPECT_EQ(decoded, (Decoded{{"a", "", "bc"}, {9}, {0, 1, 0, 0}}));
  EXPECT_FALSE(decoder.mid_frame());
}

TEST(Frame, PutAllStopsWhenAHandlerSaysSo) {
  FrameDecoder decoder;
  std::vector<std::string> payloads;
  decoder.put_all(three_frame_stream(), [&](std::string_view payload) {
    payloads.emplace_back(payload);
    return false;  // as a handler that closed its connection
  });
  EXPECT_EQ(payloads, std::vector<std::string>{R"({"ack_time":1,"ack_time_mac":2})"});
}

TEST(Frame, AppendFrameAcceptsExactlyTheLimit) {
  std::string out;
  ASSERT_TRUE(append_frame(std::string(max_payload_bytes, 'x'), out).ok());
  EXPECT_EQ(out.size(), max_payload_bytes + frame_header_bytes);
}

TEST(Frame, AppendFrameRefusesOneByteOverTheLimitAndLeavesOutUntouched) {
  std::string out = "previous";
  const Status status = append_frame(std::string(max_payload_bytes + 1, 'x'), out);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, make_error_code(LocalError::frame_too_large));
  EXPECT_EQ(status.error().detail, "payload of 16385 bytes exceeds the limit of 16384 bytes");
  EXPECT_EQ(out, "previous");
  EXPECT_FALSE(append_frame("12345", out, 4).ok()) << "the limit is configurable";
}

TEST(Frame, DecodesAStreamGivenInOneChunk) {
  FrameDecoder decoder;
  Decoded decoded;
  feed(decoder, three_frame_stream(), decoded);
  EXPECT_EQ(decoded, expected_three_frames);
  EXPECT_TRUE(decoder.finish().ok());
  EXPECT_FALSE(decoder.mid_frame());
}

TEST(Frame, EverySplitIntoTwoChunksDecodesTheSame) {
  const std::string stream = three_frame_stream();
  for (std::size_t split = 0; split <= stream.size(); ++split) {
    SCOPED_TRACE(split);
    FrameDecoder decoder;
    Decoded decoded;
    const std::string first = stream.substr(0, split);  // copies: payload views must not
    const std::string second = stream.substr(split);    // outlive their chunk
    feed(decoder, first, decoded);
    feed(decoder, second, decoded);
    EXPECT_EQ(decoded, expected_three_frames);
    EXPECT_TRUE(decoder.finish().ok());
  }
}

TEST(Frame, EverySplitIntoThreeChunksDecodesTheSame) {
  const std::string stream = three_frame_stream();
  for (std::size_t a = 0; a <= stream.size(); ++a) {
    for (std::size_t b = a; b <= stream.size(); ++b) {
      FrameDecoder decoder;
      Decoded decoded;
      feed(decoder, stream.substr(0, a), decoded);
      feed(decoder, stream.substr(a, b - a), decoded);
      feed(decoder, stream.substr(b), decoded);
      ASSERT_EQ(decoded, expected_three_frames) << a << " " << b;
    }
  }
}

TEST(Frame, ByteByByteDecodesTheSame) {
  const std::string stream = three_frame_stream();
  FrameDecoder decoder;
  Decoded decoded;
  for (const char byte : stream) {
    feed(decoder, std::string_view(&byte, 1), decoded);
  }
  EXPECT_EQ(decoded, expected_three_frames);
  EXPECT_TRUE(decoder.finish().ok());
}

TEST(Frame, WholeFramesArriveWithoutCopying) {
  const std::string stream = frame("payload");
  FrameDecoder decoder;
  FrameEvent event;
  EXPECT_EQ(decoder.put(stream, event), stream.size());
  ASSERT_EQ(event.kind, FrameEvent::Kind::frame);
  EXPECT_EQ(event.payload.data(), stream.data() + frame_header_bytes);
}

TEST(Frame, PutReportsAtMostOneEventAndConsumesOnlyItsBytes) {
  const std::string stream = frame("a") + frame("bc");
  FrameDecoder decoder;
  FrameEvent event;
  EXPECT_EQ(decoder.put(stream, event), 5u);
  EXPECT_EQ(event.payload, "a");
  EXPECT_EQ(decoder.put(std::string_view(stream).substr(5), event), 6u);
  EXPECT_EQ(event.payload, "bc");
  EXPECT_EQ(decoder.put("", event), 0u);
  EXPECT_EQ(event.kind, FrameEvent::Kind::need_more);
}

TEST(Frame, ZeroLengthPayloadIsAnEmptyFrame) {
  FrameDecoder decoder;
  FrameEvent event;
  EXPECT_EQ(decoder.put(header(0), event), 4u);
  EXPECT_EQ(event.kind, FrameEvent::Kind::frame);
  EXPECT_TRUE(event.payload.empty());
  EXPECT_FALSE(decoder.mid_frame());
}

TEST(Frame, PayloadOfExactlyTheLimitIsAccepted) {
  const std::string payload(max_payload_bytes, 'p');
  const std::string stream = frame(payload);
  for (const std::size_t chunk : {stream.size(), std::size_t{1000}, std::size_t{1}}) {
    SCOPED_TRACE(chunk);
    FrameDecoder decoder;
    Decoded decoded;
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
      feed(decoder, std::string_view(stream).substr(at, chunk), decoded);
    }
    ASSERT_EQ(decoded.frames.size(), 1u);
    EXPECT_EQ(decoded.frames[0], payload);
  }
}

TEST(Frame, OversizedFrameIsDrainedAndReportedThenTheNextFrameDecodes) {
  const std::string stream =
      header(max_payload_bytes + 1) + std::string(max_payload_bytes + 1, '{') + frame("next");
  for (const std::size_t chunk : {stream.size(), std::size_t{4096}, std::size_t{3}}) {
    SCOPED_TRACE(chunk);
    FrameDecoder decoder;
    Decoded decoded;
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
      feed(decoder, std::string_view(stream).substr(at, chunk), decoded);
    }
    EXPECT_EQ(decoded.dropped_lengths, std::vector<std::uint32_t>{16385});
    EXPECT_EQ(decoded.frames, std::vector<std::string>{"next"});
    EXPECT_EQ(decoded.order, (std::vector<int>{1, 0}));
    EXPECT_TRUE(decoder.finish().ok());
  }
}

TEST(Frame, HugeDeclaredLengthIsDrainedNotAllocated) {
  FrameDecoder decoder;
  FrameEvent event;
  EXPECT_EQ(decoder.put(header(0xFFFFFFFF), event), 4u);
  EXPECT_EQ(event.kind, FrameEvent::Kind::need_more);
  const std::string chunk(1 << 20, 'z');
  std::uint64_t drained = 0;
  while (drained < 0xFFFFFFFFull) {
    const std::size_t size =
        static_cast<std::size_t>(std::min<std::uint64_t>(chunk.size(), 0xFFFFFFFFull - drained));
    ASSERT_EQ(decoder.put(std::string_view(chunk).substr(0, size), event), size);
    drained += size;
    if (drained < 0xFFFFFFFFull) {
      ASSERT_EQ(event.kind, FrameEvent::Kind::need_more);
    }
  }
  EXPECT_EQ(event.kind, FrameEvent::Kind::oversized_dropped);
  EXPECT_EQ(event.declared_length, 0xFFFFFFFFu);
  EXPECT_FALSE(decoder.mid_frame());
}

TEST(Frame, ConfigurableLimit) {
  FrameDecoder decoder(3);
  Decoded decoded;
  feed(decoder, frame("abc") + frame("abcd"), decoded);
  EXPECT_EQ(decoded.frames, std::vector<std::string>{"abc"});
  EXPECT_EQ(decoded.dropped_lengths, std::vector<std::uint32_t>{4});
}

TEST(Frame, TruncatedStreamIsReportedByFinish) {
  struct Case {
    std::string stream;
    const char* detail;
  };
  const Case cases[] = {
      {header(5).substr(0, 3), "stream ended inside a frame header: 1 of 4 header bytes missing"},
      {header(5) + "ab", "stream ended inside a 5-byte payload: 3 payload bytes missing"},
      {header(20000) + "xyz",
       "stream ended while draining an oversized 20000-byte frame: 19997 bytes missing"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.detail);
    FrameDecoder decoder;
    Decoded decoded;
    feed(decoder, c.stream, decoded);
    EXPECT_TRUE(decoder.mid_frame());
    const Status status = decoder.finish();
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, make_error_code(PeerError::truncated_frame));
    EXPECT_EQ(status.error().detail, c.detail);
  }
}

TEST(Frame, ResetDiscardsAPartialFrame) {
  FrameDecoder decoder;
  Decoded decoded;
  feed(decoder, header(10) + "abc", decoded);
  decoder.reset();
  EXPECT_FALSE(decoder.mid_frame());
  feed(decoder, frame("ok"), decoded);
  EXPECT_EQ(decoded.frames, std::vector<std::string>{"ok"});
}

}  // namespace
}  // namespace ocp
