#pragma once
// Escaping for the report formats (private to the library).
#include <cstdio>
#include <string>
#include <string_view>

namespace ocp::conformance::detail {

inline std::string json_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 8);
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          out += buffer;
        } else {
          out += c;
        }
    }
  }
  return out;
}

// HTML and XML text/attribute content. Control bytes (raw wire garbage) become U+FFFD-free
// '?' so an XML parser never rejects the file.
inline std::string markup_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 8);
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') {
          out += '?';
        } else {
          out += c;
        }
    }
  }
  return out;
}

// Payloads in reports are cut at `max` bytes (a drained frame may be 16 KiB+ of filler).
inline std::string clip(std::string_view text, std::size_t max = 2048) {
  if (text.size() <= max) return std::string(text);
  return std::string(text.substr(0, max)) + "… (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace ocp::conformance::detail
