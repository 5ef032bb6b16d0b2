// The product's own message shapes (issue #26): the simulator's Streamer always sends one
// shape, but the product may send others that SPEC and the seeds allow, and a client must
// handle every one (SPEC §2 Decision: graded MUST on what the real product can send). This
// case sends each form the product can send, each cited where it is allowed, interleaved,
// and names the form of the first frame whose pair never came back.
#include "case_helpers.hpp"
#include "conformance/control_frames.hpp"
#include "conformance/vehicle_cases.hpp"
#include "ocp/frame.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

struct ControlForm {
  const char* name;  // what the form is, and where it is allowed
  void (*shape)(CraftedControl&);
};

// Every form of OcpControlMessage the product may send besides the simulator's own.
const std::vector<ControlForm>& product_control_forms() {
  static const std::vector<ControlForm> forms{
      {"no \"controller\" key (seed 001 schema: required is telemetry, ack_time, ack_time_mac; Rust "
       "`Option<Controller>`)",
       [](CraftedControl& c) { c.controller = CraftedController::absent; }},
      {"\"client_user_data\": null (SPEC §3.2: \"omitted or null when the operator sent none\"; seed 001 "
       "`Option<Value>`)",
       [](CraftedControl& c) { c.client_user_data = "null"; }},
      {"telemetry without \"missing_cameras\" (seed 001 schema: telemetry requires latency, fault, fault_reason only)",
       [](CraftedControl& c) { c.missing_cameras.clear(); }},
      {"a camera lost: \"missing_cameras\": [\"rear\"], fault true, \"Camera Lost\" (SPEC §3.2, §6: CameraLost passes "
       "the controller through)",
       [](CraftedControl& c) {
         c.missing_cameras = R"(["rear"])";
         c.fault = true;
         c.fault_reason = "Camera Lost";
       }},
      {"all of them in one frame (SPEC §3.2, seed 001)",
       [](CraftedControl& c) {
         c.controller = CraftedController::absent;
         c.client_user_data = "null";
         c.missing_cameras.clear();
       }},
      {"a control-path fault with \"controller\": null (SPEC §3.2: with ocp_disable_gamepad the controller \"stays "
       "null\" "
       "during a fault)",
       [](CraftedControl& c) {
         c.controller = CraftedController::null;
         c.fault = true;
         c.fault_reason = "High Latency, Latency Loop Not Closed";
       }},
      // Last of the forms, so the last frame of the case is one: a client whose frame limit is
      // below 16 KiB skips it and never echoes the last pair.
      {"a frame of exactly 16 384 bytes: a large client_user_data (SPEC §2: the limit is 16 384; the operator's "
       "user data is passed through)",
       [](CraftedControl& c) {
         c.client_user_data = R"({"blob":""})";
         const std::size_t rest = max_payload_bytes - control_payload(c).size();
         c.client_user_data = R"({"blob":")" + std::string(rest, 'x') + R"("})";
       }},
  };
  return forms;
}

Outcome product_control_shapes(CaseContext& context) {
  context.run_for(milliseconds(200));
  const auto& forms = product_control_forms();
  const std::size_t rounds = 6;
  const CraftedRun run =
      send_crafted(context, forms.size() * rounds, milliseconds(10), milliseconds(300), [&](std::size_t i) {
        CraftedControl control{crafted_pair(71, i)};
        forms[i % forms.size()].shape(control);
        return control;
      });
  Outcome graded = grade_crafted(context, run, fmt::format("in the product's {} other shapes", forms.size()));
  if (graded.verdict == Verdict::ok) return graded;
  // Name the form of the first frame whose pair never came back: that is where the client choked.
  const Observations observed = Observations::from(context.entries());
  for (std::size_t i = 0; i < run.pairs.size(); ++i) {
    if (first_echo(observed, run.pairs[i], run.start_us)) continue;
    graded.actual +=
        fmt::format("; the first frame never echoed (#{}) is the form: {}", i + 1, forms[i % forms.size()].name);
    break;
  }
  return graded;
}

}  // namespace

void add_product_shape_cases(std::vector<VehicleCase>& cases) {
  cases.push_back(
      {{{"vehicle/3.2/4",
         "handles every control message shape the product sends",
         "SPEC §3.2, §2 Decision, seed 001 (control message schema)",
         "\"a third-party client is graded MUST only on what the real product can send it\" — the product may omit "
         "\"controller\" and \"missing_cameras\" (seed 001 schema), send \"client_user_data\": null (SPEC §3.2) and a "
         "non-empty \"missing_cameras\" when a camera is lost (SPEC §3.2, §6), a fault with a null controller "
         "(SPEC §3.2) and frames up to the 16 384-byte limit (SPEC §2)",
         Tier::must,
         milliseconds(10'000),
         {"OK: 42 frames in the product's other shapes (no controller key; client_user_data null; no missing_cameras; "
          "a camera lost; all at once; a fault with controller null; a 16 384-byte frame) are accepted; the last "
          "pair echoed; connection kept"},
         "broken_client.py need-controller-key (or need-user-data-object, need-missing-cameras, no-lost-camera, "
         "fault-needs-controller, small-limit)"},
        product_control_shapes},
       {}});
}

}  // namespace ocp::conformance
