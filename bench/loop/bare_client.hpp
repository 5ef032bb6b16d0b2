#pragma once
// BareClient: the fastest correct client, a reference of `ocp_bench loop --compare`. One thread
// blocked in read() on a plain TCP_NODELAY socket; each control message is decoded with the
// libocp codec and answered at once with its pair — no event loop, no timers, no safety layer,
// no model, no keep-alive. Run against a Streamer of its own, its echo delay is what the
// Streamer and the machine cost a client that does nothing else; the client under test divided
// by it is what the client's own design adds (the machine floor, FloorEcho, has no Streamer in
// it at all).
#include <atomic>
#include <cstdint>
#include <thread>

namespace ocp::bench {

class BareClient {
 public:
  explicit BareClient(std::uint16_t port);
  ~BareClient() { stop(); }
  BareClient(const BareClient&) = delete;
  BareClient& operator=(const BareClient&) = delete;
  void stop();   // unblocks the read and joins

 private:
  std::atomic<int> socket_{-1};
  std::thread thread_;
};

}  // namespace ocp::bench
