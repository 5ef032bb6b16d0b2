// Saying so when a peer does not speak OCP framing (framing_diagnosis.hpp), and the framed
// connection of both TCP APIs using it.
#include <gtest/gtest.h>

#include <string>

#include "ocp/framed_connection.hpp"
#include "ocp/framing_diagnosis.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

TEST(FramingDiagnosis, NamesWhatThePeerSpeaks) {
  EXPECT_EQ(describe_non_ocp_bytes("GET / HTTP/1.1\r\n"),
            "this does not look like OCP framing (got 'GET / HT…': an HTTP client?)");
  EXPECT_EQ(describe_non_ocp_bytes("HTTP/1.1 400 Bad Request"),
            "this does not look like OCP framing (got 'HTTP/1.1…': an HTTP server?)");
  EXPECT_EQ(describe_non_ocp_bytes("hello\n"),
            "this does not look like OCP framing (got 'hello.': plain text, not a length-prefixed frame)");
  EXPECT_EQ(describe_non_ocp_bytes(R"({"ack_time":1})"),
            "this does not look like OCP framing (got '{\"ack_ti…': JSON without the 4-byte length prefix?)");
  EXPECT_NE(describe_non_ocp_bytes(std::string("\x16\x03\x01\x02\x00", 5)).find("TLS"), std::string::npos);
  EXPECT_NE(describe_non_ocp_bytes(std::string("\x01\x02\xff\xfe", 4)).find("4278125057 bytes"), std::string::npos);
}

TEST(FramingDiagnosis, SnifferSpeaksOnceAndOnlyAboutImplausibleHeaders) {
  FramingSniffer plausible;
  EXPECT_EQ(plausible.observe(std::string("\x20\x4e\x00\x00", 4)), std::nullopt);  // 20 000: just oversized
  EXPECT_EQ(plausible.observe("GET / HTTP/1.1"), std::nullopt);                      // the watch is over
  FramingSniffer text;
  EXPECT_EQ(text.observe("he"), std::nullopt);  // not 4 bytes yet
  const auto said = text.observe("llo");
  ASSERT_TRUE(said.has_value());
  EXPECT_NE(said->find("'hello'"), std::string::npos) << *said;
  EXPECT_EQ(text.observe("more"), std::nullopt);
  EXPECT_EQ(text.diagnosis(), said);
}

TEST(FramingDiagnosis, SnifferTakesItsOwnThresholdAndKeepsTheDeclaredLength) {
  // The vehicle client's: a first frame over the payload limit is already no OCP server's.
  FramingSniffer strict(static_cast<std::uint32_t>(max_payload_bytes + 1));
  EXPECT_EQ(strict.declared_length(), std::nullopt);
  const auto said = strict.observe(std::string("\x20\x4e\x00\x00", 4));  // 20 000
  ASSERT_TRUE(said.has_value());
  EXPECT_NE(said->find("a length prefix of 20000 bytes, far over the 16384-byte limit"), std::string::npos)
      << *said;
  EXPECT_EQ(strict.declared_length(), 20000u);
  FramingSniffer at_the_limit(static_cast<std::uint32_t>(max_payload_bytes + 1));
  EXPECT_EQ(at_the_limit.observe(std::string("\x00\x40\x00\x00", 4)), std::nullopt);  // 16 384: fine
  EXPECT_EQ(at_the_limit.declared_length(), 16384u);
}

struct ConnectionRun {
  VirtualExecutor executor;
  std::vector<std::string> warnings;
  CloseReason close_reason;
  std::shared_ptr<ByteStream> peer;
  std::shared_ptr<FramedConnection> connection;

  ConnectionRun() {
    PipeEnds ends = make_pipe(executor, PipeOptions{});
    peer = ends.b;
    peer->set_handlers(ByteStreamHandlers{[](std::string_view) {}, [](const std::string&) {}});
    Logger logger(executor, "test", [this](const LogRecord& record) {
      if (record.level == LogLevel::warn) warnings.emplace_back(record.message);
    });
    FramedConnection::Handlers handlers;
    handlers.on_payload = [](std::string_view) -> Status { return Ok{}; };
    handlers.on_closed = [this](const CloseReason& reason) { close_reason = reason; };
    FramedConnection::Options options;
    options.label = "vehicle";
    connection = FramedConnection::open(executor, logger, ends.a, options, {}, std::move(handlers));
  }
};

TEST(FramingDiagnosis, FramedConnectionWarnsAtOnceAndRepeatsItWhenClosing) {
  ConnectionRun run;
  run.executor.call_at(SimTime{1000}, [&] { run.peer->write("GET / HTTP/1.1\r\nHost: x\r\n\r\n"); });
  run.executor.run_until(SimTime{2000});
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_NE(run.warnings[0].find("an HTTP client?"), std::string::npos) << run.warnings[0];
  EXPECT_TRUE(run.connection->is_open());  // still drained as SPEC §2 says; the timeout ends it
  run.executor.run_until(SimTime{2'001'000});
  EXPECT_FALSE(run.connection->is_open());
  EXPECT_EQ(run.close_reason.code, PeerError::read_timeout) << run.close_reason;
  EXPECT_NE(run.close_reason.detail.find("an HTTP client?"), std::string::npos) << run.close_reason;
}

TEST(FramingDiagnosis, PlainTextThatEndsSaysSoInTheCloseReason) {
  ConnectionRun run;
  run.executor.call_at(SimTime{1000}, [&] {
    run.peer->write("hello\n");
    run.peer->close();
  });
  run.executor.run_until(SimTime{2000});
  EXPECT_EQ(run.close_reason.code, PeerError::truncated_frame) << run.close_reason;
  EXPECT_NE(run.close_reason.detail.find("plain text"), std::string::npos) << run.close_reason;
}

TEST(FramingDiagnosis, AnOrdinaryOversizedFrameIsNotCalledNonOcp) {
  ConnectionRun run;
  std::string frame("\x20\x4e\x00\x00", 4);
  frame += std::string(20'000, ' ');
  run.executor.call_at(SimTime{1000}, [&] { run.peer->write(frame); });
  run.executor.run_until(SimTime{2000});
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_NE(run.warnings[0].find("dropped oversized frame"), std::string::npos);
}

}  // namespace
}  // namespace ocp
