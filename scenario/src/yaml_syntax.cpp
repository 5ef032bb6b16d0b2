// Syntax errors explained (yaml_syntax.hpp).
#include "yaml_syntax.hpp"

#include <sstream>

#include "ocp/bounded_file.hpp"
#include <string_view>

namespace ocp::scenario {
namespace {

struct Explanation {
  std::string_view yaml_cpp;   // yaml-cpp's message (ErrorMsg in yaml-cpp/exceptions.h)
  std::string_view expected;   // what YAML expected there
};

// The messages indentation mistakes and unclosed brackets produce.
constexpr Explanation explanations[] = {
    {"end of sequence not found",
     "YAML expected another list item ('- …') at the list's indentation, or a line indented less to end the list: "
     "check this line's indentation"},
    {"end of map not found",
     "YAML expected another 'key: value' at the mapping's indentation, or a line indented less to end the mapping: "
     "check this line's indentation"},
    {"illegal map value",
     "YAML did not expect 'key: value' here: a line indented deeper than the key above it, or a value that holds "
     "': ' (quote it): check this line's indentation"},
    {"end of sequence flow not found", "YAML expected ']' to close a '[' list"},
    {"end of map flow not found", "YAML expected '}' to close a '{' mapping"},
    {"block sequence entries are not allowed in this context",
     "YAML did not expect a list item ('- …') here: indent it under a key, or put it at the list's indentation"},
};

std::string line_text(const std::string& text, int line) {
  std::istringstream in(text);
  std::string current;
  for (int number = 1; std::getline(in, current); ++number) {
    if (number == line) return current;
  }
  return {};
}

}  // namespace

std::string explain_yaml_syntax_error(const std::string& message, const std::string& text, int line) {
  std::string reason = message;
  for (const Explanation& explanation : explanations) {
    if (message == explanation.yaml_cpp) {
      reason = std::string(explanation.expected) + " (YAML: " + message + ")";
      break;
    }
  }
  const std::string quoted = line_text(text, line);
  // An excerpt: the line may be 200 KB of brackets, or a file that is no scenario at all.
  if (!quoted.empty()) reason += "; line " + std::to_string(line) + " is \"" + escaped_excerpt(quoted) + "\"";
  return reason;
}

}  // namespace ocp::scenario
