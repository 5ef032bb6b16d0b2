// The vehicle client's requirements (issue #26): every rule of SPEC §2, §3, §5, §10 and seed
// 000/001 that a third-party vehicle client can break, one row per broken behaviour. Tiers per
// SPEC §2's Decision: MUST only on what the product can send the client, or on what the product
// documentation requires the client itself to send. The four §10 safety rows are the vehicle's
// own business: the wire shows them only through the client's safety report (safety_report.hpp),
// so they are SHOULD, and a client that does not report is not judged on them.
#include "conformance/requirements.hpp"

namespace ocp::conformance {
namespace {

const std::vector<Requirement> vehicle_requirement_table{
    {"V-2-valid-json", "every response is a length-prefixed JSON object (malformed JSON closes the connection)",
     "SPEC §2, seed 000 (Message framing)", Tier::must, {"vehicle/2/1"}, {"vehicle_client --misbehave-malformed-json"}, ""},
    {"V-2-max-16KiB", "no response above 16 KiB, in any case of the run", "SPEC §2, seed 000 (Message framing)", Tier::must,
     {"vehicle/2/1"}, {"vehicle_client --misbehave-oversized-frames", "broken_client.py once-oversized"}, ""},
    {"V-2-u64-exact", "ack_time (u64, above 2^53) and ack_time_mac (u32) copied byte-exact, never through a double",
     "SPEC §2, seed 000 (IMPORTANT box)", Tier::must, {"vehicle/2/2"}, {"vehicle_client --misbehave-ack-through-double"}, ""},
    {"V-2-split-frames", "reads a control frame however TCP splits it", "SPEC §2", Tier::must, {"vehicle/2/3"},
     {"broken_client.py naive-recv"}, ""},
    {"V-2-coalesced-frames", "reads several control frames coalesced in one segment", "SPEC §2", Tier::must, {"vehicle/2/4"},
     {"broken_client.py naive-recv"}, ""},
    {"V-2-oversized-inbound", "survives an inbound frame above 16 KiB (the product never sends one)", "SPEC §2 Decisions, seed 001",
     Tier::should, {"vehicle/2/5"}, {"broken_client.py reject-oversized"}, ""},
    {"V-2-unknown-fields", "ignores unknown extra fields", "SPEC §2", Tier::must, {"vehicle/2/6"}, {"broken_client.py strict-schema"}, ""},
    {"V-2-read-timeout", "keeps responding while no control message arrives (the 2 s read timeout never fires)",
     "SPEC §2, seed 000 (Connect from the vehicle process)", Tier::must, {"vehicle/2/7"},
     {"broken_client.py echo-only", "vehicle_client --misbehave-silent", "broken_client.py slow-keepalive"}, ""},
    {"V-3.1-reconnect-close", "reconnects after the Streamer closes the connection", "seed 000 (Connect from the vehicle process), SPEC §3.1",
     Tier::must, {"vehicle/3.1/1"}, {"broken_client.py no-reconnect"}, ""},
    {"V-3.1-reconnect-restart", "reconnects after a Streamer restart", "SPEC §3.1, seed 000", Tier::must, {"vehicle/3.1/2"},
     {"broken_client.py no-reconnect"}, ""},
    {"V-3.1-no-stale-pair", "after a reconnect echoes only pairs of the new connection (a restart draws a new MAC key)",
     "SPEC §3.1, §5", Tier::must, {"vehicle/3.1/1", "vehicle/3.1/2"}, {"broken_client.py sticky-pair"}, ""},
    {"V-3.1-one-connection", "one connection at a time: no second connection while one is active",
     "SPEC §3.1, seed 000 (Connect from the vehicle process)", Tier::must, {"vehicle/3.1/3"}, {"broken_client.py second-connection"}, ""},
    {"V-3.1-reconnect-not-at-once", "reconnects after a short delay, not in a tight loop (≥ 20 ms)",
     "seed 000 (Practical connection rules; the Rust example sleeps 100 ms)", Tier::should, {"vehicle/3.1/4"},
     {"broken_client.py reconnect-at-once"}, ""},
    {"V-3.1-reconnect-within-1s", "reconnects within 1 s (NoControlMessage fires after 1 s)", "seed 000 (Practical connection rules), SPEC §3.2",
     Tier::should, {"vehicle/3.1/4"}, {"broken_client.py reconnect-slowly"}, ""},
    {"V-3.2-controller-null", "handles controller null", "SPEC §3.2, seed 000 (Read control messages)", Tier::must, {"vehicle/3.2/1"},
     {"broken_client.py require-controller"}, ""},
    {"V-3.2-fault-default", "handles the default controller with telemetry.fault true and several fault reasons", "SPEC §3.2, §6, seed 000",
     Tier::must, {"vehicle/3.2/2"}, {"broken_client.py fault-enum"}, ""},
    {"V-3.2-nested-user-data", "handles nested client_user_data", "SPEC §3.2, seed 001", Tier::must, {"vehicle/3.2/3"},
     {"broken_client.py flat-user-data"}, ""},
    {"V-3.2-no-controller-key", "handles a control message without the controller key", "seed 001 (control message schema)", Tier::must,
     {"vehicle/3.2/4"}, {"broken_client.py need-controller-key"}, ""},
    {"V-3.2-user-data-null", "handles client_user_data null", "SPEC §3.2", Tier::must, {"vehicle/3.2/4"},
     {"broken_client.py need-user-data-object"}, ""},
    {"V-3.2-no-missing-cameras", "handles telemetry without missing_cameras", "seed 001 (control message schema)", Tier::must,
     {"vehicle/3.2/4"}, {"broken_client.py need-missing-cameras"}, ""},
    {"V-3.2-camera-lost", "handles a non-empty missing_cameras (a camera lost: fault true, controller passed through)", "SPEC §3.2, §6",
     Tier::must, {"vehicle/3.2/4"}, {"broken_client.py no-lost-camera"}, ""},
    {"V-3.2-fault-controller-null", "handles telemetry.fault true with controller null (a control-path fault with the gamepad disabled)",
     "SPEC §3.2", Tier::must, {"vehicle/3.2/4"}, {"broken_client.py fault-needs-controller"}, ""},
    {"V-2-large-frames", "reads control frames up to the 16 384-byte limit (a large client_user_data)", "SPEC §2, seed 000 (Message framing)",
     Tier::must, {"vehicle/3.2/4"}, {"broken_client.py small-limit"}, ""},
    {"V-3.3-echo-latest", "keeps echoing the latest pair", "SPEC §3.3, §5, seed 001 (Response message)", Tier::must, {"vehicle/3.3/1"},
     {"vehicle_client --misbehave-stop-echo"}, ""},
    {"V-3.3-echo-latest-long", "keeps echoing the latest pair on a long connection (10 s and more)", "SPEC §3.3, §5, seed 000 (Keep the socket open and respond continuously)",
     Tier::must, {"vehicle/3.3/1"}, {"broken_client.py tires"}, ""},
    {"V-3.3-echo-exact", "echoes the pair unchanged", "SPEC §3.3, seed 001 (Response message)", Tier::must, {"vehicle/3.3/1"},
     {"vehicle_client --misbehave-corrupt-mac"}, ""},
    {"V-3.3-echo-at-once", "echoes each control message at once, not on its own schedule", "seed 000 (Send responses), SPEC §5", Tier::should,
     {"vehicle/3.3/2"}, {"vehicle_client --misbehave-delay-responses-ms 50", "broken_client.py timer-echo"}, ""},
    {"V-3.3-tcp-nodelay", "no Nagle delay: TCP no-delay, or one write per frame", "seed 000 (Practical connection rules: \"Use TCP no-delay\")",
     Tier::should, {"vehicle/3.3/2"}, {"broken_client.py split-write"}, ""},
    {"V-3.3-user-data-schema", "vehicle_user_data has user_data, and pos is null or numeric lat/lon, in every response of the run",
     "SPEC §3.3, seed 001 (respond message schema)", Tier::must, {"vehicle/3.3/3"},
     {"broken_client.py bad-pos", "broken_client.py once-bad-pos"}, ""},
    {"V-3.3-user-data-object", "user_data is an object (any JSON value is accepted)", "seed 001 (respond message schema), SPEC §3.3 Decision",
     Tier::should, {"vehicle/3.3/3"}, {"broken_client.py scalar-user-data"}, ""},
    {"V-3.3-no-early-echo", "echoes no pair before the first control message", "seed 000 (Send responses)", Tier::should, {"vehicle/3.3/4"},
     {"broken_client.py early-echo"}, ""},
    {"V-10-command-timeout", "enforces its own command timeout: safe state within 1 s of the last control message",
     "SPEC §10, §8, seed 000 (safety)", Tier::should, {"vehicle/10/1"},
     {"broken_client.py no-watchdog", "vehicle_client --watchdog-ms 1500"}, ""},
    {"V-10-actuator-limits", "enforces actuator limits: throttle and brake 0..1, steer -1..1, whatever the command",
     "SPEC §10, seed 000 (safety)", Tier::should, {"vehicle/10/2"}, {"broken_client.py no-limits"}, ""},
    {"V-10-interlocks", "enforces drive-state interlocks and emergency stop", "SPEC §10, seed 000 (safety)", Tier::should,
     {"vehicle/10/3"}, {"broken_client.py no-interlock"}, ""},
    {"V-10-fault-safe-state", "maps telemetry.fault to a vehicle-specific safe state", "SPEC §10, seed 000 (Handle faults safely)",
     Tier::should, {"vehicle/10/4"}, {"broken_client.py ignore-fault"}, ""},
};

}  // namespace

const std::vector<Requirement>& vehicle_requirements() { return vehicle_requirement_table; }

}  // namespace ocp::conformance
