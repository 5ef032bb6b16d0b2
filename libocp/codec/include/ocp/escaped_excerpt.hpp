#pragma once
// Short excerpts of untrusted text for error messages (a file's line, a field's value): pure,
// so the parsers of the sans-IO layers quote their input the same way the file reader does.
#include <cstddef>
#include <string>
#include <string_view>

namespace ocp {

// At most `max_chars` (40) of `text`, on one line: printable ASCII as is, \n \r \t and \\ escaped,
// every other byte as \xNN; "…" when cut.
std::string escaped_excerpt(std::string_view text, std::size_t max_chars = 40);

}  // namespace ocp
