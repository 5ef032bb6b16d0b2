#pragma once
// Names that reach a generated script or a printed command line (--out, --partition, --profile
// of `ocp_campaign run` and `slurm`): a control character in one would end the line it is on
// (an `#SBATCH` directive, a comment, a "Replay:" line) and start a command of its own, so it is
// refused (exit 2); every other byte is kept and the value quoted with shell_quoted().
#include <CLI/CLI.hpp>

#include <fmt/format.h>

#include <optional>
#include <string>

namespace ocp::campaign {

// Why `value` cannot be a name in a script ("a newline at byte 4"), or nullopt when it can.
inline std::optional<std::string> script_name_problem(const std::string& value) {
  for (std::size_t at = 0; at < value.size(); ++at) {
    const auto byte = static_cast<unsigned char>(value[at]);
    if (byte < 0x20 || byte == 0x7f) {
      const char* what = byte == '\n' ? "a newline" : byte == '\r' ? "a carriage return" : "a control character";
      return fmt::format("{} (0x{:02x}) at byte {}: names that reach a script may not hold control characters", what,
                         byte, at);
    }
  }
  return std::nullopt;
}

// The CLI11 check of such an option: "--out: a newline (0x0a) at byte 4: …", exit 2.
inline CLI::Validator script_name() {
  return CLI::Validator([](std::string& text) { return script_name_problem(text).value_or(""); }, "NAME");
}

// A folder inside a Slurm filename pattern (#SBATCH --output=…): '%' is Slurm's escape, so a
// literal '%' is written "%%"; sbatch's reader of directives takes a backslash as an escape even
// inside quotes, so a literal backslash is written twice. The result is then quoted with shell_quoted().
inline std::string slurm_pattern_literal(const std::string& text) {
  std::string out;
  for (const char c : text) out += c == '%' ? std::string("%%") : c == '\\' ? std::string("\\\\") : std::string(1, c);
  return out;
}

// A value of an #SBATCH directive other than a pattern: only sbatch's backslash escape.
inline std::string sbatch_literal(const std::string& text) {
  std::string out;
  for (const char c : text) out += c == '\\' ? std::string("\\\\") : std::string(1, c);
  return out;
}

}  // namespace ocp::campaign
