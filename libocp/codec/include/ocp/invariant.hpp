#pragma once
// Invariants: what must hold at every step, whatever the peer, the link or the timeline does,
// stated where it is kept (after TigerBeetle's assertions). A broken invariant is our bug, never
// the peer's: it stops the process at once with the condition, the place and why it must hold.
//
// They are checked in the sanitizer and fuzz builds (OCP_INVARIANTS, set by the build when
// OCP_SANITIZE or OCP_FUZZ is on), where every test, the fuzzers and the stress runs exercise
// them, and compiled out of release builds, which the benchmarks measure. The condition is
// still parsed in release builds, so an invariant cannot rot there unnoticed.
namespace ocp {

[[noreturn]] void invariant_failed(const char* condition, const char* why, const char* file, int line);

}  // namespace ocp

#if defined(OCP_INVARIANTS)
#define OCP_INVARIANT(condition, why) \
  ((condition) ? static_cast<void>(0) : ::ocp::invariant_failed(#condition, why, __FILE__, __LINE__))
#else
#define OCP_INVARIANT(condition, why) static_cast<void>(sizeof((condition) ? 1 : 0))
#endif
