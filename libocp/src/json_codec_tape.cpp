#include "json_codec_tape.hpp"

#include <array>
#include <cstring>
#include <limits>

#include "json_codec_rapidjson.hpp"
#include "ocp/json_codec.hpp"

namespace ocp::json_detail {
namespace {

// Bounded in-situ stream over the tape's private copy of the input. In-situ parsing decodes
// strings in place and hands out numbers as pointers into the copy, so RapidJSON never needs
// its internal stack (whose first growth is undefined behaviour in RapidJSON 1.1: it offsets a
// null pointer) and nothing is copied twice. Past the end it reads '\0', which RapidJSON
// treats as end of input; writes always trail the read position.
class InsituStream {
 public:
  using Ch = char;
  InsituStream(char* begin, std::size_t size)
      : begin_(begin), current_(begin), end_(begin + size), write_(begin) {}

  Ch Peek() const { return current_ == end_ ? '\0' : *current_; }
  Ch Take() { return current_ == end_ ? '\0' : *current_++; }
  std::size_t Tell() const { return static_cast<std::size_t>(current_ - begin_); }

  Ch* PutBegin() { return write_ = current_; }
  void Put(Ch c) { *write_++ = c; }
  void Flush() {}
  std::size_t PutEnd(Ch* begin) { return static_cast<std::size_t>(write_ - begin); }

 private:
  char* begin_;
  char* current_;
  char* end_;
  char* write_;
};

class TapeHandler {
 public:
  TapeHandler(Tape& tape, const InsituStream& stream) : tape_(tape), stream_(stream) {}

  // Literals, brackets: RapidJSON has consumed the token from our stream when it calls us.
  bool Null() { return push(TokenKind::null_value, stream_.Tell() - 4); }
  bool Bool(bool value) {
    return value ? push(TokenKind::true_value, stream_.Tell() - 4)
                 : push(TokenKind::false_value, stream_.Tell() - 5);
  }
  // With kParseNumbersAsStringsFlag every number arrives through RawNumber.
  bool Int(int) { return false; }
  bool Uint(unsigned) { return false; }
  bool Int64(std::int64_t) { return false; }
  bool Uint64(std::uint64_t) { return false; }
  bool Double(double) { return false; }
  bool RawNumber(const char* text, rapidjson::SizeType length, bool) {
    return push_text(TokenKind::number, text, length);
  }
  bool String(const char* text, rapidjson::SizeType length, bool) {
    return check_surrogates(text, length) && push_text(TokenKind::string, text, length);
  }
  bool Key(const char* text, rapidjson::SizeType length, bool) {
    return check_surrogates(text, length) && push_text(TokenKind::key, text, length);
  }
  bool StartObject() { return open(TokenKind::object_begin); }
  bool EndObject(rapidjson::SizeType) { return close(TokenKind::object_end); }
  bool StartArray() { return open(TokenKind::array_begin); }
  bool EndArray(rapidjson::SizeType) { return close(TokenKind::array_end); }

  bool too_deep() const { return too_deep_; }
  bool lone_surrogate() const { return lone_surrogate_; }

 private:
  bool push(TokenKind kind, std::size_t source_offset) {
    Token token;
    token.kind = kind;
    token.source_offset = static_cast<std::uint32_t>(source_offset);
    tape_.tokens.push_back(token);
    return true;
  }
  bool push_text(TokenKind kind, const char* text, rapidjson::SizeType length) {
    Token token;
    token.kind = kind;
    token.text_begin = static_cast<std::uint32_t>(text - tape_.text.data());
    token.text_length = length;
    // Strings and numbers are read through a copy of our stream, which still points at
    // their first byte when RapidJSON calls us.
    token.source_offset = static_cast<std::uint32_t>(stream_.Tell());
    tape_.tokens.push_back(token);
    return true;
  }
  // RapidJSON 1.1 rejects a lone high surrogate escape but turns a lone low one ("\udc00")
  // into the bytes ED B0 80, which are not UTF-8. Surrogates only ever encode as ED A0..BF.
  bool check_surrogates(const char* text, rapidjson::SizeType length) {
    const char* end = text + length;
    for (const char* at = text; (at = static_cast<const char*>(std::memchr(
                                     at, '\xED', static_cast<std::size_t>(end - at)))) != nullptr;
         ++at) {
      if (end - at > 1 && static_cast<unsigned char>(at[1]) >= 0xA0) {
        lone_surrogate_ = true;
        return false;
      }
    }
    return true;
  }
  bool open(TokenKind kind) {
    if (depth_ == max_json_depth) {
      too_deep_ = true;
      return false;
    }
    open_indexes_[static_cast<std::size_t>(depth_++)] =
        static_cast<std::uint32_t>(tape_.tokens.size());
    return push(kind, stream_.Tell() - 1);
  }
  bool close(TokenKind kind) {
    // RapidJSON only reports an end matching an open container, so depth_ > 0 here.
    const std::uint32_t begin_index = open_indexes_[static_cast<std::size_t>(--depth_)];
    tape_.tokens[begin_index].end_index = static_cast<std::uint32_t>(tape_.tokens.size());
    return push(kind, stream_.Tell());
  }

  Tape& tape_;
  const InsituStream& stream_;
  int depth_ = 0;
  bool too_deep_ = false;
  bool lone_surrogate_ = false;
  std::array<std::uint32_t, max_json_depth> open_indexes_{};
};

constexpr unsigned parse_flags = rapidjson::kParseInsituFlag |
                                 rapidjson::kParseValidateEncodingFlag |
                                 rapidjson::kParseNumbersAsStringsFlag;

Error malformed(std::string detail) {
  return Error{make_error_code(ProtocolError::malformed_json), std::move(detail)};
}

}  // namespace
}  // namespace ocp::json_detail

// RapidJSON's ParseNumber relies on the stream being copied (it reads the number through a
// copy and then asks the original for the number's start), exactly as for its own
// InsituStringStream.
namespace rapidjson {
template <>
struct StreamTraits<ocp::json_detail::InsituStream> {
  enum { copyOptimization = 1 };
};
}  // namespace rapidjson

namespace ocp::json_detail {

std::string_view Tape::source_of(std::size_t index) const {
  const Token& token = tokens[index];
  const std::size_t begin = token.source_offset;
  std::size_t end = begin;
  switch (token.kind) {
    case TokenKind::object_begin:
    case TokenKind::array_begin: end = tokens[token.end_index].source_offset; break;
    case TokenKind::number: end = begin + token.text_length; break;  // verbatim in the source
    case TokenKind::null_value:
    case TokenKind::true_value: end = begin + 4; break;
    case TokenKind::false_value: end = begin + 5; break;
    case TokenKind::string:
    case TokenKind::key:
      // The tokenizer validated the string: its end is the first unescaped quote.
      end = begin + 1;
      while (end < source.size() && source[end] != '"') end += source[end] == '\\' ? 2 : 1;
      end += 1;
      break;
    case TokenKind::object_end:
    case TokenKind::array_end: break;  // not values
  }
  return source.substr(begin, end - begin);
}

Status tokenize(std::string_view json, Tape& tape, bool require_object) {
  tape.source = json;
  tape.tokens.clear();
  if (json.size() >= std::numeric_limits<std::uint32_t>::max()) {
    return malformed("document larger than 4 GiB");
  }
  tape.text.assign(json);  // the in-situ work copy; never resized while parsing
  rapidjson::Reader reader;
  InsituStream stream(tape.text.data(), tape.text.size());
  TapeHandler handler(tape, stream);
  const rapidjson::ParseResult result = reader.Parse<parse_flags>(stream, handler);
  if (handler.too_deep()) {
    return Error{make_error_code(ProtocolError::too_deep),
                 "nesting deeper than " + std::to_string(max_json_depth) + " levels at offset " +
                     std::to_string(stream.Tell())};
  }
  if (handler.lone_surrogate()) {
    return malformed("string holds a lone UTF-16 surrogate escape (before offset " +
                     std::to_string(stream.Tell()) + ")");
  }
  if (result.IsError()) {
    return malformed(std::string(rapidjson::GetParseError_En(result.Code())) + " (offset " +
                     std::to_string(result.Offset()) + ")");
  }
  if (stream.Tell() != json.size()) {
    // RapidJSON stops at a NUL byte as if the input ended there.
    return malformed("unexpected NUL byte (offset " + std::to_string(stream.Tell()) + ")");
  }
  if (require_object && tape.tokens.front().kind != TokenKind::object_begin) {
    return Error{make_error_code(ProtocolError::not_an_object),
                 "top-level value is not an object"};
  }
  return Ok{};
}

Tape& thread_tape() {
  thread_local Tape tape;
  return tape;
}

}  // namespace ocp::json_detail

namespace ocp {

Status validate_raw_json(std::string_view text) {
  json_detail::Tape tape;
  return json_detail::tokenize(text, tape, /*require_object=*/false);
}

}  // namespace ocp
