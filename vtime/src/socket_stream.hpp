#pragma once
// One accepted OCP connection in virtual time: a ByteStream over a real loopback TCP socket.
// Writes wait in `outbox` until the controller flushes them at the end of the instant; bytes
// the client wrote are taken by the controller when the client waits, and handed to the
// handlers through the executor at that instant — or later, when the client's kernel would
// hold them (Nagle's algorithm without TCP_NODELAY: NagleModel).
#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include "ocp/byte_stream.hpp"
#include "ocp/virtual_executor.hpp"
#include "vtime/nagle.hpp"
#include "vtime/protocol.hpp"

namespace ocp::vtime {

// What the shims reported about one connection (every WrittenCount since it was last taken).
struct ClientWrites {
  std::uint64_t written = 0;           // bytes written to it so far
  std::uint64_t first_write_end = 0;   // the end of the first write not taken yet (0: none reported)
  bool no_delay = false;               // the program's TCP_NODELAY, as last reported
  void merge(const WrittenCount& count);
  // Adds one process's report, whose first write is then taken (cleared there).
  void take(ClientWrites& other);
};

class SocketStream final : public ByteStream, public std::enable_shared_from_this<SocketStream> {
 public:
  // `name`: the peer's name in events; not its port, which differs from run to run.
  SocketStream(VirtualExecutor& executor, int fd, std::uint16_t peer_port, std::string name);
  ~SocketStream() override;

  void set_handlers(ByteStreamHandlers handlers) override;
  void write(std::string_view bytes) override;
  void close() override;
  bool is_open() const override { return open_; }
  std::string peer_name() const override { return name_; }
  void set_no_delay(bool on) override;
  std::size_t queued_bytes() const override { return outbox_.size(); }
  bool peer_hung_up() const override { return eof_seen_; }

  // The controller's side.
  std::uint16_t peer_port() const { return peer_port_; }
  int fd() const { return fd_; }
  bool finished() const { return fd_ < 0; }
  // Writes what the socket takes; closes after the last byte when close() was called. Returns
  // the bytes written (and whether anything changed at all, through `changed`).
  std::size_t flush(bool& changed);
  std::uint64_t written_total() const { return written_total_; }
  // Reads what is there (waiting, bounded, until `reported.written` bytes in all have come, or
  // the client's close when `expect_eof`); hands over, at this instant, what the client's kernel
  // would send now (NagleModel). Returns the bytes read.
  std::size_t take(const ClientWrites& reported, bool expect_eof);
  std::uint64_t received_total() const { return received_total_; }
  // True once after take() saw the client's close.
  bool take_eof_news() { return std::exchange(eof_news_, false); }

 private:
  void hand_over(std::string bytes);
  // What the client's kernel sent, up to `sent_end` of its bytes: handed over now.
  void send_unsent(std::uint64_t sent_end);
  void schedule_delayed_ack();
  void hand_over_close(std::string reason);
  void close_socket();

  VirtualExecutor& executor_;
  int fd_;
  std::uint16_t peer_port_;
  std::string name_;
  bool open_ = true;            // for the simulator: false after close() or the peer's close
  bool close_requested_ = false;
  bool eof_seen_ = false;
  bool eof_news_ = false;
  std::string outbox_;
  std::string early_;           // bytes taken before handlers were set
  bool early_close_ = false;
  ByteStreamHandlers handlers_;
  bool have_handlers_ = false;
  std::uint64_t written_total_ = 0;
  std::uint64_t received_total_ = 0;
  std::string unsent_;          // read, but held by the client's kernel (Nagle)
  NagleModel nagle_;
  SimTime delayed_ack_at_{-1};  // the last delayed ACK scheduled
};

}  // namespace ocp::vtime
