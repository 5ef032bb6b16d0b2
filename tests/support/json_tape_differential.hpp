#pragma once
// The fast JSON path stays honest: the hand-written tokenizer (json_codec_tape.cpp's fast path)
// and RapidJSON (tokenize_with_rapidjson) are run on the same bytes and must agree — the same
// tape, or the same error. Shared by the unit test over the checked-in corpora and the
// fuzz_json_tape_differential target. Needs libocp/codec/src on the include path.
//
// What is compared, and the one normalisation:
//   * Fast path alone: it may decline any document (RapidJSON then parses it), but a document
//     it takes must be one RapidJSON takes too, with an identical tape.
//   * tokenize (fast path + fallback) against tokenize_with_rapidjson, with and without the
//     object-root rule: both succeed with identical tapes, or both fail with the same code and
//     the same detail.
//   * Tapes: every token's kind, source offset, matching-end index, text position and length,
//     and its decoded text. Not the work buffer `Tape::text` as a whole: RapidJSON parses in
//     situ and writes a terminator after each string it decodes, the fast path writes nothing;
//     no reader ever looks outside a token's text.
//   * The known RapidJSON 1.1 defects are handled inside libocp, not here, so the comparison is
//     strict: the lone low surrogate it accepts is rejected by the tape handler (both sides then
//     report malformed_json), and the UB of its first stack growth never happens because the
//     codec parses in situ.
#include <sstream>
#include <string>
#include <string_view>

#include "json_codec_tape.hpp"
#include "ocp/error.hpp"

namespace ocp::testing {

inline const char* token_kind_name(json_detail::TokenKind kind) {
  using json_detail::TokenKind;
  switch (kind) {
    case TokenKind::null_value: return "null";
    case TokenKind::true_value: return "true";
    case TokenKind::false_value: return "false";
    case TokenKind::number: return "number";
    case TokenKind::string: return "string";
    case TokenKind::key: return "key";
    case TokenKind::object_begin: return "{";
    case TokenKind::object_end: return "}";
    case TokenKind::array_begin: return "[";
    case TokenKind::array_end: return "]";
  }
  return "?";
}

// The first difference between two tapes of the same source, or "" when they are the same.
inline std::string tape_difference(const json_detail::Tape& left, const json_detail::Tape& right) {
  std::ostringstream out;
  if (left.source != right.source) return "different sources";
  if (left.tokens.size() != right.tokens.size()) {
    out << "token count " << left.tokens.size() << " vs " << right.tokens.size();
    return out.str();
  }
  for (std::size_t index = 0; index < left.tokens.size(); ++index) {
    const json_detail::Token& a = left.tokens[index];
    const json_detail::Token& b = right.tokens[index];
    const char* field = nullptr;
    if (a.kind != b.kind) field = "kind";
    else if (a.source_offset != b.source_offset) field = "source offset";
    else if (a.end_index != b.end_index) field = "end index";
    else if (a.text_begin != b.text_begin) field = "text begin";
    else if (a.text_length != b.text_length) field = "text length";
    else if (left.text_of(a) != right.text_of(b)) field = "text";
    if (field != nullptr) {
      out << "token " << index << " (" << token_kind_name(a.kind) << " at " << a.source_offset << " vs "
          << token_kind_name(b.kind) << " at " << b.source_offset << "): " << field << " differs";
      return out.str();
    }
  }
  return "";
}

// The first difference between two tokenizations (status, then tape), or "".
inline std::string outcome_difference(const Status& left_status, const json_detail::Tape& left,
                                      const Status& right_status, const json_detail::Tape& right) {
  if (left_status.ok() != right_status.ok()) {
    return std::string(left_status.ok() ? "tokenizer accepts" : "tokenizer rejects (" + left_status.error().message() + ")") +
           ", RapidJSON " +
           (right_status.ok() ? std::string("accepts") : "rejects (" + right_status.error().message() + ")");
  }
  if (!left_status.ok()) {
    if (left_status.error().code != right_status.error().code ||
        left_status.error().detail != right_status.error().detail) {
      return "different errors: " + left_status.error().message() + " vs " + right_status.error().message();
    }
    return "";
  }
  return tape_difference(left, right);
}

struct TapeDifferential {
  bool fast_path_took = false;  // the hand-written tokenizer took the document itself
  std::string difference;       // "" when both sides agree
};

// Runs every comparison above on `json`.
inline TapeDifferential compare_json_tokenizers(std::string_view json) {
  TapeDifferential result;
  json_detail::Tape fast;
  json_detail::Tape reference;
  result.fast_path_took = json_detail::tokenize_fast_path(json, fast);
  if (result.fast_path_took) {
    const Status status = json_detail::tokenize_with_rapidjson(json, reference, /*require_object=*/false);
    result.difference = outcome_difference(Ok{}, fast, status, reference);
    if (!result.difference.empty()) return result;
  }
  for (const bool require_object : {true, false}) {
    json_detail::Tape combined;
    const Status combined_status = json_detail::tokenize(json, combined, require_object);
    const Status reference_status = json_detail::tokenize_with_rapidjson(json, reference, require_object);
    result.difference = outcome_difference(combined_status, combined, reference_status, reference);
    if (!result.difference.empty()) {
      result.difference = std::string(require_object ? "object root: " : "any root: ") + result.difference;
      return result;
    }
  }
  return result;
}

}  // namespace ocp::testing
