#pragma once
// `ocp_scenario extract-link`: a run's trace.jsonl (docs/trace-format.md) → a link recording
// of one vehicle (docs/link-recording.md), for `link: {replay: FILE}`. Observes the trace only:
// the link events (sent, delivered, dropped, per route and message id) and, where the two
// ends' clocks differ, the Streamer's latency samples (RTT/2).
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "ocp/link_recording.hpp"

namespace ocp::scenario {

struct ExtractLinkOptions {
  std::string trace_path;
  std::string vehicle;     // empty: the trace's only vehicle
  bool rtt_half = false;   // the clocks differ: every delay is RTT/2, whatever the trace holds
};

// Bad input ("FILE:LINE: reason"), an unknown vehicle (with the known names), nothing to extract.
class ExtractLinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ExtractedLink {
  LinkRecording recording;
  std::vector<std::string> comments;   // the file's header: where from, how, what was left out
};
ExtractedLink extract_link(std::string_view trace_jsonl, const ExtractLinkOptions& options);

// The subcommand: writes the recording to `out`, errors to `err`; returns the exit code
// (0, or 2 for bad input, as for a bad scenario file).
int extract_link_command(const ExtractLinkOptions& options, std::ostream& out, std::ostream& err);

}  // namespace ocp::scenario
