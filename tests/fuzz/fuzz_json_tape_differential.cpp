// libFuzzer target: the hand-written JSON fast path against RapidJSON on every input (see
// tests/support/json_tape_differential.hpp): the same tape or the same error, or it traps.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string_view>

#include "json_tape_differential.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const ocp::testing::TapeDifferential result = ocp::testing::compare_json_tokenizers(input);
  if (!result.difference.empty()) {
    std::fprintf(stderr, "tokenizers disagree: %s\n", result.difference.c_str());
    __builtin_trap();
  }
  return 0;
}
