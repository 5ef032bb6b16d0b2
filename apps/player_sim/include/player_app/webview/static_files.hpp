#pragma once
// Static files of the web view (docs/webview.md): maps a request target to a file inside the
// root folder, refusing anything that could escape it, and names its content type.
// Pure functions (plus file-system look-ups), so the rules are unit-tested without sockets.
#include <filesystem>
#include <string>
#include <string_view>

namespace ocp::webview {

enum class FileLookup { found, not_found, refused, bad_request };

struct ResolvedFile {
  FileLookup outcome = FileLookup::not_found;
  std::filesystem::path path;   // set when found
  std::string reason;           // why refused / bad request, for the log and the reply body
};

// `target` is the raw HTTP request target ("/dashboard/?x=1"). The query and fragment are
// ignored, %XX escapes decoded; "..", ".", backslashes, NUL and malformed escapes are refused
// before the file system is touched, and the final path (symlinks resolved) must still lie
// inside `root`. A folder serves its index.html.
ResolvedFile resolve_static_file(const std::filesystem::path& root, std::string_view target);

// "text/html; charset=utf-8", "text/javascript; charset=utf-8", …; unknown extensions are
// application/octet-stream (the server also sends nosniff, so a browser never guesses).
std::string_view content_type_for(const std::filesystem::path& path);

}  // namespace ocp::webview
