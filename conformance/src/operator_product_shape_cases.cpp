// `ocp_conformance operator`, the product's own VehicleOcpShared shapes (issue #26): the
// simulated Player always fills every field, but the product may send null or a list where
// SPEC §4.1 allows it, and fields a later product adds (SPEC §2); a client must keep reading
// and returning pairs through every one. And with a single vehicle the active_vehicle rules
// of SPEC §7 hold too: absent, or the one linked vehicle.
#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"
#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"
#include "operator_observations.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

struct SharedForm {
  const char* name;  // what the form is, and where it is allowed
  std::function<void(VehicleOcpShared&)> shape;
  bool unknown_fields = false;
};

VehicleFeedback& hosted_feedback(VehicleOcpShared& shared) { return shared.vehicle_feedback[host_vehicle_name]; }

const std::vector<SharedForm>& product_shared_forms() {
  static const std::vector<SharedForm> forms{
      {"\"vehicle_data\": null (SPEC §4.1: `{…} | null`, before the vehicle sent any)",
       [](VehicleOcpShared& s) { hosted_feedback(s).vehicle_data.reset(); }},
      {"a camera lost: \"missing_cameras\": [\"rear\"] (SPEC §4.1: `[\"rear\"] | null`)",
       [](VehicleOcpShared& s) { hosted_feedback(s).missing_cameras = std::vector<std::string>{"rear"}; }},
      {"\"message_latency_roundtrip\": null (SPEC §4.1: `80 | null`, until measured)",
       [](VehicleOcpShared& s) { hosted_feedback(s).message_latency_roundtrip.reset(); }},
      {"\"last_input\": null (SPEC §4.1: `{controller} | null`)", [](VehicleOcpShared& s) { s.last_input.reset(); }},
      {"unknown extra fields at top level and in the vehicle's entry (SPEC §2: \"Unknown extra fields are ignored … on "
       "every message\")",
       {},
       true},
      {"\"last_remote_input\": null for a control vehicle (SPEC §4.1: `{controller} | null`)",
       [](VehicleOcpShared& s) { hosted_feedback(s).last_remote_input.reset(); }},
      {"non-ASCII text: UTF-8 in vehicle_data (SPEC §2: the length prefix counts UTF-8 bytes, not characters)",
       [](VehicleOcpShared& s) {
         hosted_feedback(s).vehicle_data = VehicleUserData{
             std::nullopt, RawJson{R"({"driver":"Åsa Öberg","route":"Göteborg → Malmö","名前":"トラック"})"}};
       }},
      {"a frame of about 16 KiB: a large vehicle_data (SPEC §2: frames up to 16 384 bytes; a fleet's vehicle_data is "
       "as "
       "large as its vehicles send)",
       [](VehicleOcpShared& s) {
         VehicleFeedback& f = hosted_feedback(s);
         f.vehicle_data = VehicleUserData{std::nullopt, RawJson{R"({"blob":""})"}};
         std::string json;
         encode_vehicle_ocp_shared(s, json);
         // A little under the limit: the pair's digits are already in, nothing else changes.
         const std::size_t rest = max_payload_bytes - json.size() - 16;
         f.vehicle_data->user_data = RawJson{R"({"blob":")" + std::string(rest, 'x') + R"("})"};
       }},
  };
  return forms;
}

Outcome product_shared_shapes(CaseContext& context) {
  Outcome outcome;
  if (!ready_for_crafted(context, outcome)) return outcome;
  PlayerCore& player = context.host().player();
  const auto& forms = product_shared_forms();
  const std::int64_t start = context.now_us();
  std::vector<AckPair> sent;
  for (std::size_t i = 0; i < forms.size() * 4 && player.client_connected(); ++i) {
    sent.push_back(crafted_pair(81, i));
    const SharedForm& form = forms[i % forms.size()];
    (void)player.write_raw_to_client(shared_frame(context, sent.back(), form.shape, form.unknown_fields));
    context.run_for(milliseconds(15));
  }
  context.run_for(milliseconds(300));
  // Every form's last frame must come back: a client that skips a form still failed it.
  std::vector<AckPair> required;
  for (std::size_t f = 0; f < forms.size() && sent.size() >= forms.size(); ++f)
    required.push_back(sent[sent.size() - forms.size() + f]);
  Outcome graded =
      grade_crafted_shared(context, start, sent, required,
                           fmt::format("{} frames in the product's {} other shapes", sent.size(), forms.size()));
  if (graded.verdict == Verdict::ok) return graded;
  // Name the form of the first frame whose pair never came back: that is where the client choked.
  const OperatorObservations observed = OperatorObservations::from(context.entries(), start);
  const auto returned = observed.returned.find(host_vehicle_name);
  for (std::size_t i = 0; i < sent.size(); ++i) {
    bool back = false;
    if (returned != observed.returned.end()) {
      for (const SentPair& r : returned->second) back = back || r.ack == sent[i];
    }
    if (back) continue;
    graded.actual +=
        fmt::format("; the first frame never returned (#{}) is the form: {}", i + 1, forms[i % forms.size()].name);
    break;
  }
  return graded;
}

// SPEC §7 with one vehicle: active_vehicle "may be omitted"; when sent it must still name the
// linked vehicle, or that one vehicle raises VehicleControlInactive and gets no gamepad input.
Outcome single_vehicle_active(CaseContext& context) {
  context.run_for(milliseconds(1000));
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  for (const auto& a : observed.active_vehicle) {
    if (!observed.linked.contains(a.value)) {
      return failed(fmt::format(
          "one vehicle linked ('{}'); active_vehicle '{}' names none: that vehicle gets no gamepad input and "
          "raises VehicleControlInactive",
          host_vehicle_name, a.value));
    }
  }
  if (observed.active_vehicle.empty())
    return ok(fmt::format("one vehicle linked; active_vehicle omitted in all {} client frames (allowed)",
                          observed.client_frames_us.size()));
  return ok(fmt::format("one vehicle linked; active_vehicle '{}' in {} of {} client frames", host_vehicle_name,
                        observed.active_vehicle.size(), observed.client_frames_us.size()));
}

}  // namespace

void add_operator_product_shape_cases(std::vector<VehicleCase>& cases) {
  cases.push_back(
      {{{"operator/4.1/1",
         "handles every VehicleOcpShared shape the product sends",
         "SPEC §4.1, §2 Decision, §2",
         "\"a third-party client is graded MUST only on what the real product can send it\" — SPEC §4.1: "
         "\"message_latency_roundtrip\": 80 | null, \"missing_cameras\": [\"rear\"] | null, \"vehicle_data\": {…} | "
         "null, "
         "\"last_input\": {controller} | null, \"last_remote_input\": {controller} | null — §2: \"Unknown extra fields "
         "are "
         "ignored (forward compatibility), on every message.\", frames of UTF-8 up to 16 384 bytes",
         Tier::must,
         milliseconds(10'000),
         {"OK: 32 frames in the product's other shapes (vehicle_data null; a camera lost; message_latency_roundtrip "
          "null; last_input null; unknown fields; last_remote_input null; non-ASCII text; a frame of about 16 KiB) are "
          "read and the last pair of each shape returned; connection kept"},
         "broken_client.py op-need-vehicle-data (or op-no-lost-camera, op-need-latency, op-need-last-input, "
         "op-strict-schema, "
         "op-need-remote-input, op-char-length, op-small-limit)"},
        product_shared_shapes},
       operator_setup()});
  cases.push_back(
      {{{"operator/7/2",
         "with one vehicle, active_vehicle is omitted or names it",
         "SPEC §7",
         "\"active_vehicle selects the one vehicle that receives gamepad input. One vehicle: may be omitted.\" — "
         "\"Non-selected vehicles raise VehicleControlInactive.\"",
         Tier::must,
         milliseconds(10'000),
         {"OK: with one vehicle linked, every active_vehicle the client sends names it (or it sends none)"},
         "broken_client.py op-fixed-active"},
        single_vehicle_active},
       operator_setup()});
}

}  // namespace ocp::conformance
