#pragma once
// Shared pieces of the vehicle case bodies (private to the library).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "conformance/case.hpp"
#include "conformance/case_context.hpp"
#include "conformance/control_frames.hpp"
#include "conformance/observations.hpp"
#include "ocp/pair_diagnosis.hpp"

namespace ocp::conformance::detail {

using std::chrono::milliseconds;

// The Streamer's ack_time is its age in µs plus the setup's offset, and wraps past 2^64-1: an
// offset just below it leaves this much life before the pairs become small again (and would
// survive a double). 10 min: far beyond any case, with a client that takes seconds to start.
inline constexpr std::uint64_t ocp_ack_time_headroom_us = 600'000'000;

inline Outcome ok(std::string actual) { return {Verdict::ok, std::move(actual), {}}; }
inline Outcome non_strict(std::string actual) { return {Verdict::non_strict, std::move(actual), {}}; }
inline Outcome informational(std::string actual) { return {Verdict::informational, std::move(actual), {}}; }
inline Outcome failed(std::string actual) { return {Verdict::failed, std::move(actual), {}}; }

// SPEC §2 Decision: a client is graded MUST only on what the real product can send it. A case
// that checks robustness beyond that (surviving a frame above 16 KiB, which the product never
// sends) is SHOULD, and its failure is reported as NON-STRICT, with the reason.
inline Outcome beyond_what_the_product_sends(Outcome outcome) {
  if (outcome.verdict != Verdict::failed) return outcome;
  return non_strict(outcome.actual + " (a robustness check: the product never sends a frame above 16 KiB)");
}

// SPEC §2 Decision: a MUST is graded at the product's own line. The product closes a connection
// after 2 000 ms without a byte, so a silence that long fails; one under it by less than half
// (over 1 000 ms) works with little room: NON-STRICT, the margin named.
inline constexpr std::int64_t product_read_timeout_us = 2'000'000;
inline constexpr std::int64_t silence_margin_us = 1'000'000;
inline Outcome grade_longest_silence(const std::string& counts, std::int64_t longest_us) {
  if (longest_us >= product_read_timeout_us) {
    return failed(counts + " (the product closes the connection after 2 000 ms without a byte)");
  }
  if (longest_us > silence_margin_us) {
    return non_strict(
        fmt::format("{} (under the product's 2 000 ms read timeout by only {} ms: keep-alives well inside "
                    "it, e.g. every 10 ms to 1 s)",
                    counts, (product_read_timeout_us - longest_us) / 1000));
  }
  return ok(counts);
}

inline std::string last_close(const Observations& observed) {
  return observed.close_codes.empty() ? std::string("unknown reason") : observed.close_codes.back();
}

inline std::string describe(const AckPair& pair) { return fmt::format("({}, {})", pair.ack_time, pair.ack_time_mac); }

// First response at or after `after_us` carrying exactly `pair`, or nullptr.
inline const Response* first_echo(const Observations& observed, const AckPair& pair, std::int64_t after_us) {
  for (const Response& response : observed.responses) {
    if (response.time_us >= after_us && response.ack && *response.ack == pair) return &response;
  }
  return nullptr;
}

// Responses in the window (observations.hpp: what the client wrote before it read a control
// message is vehicle/3.3/4's business) at or after `after_us` whose pair is neither one the
// Streamer sent nor `extra`.
inline std::vector<AckPair> unknown_pairs(const Observations& observed, std::int64_t after_us,
                                          const std::vector<AckPair>& extra = {}) {
  const auto known = [&](const AckPair& pair) {
    return observed.find_sent(pair) >= 0 || std::find(extra.begin(), extra.end(), pair) != extra.end();
  };
  std::vector<AckPair> out;
  for (const Response& response : observed.responses) {
    if (response.time_us >= after_us && response.ack && !known(*response.ack)) out.push_back(*response.ack);
  }
  return out;
}

// A failure over pairs nobody sent, with the cause named when one fits (ocp/pair_diagnosis.hpp).
inline Outcome failed_with_cause(std::string actual, const std::vector<AckPair>& altered,
                                 const std::vector<AckPair>& sent) {
  Outcome outcome = failed(std::move(actual));
  const PairDiagnosis diagnosis = diagnose_altered_pairs(altered, sent);
  outcome.cause = diagnosis.cause;
  if (!diagnosis.cause.empty()) outcome.actual += "; cause: " + diagnosis.cause + " (" + diagnosis.example + ")";
  return outcome;
}

// Every pair the Streamer sent on the vehicle wire, in order.
inline std::vector<AckPair> sent_pairs(const Observations& observed) {
  std::vector<AckPair> sent;
  for (const SentPair& pair : observed.sent) sent.push_back(pair.ack);
  return sent;
}

// The same on the vehicle wire; `crafted`: hand-made pairs written besides the Streamer's own.
inline Outcome failed_over_altered_pairs(std::string actual, const std::vector<AckPair>& altered,
                                         const Observations& observed, const std::vector<AckPair>& crafted = {}) {
  std::vector<AckPair> sent = crafted;
  for (const AckPair& pair : sent_pairs(observed)) sent.push_back(pair);
  return failed_with_cause(std::move(actual), altered, sent);
}

inline std::string list_pairs(const std::vector<AckPair>& pairs, std::size_t max = 3) {
  std::string out;
  for (std::size_t i = 0; i < pairs.size() && i < max; ++i) {
    out += i ? ", " : "";
    out += describe(pairs[i]);
  }
  if (pairs.size() > max) out += fmt::format(" … ({} in all)", pairs.size());
  return out;
}

// Hand-made frames: pauses the Streamer's own output, writes `count` frames `gap` apart, then
// watches `settle` more. Pairs are distinct and large (u64 above 2^63, u32 above 2^31).
struct CraftedRun {
  std::vector<AckPair> pairs;
  std::int64_t start_us = 0;
  std::size_t closes_before = 0;
};

inline AckPair crafted_pair(std::uint64_t salt, std::size_t i) {
  return AckPair{(std::uint64_t{1} << 63) + salt * 1'000'000 + i,
                 0x80000000u + static_cast<std::uint32_t>(salt * 1000 + i)};
}

inline CraftedRun send_crafted(CaseContext& context, std::size_t count, milliseconds gap, milliseconds settle,
                               const std::function<CraftedControl(std::size_t)>& make) {
  CraftedRun run;
  run.start_us = context.now_us();
  run.closes_before = Observations::from(context.entries()).closed_us.size();
  context.streamer().set_control_output_paused(true);
  for (std::size_t i = 0; i < count; ++i) {
    CraftedControl control = make(i);
    run.pairs.push_back(control.ack);
    if (!context.streamer().vehicle_connected()) break;
    (void)context.streamer().write_raw_to_vehicle(frame_bytes(control_payload(control)));
    context.run_for(gap);
  }
  context.run_for(settle);
  return run;
}

// The common verdict of "the client must accept these frames": still connected, the last pair
// echoed, no pair echoed that nobody sent.
inline Outcome grade_crafted(CaseContext& context, const CraftedRun& run, const std::string& what) {
  const Observations observed = Observations::from(context.entries());
  std::size_t echoed = 0;
  for (const AckPair& p : run.pairs) echoed += first_echo(observed, p, run.start_us) != nullptr;
  const bool closed = observed.closed_us.size() > run.closes_before;
  const auto unknown = unknown_pairs(observed, run.start_us);
  const bool last = !run.pairs.empty() && first_echo(observed, run.pairs.back(), run.start_us) != nullptr;
  const std::string counts = fmt::format("{} frames {}; {} of their pairs echoed", run.pairs.size(), what, echoed);
  if (closed) {
    return failed(fmt::format("{}; the connection closed ({})", counts,
                              observed.close_codes.empty() ? "?" : observed.close_codes.back()));
  }
  if (!unknown.empty()) {
    return failed_over_altered_pairs(fmt::format("{}; echoed pairs never sent: {}", counts, list_pairs(unknown)),
                                     unknown, observed, run.pairs);
  }
  if (!last) return failed(fmt::format("{}; the last pair {} was never echoed", counts, describe(run.pairs.back())));
  return ok(fmt::format("{}; last pair echoed; connection kept", counts));
}

// "Reconnect after a short delay" (seed 000, Practical connection rules): the seed's own
// example client sleeps 100 ms before it reconnects (seed 000, the Rust example:
// `thread::sleep(Duration::from_millis(100))`), and the Streamer's 2 s read timeout and
// 1 s NoControlMessage bound what "short" can mean. So: at least 20 ms (a client that
// reconnects at once hammers a restarting Streamer in a tight loop) and at most 1 s (the
// vehicle is without control meanwhile). Three server closes, each one measured.
inline constexpr std::int64_t reconnect_min_us = 20'000;
inline constexpr std::int64_t reconnect_max_us = 1'000'000;

// `close` ends the client's connection from the server side (the Streamer's or the Player's).
inline Outcome grade_reconnect_delays(CaseContext& context, const std::function<void()>& close) {
  std::vector<double> delays_ms;
  for (int round = 0; round < 3; ++round) {
    context.run_for(milliseconds(200));
    if (!context.host().client_connected()) break;
    const std::int64_t break_us = context.now_us();
    context.note("server closes the client's connection");
    close();
    const bool back = context.wait_until(
        [&] { return !Observations::from(context.entries(), break_us).opened_us.empty(); }, milliseconds(3000));
    if (!back) break;
    delays_ms.push_back(
        static_cast<double>(Observations::from(context.entries(), break_us).opened_us.front() - break_us) / 1000.0);
  }
  std::string list;
  for (const double d : delays_ms) list += fmt::format("{}{:.1f} ms", list.empty() ? "" : ", ", d);
  const std::string counts =
      fmt::format("reconnect delays after {} server closes: {}", delays_ms.size(), list.empty() ? "none" : list);
  if (delays_ms.size() < 3)
    return non_strict(counts + fmt::format("; no reconnect within 3 s after close {}", delays_ms.size() + 1));
  const double shortest = *std::min_element(delays_ms.begin(), delays_ms.end());
  const double longest = *std::max_element(delays_ms.begin(), delays_ms.end());
  if (shortest < static_cast<double>(reconnect_min_us) / 1000.0)
    return non_strict(counts + " (at once: a tight reconnect loop; wait ~100 ms)");
  if (longest > static_cast<double>(reconnect_max_us) / 1000.0)
    return non_strict(counts +
                      " (seconds: the vehicle is without control, or the operator without feedback, meanwhile)");
  return ok(counts);
}

}  // namespace ocp::conformance::detail
