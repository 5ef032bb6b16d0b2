#pragma once
// Invariants: what must hold at every step, whatever the peer, the link or the timeline does,
// stated where it is kept, at the end of each handler that changes state (after TigerBeetle's
// assertions). A broken invariant is our bug, never the peer's: it stops the process at once
// with the condition, the place and why it must hold.
//
// Two strengths:
//  * OCP_INVARIANT(condition, why): cheap (a few comparisons on values at hand). Always on,
//    release builds included, inside a measured budget: world_bench OneHour within 3 % of the
//    build without them (docs/benchmarks.md, "Invariants").
//  * OCP_INVARIANT_DEEP(condition, why): costly (a walk over a container, a recount). Checked
//    in the sanitizer and fuzz builds (OCP_INVARIANTS, set by the build when OCP_SANITIZE or
//    OCP_FUZZ is on), where every test, the fuzzers and the stress runs exercise them; in
//    release builds the condition is still parsed, so it cannot rot unnoticed, but not run.
//
// Reach: in OCP_INVARIANTS builds, with OCP_INVARIANTS_REACHED=FILE in the environment, every
// invariant appends "file:line" to FILE the first time a process checks it, so a test run
// shows which invariants its tests reach (scripts/invariants_reached).
namespace ocp {

[[noreturn]] void invariant_failed(const char* condition, const char* why, const char* file, int line);
// Records that the invariant at file:line was checked (OCP_INVARIANTS builds); returns true.
bool invariant_reached(const char* file, int line);

}  // namespace ocp

#if defined(OCP_INVARIANTS)
#define OCP_INVARIANT_REACH_()                                                            \
  [] {                                                                                    \
    static const bool reached = ::ocp::invariant_reached(__FILE__, __LINE__);             \
    static_cast<void>(reached);                                                           \
  }()
#define OCP_INVARIANT(condition, why)                                                     \
  (OCP_INVARIANT_REACH_(), __builtin_expect(static_cast<bool>(condition), 1)              \
                               ? static_cast<void>(0)                                      \
                               : ::ocp::invariant_failed(#condition, why, __FILE__, __LINE__))
#define OCP_INVARIANT_DEEP(condition, why) OCP_INVARIANT(condition, why)
#else
#define OCP_INVARIANT(condition, why)                                                     \
  (__builtin_expect(static_cast<bool>(condition), 1)                                      \
       ? static_cast<void>(0)                                                              \
       : ::ocp::invariant_failed(#condition, why, __FILE__, __LINE__))
#define OCP_INVARIANT_DEEP(condition, why) static_cast<void>(sizeof((condition) ? 1 : 0))
#endif
