#pragma once
// yaml-cpp's syntax errors in words a scenario author can act on. yaml-cpp says
// "end of map not found" where the author needs "this line is indented wrongly": the reason
// names what YAML expected at that point, and quotes the line it stopped at.
#include <string>

namespace ocp::scenario {

// `message` is yaml-cpp's (ParserException::msg), `line` 1-based in `text`.
std::string explain_yaml_syntax_error(const std::string& message, const std::string& text, int line);

}  // namespace ocp::scenario
