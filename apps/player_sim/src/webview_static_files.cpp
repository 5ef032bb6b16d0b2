// Static file resolution for the web view: path-traversal protection and content types.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <system_error>
#include <utility>

#include "player_app/webview/static_files.hpp"

namespace ocp::webview {
namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// Percent-decodes; false on a malformed escape.
bool percent_decode(std::string_view text, std::string& out) {
  out.clear();
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      out += text[i];
      continue;
    }
    if (i + 2 >= text.size()) return false;
    const int high = hex_value(text[i + 1]);
    const int low = hex_value(text[i + 2]);
    if (high < 0 || low < 0) return false;
    out += static_cast<char>(high * 16 + low);
    i += 2;
  }
  return true;
}

ResolvedFile refused(std::string reason) { return {FileLookup::refused, {}, std::move(reason)}; }
ResolvedFile bad_request(std::string reason) { return {FileLookup::bad_request, {}, std::move(reason)}; }

// True when `path` is `root` or lies below it (both already canonical).
bool is_inside(const std::filesystem::path& root, const std::filesystem::path& path) {
  const auto [root_end, _] = std::mismatch(root.begin(), root.end(), path.begin(), path.end());
  return root_end == root.end();
}

}  // namespace

ResolvedFile resolve_static_file(const std::filesystem::path& root, std::string_view target) {
  const std::size_t end = target.find_first_of("?#");
  const std::string_view raw_path = target.substr(0, end);
  if (raw_path.empty() || raw_path.front() != '/') return bad_request("request target must start with '/'");
  std::string decoded;
  if (!percent_decode(raw_path, decoded)) return bad_request("malformed %-escape in the path");
  if (decoded.find('\0') != std::string::npos) return refused("NUL byte in the path");
  if (decoded.find('\\') != std::string::npos) return refused("backslash in the path");

  std::filesystem::path relative;
  std::size_t start = 1;
  while (start <= decoded.size()) {
    std::size_t slash = decoded.find('/', start);
    if (slash == std::string::npos) slash = decoded.size();
    const std::string_view segment(decoded.data() + start, slash - start);
    if (segment == ".." || segment == ".") return refused(fmt::format("'{}' segment in the path", segment));
    if (!segment.empty()) relative /= std::string(segment);
    start = slash + 1;
  }

  std::error_code error;
  const std::filesystem::path canonical_root = std::filesystem::canonical(root, error);
  if (error) return {FileLookup::not_found, {}, fmt::format("web view root {}: {}", root.string(), error.message())};
  std::filesystem::path candidate = canonical_root / relative;
  if (std::filesystem::is_directory(candidate, error)) candidate /= "index.html";
  if (!std::filesystem::is_regular_file(candidate, error)) return {FileLookup::not_found, {}, "no such file"};
  // A symlink inside the root may point anywhere: judge where the file really is.
  const std::filesystem::path real = std::filesystem::canonical(candidate, error);
  if (error) return {FileLookup::not_found, {}, "no such file"};
  if (!is_inside(canonical_root, real)) return refused("the file lies outside the web view root");
  return {FileLookup::found, real, {}};
}

std::string_view content_type_for(const std::filesystem::path& path) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 14> types{{
      {".html", "text/html; charset=utf-8"},
      {".htm", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".map", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".jpg", "image/jpeg"},
      {".jpeg", "image/jpeg"},
      {".ico", "image/x-icon"},
      {".txt", "text/plain; charset=utf-8"},
      {".woff2", "font/woff2"},
  }};
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const auto& [known, type] : types) {
    if (extension == known) return type;
  }
  return "application/octet-stream";
}

}  // namespace ocp::webview
