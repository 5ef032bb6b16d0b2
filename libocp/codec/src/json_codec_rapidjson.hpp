#pragma once
// The one place RapidJSON is configured for the codec. Include this, never <rapidjson/...>
// directly, so every translation unit sees the same settings.
//
// RAPIDJSON_ASSERT guards RapidJSON's own invariants (API misuse), never input: the Reader
// reports bad input as parse errors. We still refuse to let a violated invariant turn into
// silent undefined behaviour in a release build: it aborts with a message, and the fuzz
// targets prove no input reaches one.
#include <cstdio>
#include <cstdlib>

namespace ocp::json_detail {
[[noreturn]] inline void rapidjson_invariant_failed(const char* condition, const char* file,
                                                    int line) {
  std::fprintf(stderr, "RapidJSON invariant violated: %s (%s:%d)\n", condition, file, line);
  std::abort();
}
}  // namespace ocp::json_detail

#define RAPIDJSON_ASSERT(condition)                                                        \
  ((condition) ? static_cast<void>(0)                                                      \
               : ::ocp::json_detail::rapidjson_invariant_failed(#condition, __FILE__, __LINE__))
#define RAPIDJSON_HAS_STDSTRING 1

#include <rapidjson/error/en.h>
#include <rapidjson/reader.h>
