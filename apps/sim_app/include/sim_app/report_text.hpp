#pragma once
// Text for the reports the tools write (JSON, HTML, JUnit XML): escaping, and wire bytes made
// safe to show. Shared by ocp_conformance, ocp_scenario and ocp_bench.
#include <cstdio>
#include <string>
#include <string_view>

namespace ocp::report {

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

// Wire bytes are not always UTF-8 (a garbage client): invalid sequences become '?', so the
// JSON and HTML reports stay valid UTF-8.
inline std::string utf8_safe(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool valid = n > 0 && i + n <= text.size();
    for (std::size_t k = 1; valid && k < n; ++k) valid = (static_cast<unsigned char>(text[i + k]) >> 6) == 0x2;
    if (valid) {
      out.append(text.substr(i, n));
      i += n;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

// Payloads in reports are cut at `max` bytes (a drained frame may be 16 KiB+ of filler).
inline std::string clip(std::string_view text, std::size_t max = 2048) {
  if (text.size() <= max) return utf8_safe(text);
  std::string out = utf8_safe(text.substr(0, max));
  out += "… (";
  out += std::to_string(text.size());
  out += " bytes)";
  return out;
}

}  // namespace ocp::report
