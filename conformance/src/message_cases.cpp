// Message content (SPEC §3.2, §3.3, seed 001 schemas): control shapes a client must accept,
// and the schema of what it sends back.
#include <rapidjson/document.h>

#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

Outcome crafted_case(CaseContext& context, std::uint64_t salt, const std::string& what,
                     const std::function<void(CraftedControl&)>& shape) {
  context.run_for(milliseconds(200));
  const CraftedRun run = send_crafted(context, 30, milliseconds(10), milliseconds(300), [&](std::size_t i) {
    CraftedControl control{crafted_pair(salt, i)};
    shape(control);
    return control;
  });
  return grade_crafted(context, run, what);
}

Outcome controller_null(CaseContext& context) {
  return crafted_case(context, 51, "with \"controller\": null",
                      [](CraftedControl& c) { c.controller = CraftedController::null; });
}

Outcome default_with_fault(CaseContext& context) {
  return crafted_case(context, 52, "with the default controller, telemetry.fault true and two fault reasons",
                      [](CraftedControl& c) {
                        c.controller = CraftedController::safe_default;
                        c.fault = true;
                        c.fault_reason = "High Latency, Latency Loop Not Closed";
                      });
}

Outcome nested_client_user_data(CaseContext& context) {
  return crafted_case(context, 53, "with client_user_data nested 16 levels deep",
                      [](CraftedControl& c) { c.client_user_data = conformance::nested_user_data(16); });
}

Outcome unknown_fields(CaseContext& context) {
  return crafted_case(context, 54, "with unknown fields at top level, in telemetry and in controller",
                      [](CraftedControl& c) { c.unknown_fields = true; });
}

// Returns "" when `payload`'s vehicle_user_data follows seed 001, else what is wrong.
// `user_data_not_object` is set when user_data is present but not an object (SPEC Decision
// accepts it; the seed schema says object).
std::string check_user_data(std::string_view payload, bool& user_data_not_object, bool& has_user_data) {
  rapidjson::Document doc;
  doc.Parse(payload.data(), payload.size());
  if (doc.HasParseError() || !doc.IsObject()) return "not a JSON object";
  const auto it = doc.FindMember("vehicle_user_data");
  if (it == doc.MemberEnd() || it->value.IsNull()) return "";
  const auto& vud = it->value;
  if (!vud.IsObject()) return "vehicle_user_data is not an object";
  has_user_data = true;
  const auto user = vud.FindMember("user_data");
  if (user == vud.MemberEnd()) return "vehicle_user_data without user_data";
  if (!user->value.IsObject()) user_data_not_object = true;
  const auto pos = vud.FindMember("pos");
  if (pos == vud.MemberEnd() || pos->value.IsNull()) return "";
  if (!pos->value.IsObject()) return "pos is neither an object nor null";
  for (const char* key : {"lat", "lon"}) {
    const auto field = pos->value.FindMember(key);
    if (field == pos->value.MemberEnd()) return std::string("pos without ") + key;
    if (!field->value.IsNumber()) return std::string("pos.") + key + " is not a number";
  }
  return "";
}

Outcome user_data_schema(CaseContext& context) {
  context.run_for(milliseconds(1000));
  const Observations observed = Observations::from(context.entries());
  std::size_t checked = 0, with_data = 0, not_object = 0;
  std::string first_problem;
  for (const Response& response : observed.all_responses) {  // the schema holds for every response
    if (response.drained) continue;
    ++checked;
    bool odd = false, has = false;
    const std::string problem = check_user_data(response.payload, odd, has);
    with_data += has;
    not_object += odd;
    if (!problem.empty() && first_problem.empty())
      first_problem = problem + " in " + std::string(response.payload.substr(0, 200));
  }
  const std::string counts = fmt::format("{} responses, {} with vehicle_user_data, {} with a non-object user_data",
                                         checked, with_data, not_object);
  if (!first_problem.empty()) return failed(counts + "; " + first_problem);
  if (observed.closed_by_peer_error())
    return failed(counts + "; the Streamer closed the connection: " + last_close(observed));
  if (checked == 0) return failed("no response to check");
  if (not_object > 0) return non_strict(counts);
  return ok(counts);
}

// vehicle/3.3/3 as a standing rule: the schema holds for every response of every case.
std::optional<StandingFinding> user_data_schema_rule(const WireLogEntry& entry) {
  if (entry.drained) return std::nullopt;  // vehicle/2/1's business
  bool not_object = false, has = false;
  const std::string problem = check_user_data(entry.text, not_object, has);
  if (!problem.empty()) return StandingFinding{Verdict::failed, problem};
  if (not_object) return StandingFinding{Verdict::non_strict, "user_data is not an object"};
  return std::nullopt;
}

}  // namespace

void add_message_cases(std::vector<VehicleCase>& cases) {
  cases.push_back({{{"vehicle/3.2/1",
                     "handles controller null",
                     "SPEC §3.2, seed 000 (Read control messages)",
                     "\"controller is null when the operator disabled gamepad forwarding\" — \"When OCP gamepad "
                     "forwarding is disabled from the operator side, controller is null.\"",
                     Tier::must,
                     milliseconds(10'000),
                     {"OK: 30 frames with controller null are accepted; the last pair echoed; connection kept"},
                     "broken_client.py require-controller"},
                    controller_null},
                   {}});
  cases.push_back({{{"vehicle/3.2/2",
                     "handles the default controller with telemetry.fault true and several fault reasons",
                     "SPEC §3.2, seed 000",
                     "\"When a control-path fault is active, OCP sends default controller values and sets the "
                     "telemetry fault state.\" — fault_reason is \"Comma-separated diagnostic text … Do not build "
                     "safety behavior that depends on exact display strings.\"",
                     Tier::must,
                     milliseconds(10'000),
                     {"OK: 30 frames with the safe default controller and fault true are accepted and still echoed; "
                      "connection kept"},
                     "broken_client.py fault-enum"},
                    default_with_fault},
                   {}});
  cases.push_back(
      {{{"vehicle/3.2/3",
         "handles nested client_user_data",
         "SPEC §3.2, seed 001",
         "\"client_user_data: Optional JSON payload from the operator side for this vehicle.\" (any JSON object)",
         Tier::must,
         milliseconds(10'000),
         {"OK: 30 frames whose client_user_data nests objects and arrays 16 levels deep are accepted; connection kept"},
         "broken_client.py flat-user-data"},
        nested_client_user_data},
       {}});
  cases.push_back(
      {{{"vehicle/2/6",
         "ignores unknown extra fields",
         "SPEC §2",
         "\"Unknown extra fields are ignored (forward compatibility), on every message.\"",
         Tier::must,
         milliseconds(10'000),
         {"OK: 30 frames with extra fields at top level, in telemetry and in controller are accepted; connection kept"},
         "broken_client.py strict-schema"},
        unknown_fields},
       {}});
  cases.push_back(
      {{{"vehicle/3.3/3",
         "vehicle_user_data follows the schema",
         "SPEC §3.3, seed 001 (respond message schema)",
         "\"vehicle_user_data optional; when present user_data is required …, pos optional or null; when present it "
         "needs numeric lat and lon.\"",
         Tier::must,
         milliseconds(10'000),
         {"OK: every vehicle_user_data is an object with user_data (an object) and pos absent, null or {lat: number, "
          "lon: number}, "
          "in this case and in every other case of the run (a standing rule: the first offending frame is named)",
          "NON-STRICT: user_data present but not an object (accepted by the SPEC Decision; seed 001 says object)"},
         "broken_client.py bad-pos (FAILED; the Streamer also drops it); broken_client.py once-bad-pos (with "
         "vehicle/3.3/1); "
         "broken_client.py scalar-user-data (NON-STRICT)"},
        user_data_schema,
        user_data_schema_rule},
       {}});
}

}  // namespace ocp::conformance
