#include "ocp/escaped_excerpt.hpp"

namespace ocp {

std::string escaped_excerpt(std::string_view text, std::size_t max_chars) {
  static constexpr char hex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t at = 0; at < text.size(); ++at) {
    if (out.size() >= max_chars) return out + "…";
    const auto byte = static_cast<unsigned char>(text[at]);
    if (byte == '\n') out += "\\n";
    else if (byte == '\r') out += "\\r";
    else if (byte == '\t') out += "\\t";
    else if (byte == '\\') out += "\\\\";
    else if (byte >= 0x20 && byte < 0x7f) out += static_cast<char>(byte);
    else out += std::string("\\x") + hex[byte >> 4] + hex[byte & 15];
  }
  return out;
}

}  // namespace ocp
