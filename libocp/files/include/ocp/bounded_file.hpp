#pragma once
// Every file a tool reads (scenarios, profiles, traces and link recordings, key files, gamepad
// scripts, baselines, summaries) goes through read_bounded_file: opened without blocking
// (O_NONBLOCK, so a FIFO cannot hang the tool), checked with fstat to be a regular file (not a
// FIFO, a device such as /dev/zero, a socket or a folder), and read only up to the cap of its
// kind. Each refusal is an Error whose detail names the file, the kind and the reason:
//   "/dev/zero: a scenario file must be a regular file, not a character device"
//   "big.yaml: 104857600 bytes; a scenario file may be at most 1048576 bytes (raise with --max-file-mb)"
// Error excerpts of a file's content go through escaped_excerpt: short, one line, no bytes
// that would reach a terminal raw.
#include <cstdint>
#include <string>
#include <string_view>

#include "ocp/error.hpp"
#include "ocp/escaped_excerpt.hpp"

namespace ocp {

struct FileKind {
  const char* name;              // "scenario file", "com key file": for messages
  std::uint64_t max_bytes;       // the stated default cap
  const char* raise_with = "";   // the option that raises it ("--max-file-mb"), or "" when fixed
};

// The caps (docs/usage.md, "Input files").
namespace file_kinds {
inline constexpr FileKind scenario{"scenario file", 1u << 20, "--max-file-mb"};
inline constexpr FileKind profile{"campaign profile", 1u << 20, "--max-file-mb"};
inline constexpr FileKind delivery_trace{"delivery trace", 64u << 20, "--max-file-mb"};
inline constexpr FileKind link_recording{"link recording", 64u << 20, "--max-file-mb"};
inline constexpr FileKind trace_jsonl{"trace", 1024u << 20, "--max-file-mb"};
inline constexpr FileKind summary{"campaign summary", 1024u << 20, "--max-file-mb"};
inline constexpr FileKind key{"com key file", 4096};
inline constexpr FileKind gamepad_script{"gamepad script", 1u << 20};
inline constexpr FileKind baseline{"conformance baseline", 16u << 20};
inline constexpr FileKind client_script{"client file", 16u << 20};
}  // namespace file_kinds

// A tool's --max-file-mb: every cap that names a flag becomes at least `bytes` (0: the defaults).
void raise_file_caps(std::uint64_t bytes);
std::uint64_t file_cap(const FileKind& kind);

// The file's whole content, or why it cannot be had (the system's reason included).
Result<std::string> read_bounded_file(const std::string& path, const FileKind& kind);

}  // namespace ocp
