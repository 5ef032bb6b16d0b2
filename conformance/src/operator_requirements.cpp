// The operator client's requirements on the Player's :4001 API (issue #26): every rule of
// SPEC §2, §4, §5, §7 and the seeds that a third-party operator client can break, one row per
// broken behaviour. Tiers per SPEC §2's Decision, as on the vehicle side.
#include "conformance/requirements.hpp"

namespace ocp::conformance {
namespace {

const std::vector<Requirement> operator_requirement_table{
    {"O-2-valid-json", "every frame is a length-prefixed JSON object (malformed JSON closes the connection)", "SPEC §2, §4.2",
     Tier::must, {"operator/2/1"}, {"broken_client.py op-malformed"}, ""},
    {"O-2-max-16KiB", "no frame above 16 KiB, in any case of the run", "SPEC §2, §4.2", Tier::must, {"operator/2/1"},
     {"broken_client.py op-oversized", "broken_client.py op-once-oversized"}, ""},
    {"O-2-read-timeout", "keeps the connection alive (a keep-alive {}) while the Player is silent: the 2 s read timeout never fires",
     "SPEC §2, §4.2 Decision", Tier::must, {"operator/2/2"}, {"broken_client.py op-no-keepalive"}, ""},
    {"O-2-split-frames", "reads a VehicleOcpShared frame however TCP splits it", "SPEC §2, §4.2", Tier::must, {"operator/2/3"},
     {"broken_client.py op-naive-recv"}, ""},
    {"O-2-coalesced-frames", "reads several VehicleOcpShared frames coalesced in one write", "SPEC §2, §4.2", Tier::must, {"operator/2/4"},
     {"broken_client.py op-naive-recv"}, ""},
    {"O-2-oversized-inbound", "skips an inbound frame above 16 KiB (the product never sends one)", "SPEC §2 Decisions", Tier::should,
     {"operator/2/5"}, {"broken_client.py op-reject-oversized"}, ""},
    {"O-2-unknown-fields", "ignores unknown extra fields", "SPEC §2", Tier::must, {"operator/4.1/1"}, {"broken_client.py op-strict-schema"}, ""},
    {"O-4.1-vehicle-data-null", "handles vehicle_data null", "SPEC §4.1", Tier::must, {"operator/4.1/1"},
     {"broken_client.py op-need-vehicle-data"}, ""},
    {"O-4.1-missing-cameras", "handles a missing_cameras list (a camera lost)", "SPEC §4.1", Tier::must, {"operator/4.1/1"},
     {"broken_client.py op-no-lost-camera"}, ""},
    {"O-4.1-latency-null", "handles message_latency_roundtrip null (not measured yet)", "SPEC §4.1", Tier::must, {"operator/4.1/1"},
     {"broken_client.py op-need-latency"}, ""},
    {"O-4.1-last-input-null", "handles last_input null", "SPEC §4.1", Tier::must, {"operator/4.1/1"}, {"broken_client.py op-need-last-input"}, ""},
    {"O-4.1-remote-input-null", "handles last_remote_input null for a control vehicle", "SPEC §4.1", Tier::must, {"operator/4.1/1"},
     {"broken_client.py op-need-remote-input"}, ""},
    {"O-2-utf8-length", "reads the length prefix as UTF-8 bytes, not characters (non-ASCII text)", "SPEC §2", Tier::must,
     {"operator/4.1/1"}, {"broken_client.py op-char-length"}, ""},
    {"O-2-large-frames", "reads VehicleOcpShared frames up to the 16 384-byte limit (a large vehicle_data)", "SPEC §2, §4.1", Tier::must,
     {"operator/4.1/1"}, {"broken_client.py op-small-limit"}, ""},
    {"O-4.2-return-latest", "returns each vehicle's latest pair, not an old one", "SPEC §4.1, §4.2", Tier::must, {"operator/4.2/1"},
     {"broken_client.py op-stale"}, ""},
    {"O-4.2-return-exact", "returns the pair unchanged", "SPEC §4.1, §4.2", Tier::must, {"operator/4.2/1"}, {"broken_client.py op-corrupt"}, ""},
    {"O-2-unchanged-pair", "keeps sending while the pair stays unchanged for over 2 s (a stalled video, a vehicle gone)",
     "SPEC §2, §4.1, §4.2", Tier::must, {"operator/2/6"}, {"broken_client.py op-answer-on-change"}, ""},
    {"O-4.2-return-latest-long", "returns the latest pair on a long connection (10 s and more)", "SPEC §4.1, §4.2", Tier::must,
     {"operator/4.2/1"}, {"broken_client.py op-tires"}, ""},
    {"O-4.2-u64-exact", "returned pairs above 2^53 survive byte-exact, never through a double", "SPEC §2", Tier::must, {"operator/4.2/2"},
     {"broken_client.py op-double"}, ""},
    {"O-4.2-reconnect-close", "reconnects after the Player closes the connection", "SPEC §4.2, seed 000", Tier::must, {"operator/4.2/3"},
     {"broken_client.py op-no-reconnect"}, ""},
    {"O-4.2-reconnect-restart", "reconnects after a Player restart", "SPEC §4.2, seed 000", Tier::must, {"operator/4.2/4"},
     {"broken_client.py op-no-reconnect"}, ""},
    {"O-4.2-no-stale-pair", "after a reconnect returns only pairs published on the new connection (new Streamer keys)", "SPEC §4.2, §5",
     Tier::must, {"operator/4.2/3", "operator/4.2/4"}, {"broken_client.py op-sticky"}, ""},
    {"O-4.2-user-data", "user_data is keyed by a linked vehicle's name and reaches it unchanged", "SPEC §4.2, seed 004", Tier::must,
     {"operator/4.2/5"}, {"broken_client.py op-wrong-name"}, ""},
    {"O-4.2-reconnect-not-at-once", "reconnects after a short delay, not in a tight loop (≥ 20 ms)",
     "seed 000 (Practical connection rules), SPEC §4.2", Tier::should, {"operator/4.2/7"}, {"broken_client.py op-reconnect-at-once"}, ""},
    {"O-4.2-reconnect-within-1s", "reconnects within 1 s", "seed 000 (Practical connection rules), SPEC §4.2", Tier::should,
     {"operator/4.2/7"}, {"broken_client.py op-reconnect-slowly"}, ""},
    {"O-4.3-one-connection", "one connection at a time: a single client-data source", "SPEC §4.2, §4.3, seed 002", Tier::must,
     {"operator/4.3/1"}, {"broken_client.py op-second-connection"}, ""},
    {"O-4.3-every-vehicle", "the locked source returns the pair of every control vehicle", "SPEC §4.3, §4.1, seed 003", Tier::must,
     {"operator/4.3/2"}, {"broken_client.py op-active-only"}, ""},
    {"O-4.1-vehicle-order", "maps vehicles by name, whatever order vehicle_feedback lists them in (a hashmap)", "SPEC §4.1, seed 004",
     Tier::must, {"operator/4.3/2"}, {"broken_client.py op-by-position"}, ""},
    {"O-4.4-disable-gamepad", "ocp_disable_gamepad: true in every entry while the gamepad is to stay off", "SPEC §4.4, §3.2, seed 003",
     Tier::must, {"operator/4.4/1"}, {"broken_client.py op-disable-once"}, ""},
    {"O-7-active-several", "with several vehicles, active_vehicle is set", "SPEC §7, seed 004", Tier::must, {"operator/7/1"},
     {"broken_client.py op-no-active"}, ""},
    {"O-7-active-not-monitor", "active_vehicle never names a monitor link", "SPEC §7, seed 004", Tier::must, {"operator/7/1"},
     {"broken_client.py op-monitor-active"}, ""},
    {"O-7-active-one", "with one vehicle, active_vehicle is omitted or names it", "SPEC §7", Tier::must, {"operator/7/2"},
     {"broken_client.py op-fixed-active"}, ""},
};

}  // namespace

const std::vector<Requirement>& operator_requirements() { return operator_requirement_table; }

}  // namespace ocp::conformance
