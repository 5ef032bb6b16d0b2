#pragma once
// Mutants: deliberately broken core behaviours, one switched on per test, that the campaign
// oracle (campaign/src/oracle*.cpp) must catch (issue #21: "every invariant can fail").
//
// Compiled in only with -DOCP_MUTANTS. No library or executable of the project sets it: the
// mutant test target (tests/campaign_mutants) compiles its own copies of the few core sources
// that carry a mutant site, with the define, and defines active_mutant(). Release binaries and
// every other test contain none of this.
namespace ocp {

enum class Mutant {
  none,
  fault_raised_one_tick_late,       // NoControlMessage raised one control period late
  default_controller_not_applied,   // control-path faults let the operator's controller through
  stale_pair_accepted,              // an older returned pair replaces the newest valid one
  delivered_counted_twice,          // a link counts each delivery twice
  // The Player's :4001 port (the oracle's operator checks, oracle_operator.cpp):
  operator_bad_frame_kept,          // a broken client frame is ignored, the connection kept
  keep_alive_locks_source,          // a keep-alive `{}` takes the tcp source lock (SPEC §4.2)
  feedback_fault_lists_stale,       // VehicleOcpShared's fault lists are never refreshed
  locked_client_pair_kept,          // the locked tcp client left, its last pair still returned (§4.3)
};

#ifdef OCP_MUTANTS
Mutant& active_mutant();   // the one switched on (tests/campaign_mutants defines it)
inline bool mutant_active(Mutant mutant) { return active_mutant() == mutant; }
#endif

}  // namespace ocp

// OCP_MUTATED(name): true when the mutant `name` is switched on (never outside the mutant test
// target). An invariant whose breach is what a mutant plants says `|| OCP_MUTATED(name)`: the
// mutant exists to prove the campaign oracle catches it from outside, which an invariant that
// stopped the process first would hide.
#ifdef OCP_MUTANTS
#define OCP_MUTATED(name) ::ocp::mutant_active(::ocp::Mutant::name)
#else
#define OCP_MUTATED(name) false
#endif
