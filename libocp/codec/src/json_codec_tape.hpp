#pragma once
// Tokenizer of the JSON codec. Plain documents (all ASCII, no escapes, no exponents: what
// our encoders write) take a small hand-written scanner; everything else, errors included,
// goes to RapidJSON's SAX Reader, which checks the grammar and UTF-8 and hands us events. Both
// record the same flat "tape" (no DOM, no per-value allocation) that the typed
// decoders then walk by index (parsing in situ on a reused copy, so nothing is allocated in
// the steady state). Each token remembers where it ends in the source, so any value
// (user data) can be cut out of the input byte-exact. Numbers are kept as their source text so
// u64/u32 fields never pass through a double.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/error.hpp"

namespace ocp::json_detail {

enum class TokenKind : std::uint8_t {
  null_value,
  true_value,
  false_value,
  number,
  string,
  key,
  object_begin,
  object_end,
  array_begin,
  array_end,
};

struct Token {
  TokenKind kind = TokenKind::null_value;
  std::uint32_t text_begin = 0;   // number/string/key: offset of its decoded text in Tape::text
  std::uint32_t text_length = 0;
  // Where the token sits in the source: its first byte, except for object_end/array_end,
  // where it is the offset just past the closing bracket.
  std::uint32_t source_offset = 0;
  std::uint32_t end_index = 0;    // object_begin/array_begin: index of the matching end token
};

struct Tape {
  std::string_view source;
  std::vector<Token> tokens;
  // RapidJSON's work copy of the source, parsed in place: decoded strings, keys and number
  // texts live inside it (a decoded string is never longer than its source). Left empty by the
  // fast path, whose texts are the source's own bytes at the same offsets: no copy.
  std::string text;

  std::string_view text_of(const Token& token) const {
    const std::string_view texts = text.empty() ? source : std::string_view(text);
    return texts.substr(token.text_begin, token.text_length);
  }
  // Index of the value after the one starting at `index` (skips whole containers).
  std::size_t next(std::size_t index) const {
    const Token& token = tokens[index];
    if (token.kind == TokenKind::object_begin || token.kind == TokenKind::array_begin) {
      return token.end_index + 1;
    }
    return index + 1;
  }
  // The exact source bytes of the value starting at token `index`.
  std::string_view source_of(std::size_t index) const;
};

// Tokenizes `json` into `tape` (storage reused). Errors: malformed_json (syntax or UTF-8),
// too_deep (nesting beyond max_json_depth), not_an_object (valid JSON, top level not an object,
// only when `require_object`).
[[nodiscard]] Status tokenize(std::string_view json, Tape& tape, bool require_object = true);

// The same with RapidJSON alone, skipping tokenize's fast path for plain documents (tests
// compare the two; tokenize falls back to it for anything the fast path does not take).
[[nodiscard]] Status tokenize_with_rapidjson(std::string_view json, Tape& tape,
                                             bool require_object = true);

// The hand-written fast path alone: true when it took the document (recording its tape, which
// must equal RapidJSON's), false when it declined it (tape left cleared). tokenize is this,
// then tokenize_with_rapidjson on a decline. Exposed for the differential tests and fuzz target.
[[nodiscard]] bool tokenize_fast_path(std::string_view json, Tape& tape);

// One tape per thread, reused across decodes so the steady state allocates nothing.
Tape& thread_tape();

}  // namespace ocp::json_detail
