#pragma once
// The app layer's loaders of the files the sans-IO layers parse: each reads the file through
// the one bounded reader (ocp/bounded_file.hpp: regular files only, a cap per kind) and hands
// the text to the parser, which never touches a file. Errors name the file.
#include <string>

#include "ocp/delivery_trace.hpp"
#include "ocp/error.hpp"
#include "ocp/link_recording.hpp"
#include "player/gamepad.hpp"

namespace ocp::sim_app {

// A Mahimahi delivery trace (--link-trace-up/--link-trace-down).
Result<DeliveryTrace> load_delivery_trace(const std::string& path);
// A recorded run's link (docs/link-recording.md).
Result<LinkRecording> load_link_recording(const std::string& path);
// A gamepad recording (--gamepad FILE; player/gamepad.hpp's text format).
Result<Recording> load_gamepad_recording(const std::string& path);

}  // namespace ocp::sim_app
