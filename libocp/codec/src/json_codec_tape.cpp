#include "json_codec_tape.hpp"

#include <array>
#include <bit>
#include <cstring>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "json_codec_rapidjson.hpp"
#include "ocp/json_codec.hpp"

namespace ocp::json_detail {
namespace {

// In-situ stream over the tape's private copy of the input. In-situ parsing decodes strings
// in place and hands out numbers as pointers into the copy, so RapidJSON never needs its
// internal stack (whose first growth is undefined behaviour in RapidJSON 1.1: it offsets a
// null pointer) and nothing is copied twice. Writes trail the read position (and never pass
// the end, see Put).
//
// Bounded: past the end it reads '\0', which RapidJSON treats as end of input. Needed when
// encoding validation is on: RapidJSON's UTF-8 decoder takes continuation bytes without
// looking, so a truncated sequence at the end would read past the terminator.
// Unbounded (all-ASCII input, no validation): RapidJSON never takes a '\0', so the work
// copy's own terminator stops it, and every Peek/Take saves a compare.
template <bool Bounded>
class InsituStream {
 public:
  using Ch = char;
  InsituStream(char* begin, std::size_t size)
      : begin_(begin), current_(begin), end_(begin + size), write_(begin) {}

  Ch Peek() const {
    if constexpr (Bounded) {
      return current_ == end_ ? '\0' : *current_;
    } else {
      return *current_;
    }
  }
  Ch Take() {
    if constexpr (Bounded) {
      return current_ == end_ ? '\0' : *current_++;
    } else {
      return *current_++;
    }
  }
  std::size_t Tell() const { return static_cast<std::size_t>(current_ - begin_); }

  Ch* PutBegin() { return write_ = current_; }
  // Bounded: the decoder copies each byte it takes before checking it, so at a truncated
  // sequence it "copies" the '\0's read past the end too: the write position would overtake
  // the read position and leave the buffer. Such a parse always fails, so the bytes past the
  // end are dropped. (Found by fuzz_json_tape_differential: an unterminated string ending in
  // the first bytes of a 4-byte sequence wrote beyond the work copy.)
  void Put(Ch c) {
    if constexpr (Bounded) {
      if (write_ == end_) return;
    }
    *write_++ = c;
  }
  void Flush() {}
  std::size_t PutEnd(Ch* begin) { return static_cast<std::size_t>(write_ - begin); }

 private:
  char* begin_;
  char* current_;
  char* end_;
  char* write_;
};

template <class Stream>
class TapeHandler {
 public:
  // `check_surrogates`: false when the input has neither escapes nor non-ASCII bytes, so no
  // decoded string can hold a surrogate.
  TapeHandler(Tape& tape, const Stream& stream, bool check_surrogates)
      : tape_(tape), stream_(stream), check_surrogates_(check_surrogates) {}

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
    if (!check_surrogates_) return true;
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
  const Stream& stream_;
  bool check_surrogates_;
  int depth_ = 0;
  bool too_deep_ = false;
  bool lone_surrogate_ = false;
  std::array<std::uint32_t, max_json_depth> open_indexes_{};
};

// The fast path for what the codec sees all day: well-formed, all-ASCII documents without
// escapes or exponents (the encoders never write them). It records exactly the tape RapidJSON
// would (same tokens, offsets and texts) at a fraction of the cost, and gives up on anything
// else (escapes, non-ASCII, control bytes, exponents, long numbers, depth, any syntax error):
// RapidJSON then parses the document from scratch, so every error and every unusual input
// goes through the one validating parser.
class FastTokenizer {
 public:
  FastTokenizer(std::string_view json, Tape& tape)
      : begin_(json.data()), at_(json.data()), end_(json.data() + json.size()), tape_(tape) {}

  // One loop, no recursion: with value() and the helpers inlined here, GCC keeps the cursor
  // and the depth in registers instead of reloading them from the object after every token.
  bool run() {
    for (;;) {
      skip_whitespace();
      const Step step = value();
      if (step == Step::failed) return false;
      if (step == Step::need_value) continue;  // an opened container's first value
      // After a value: close containers, or find the next element.
      for (;;) {
        skip_whitespace();
        if (depth_ == 0) return at_ == end_;
        if (at_ == end_) return false;
        const bool in_object = ((object_depths_ >> (depth_ - 1)) & 1) != 0;
        const char c = *at_;
        if (c == ',') {
          ++at_;
          if (in_object && !member_key()) return false;
          break;  // next value
        }
        if (c != (in_object ? '}' : ']')) return false;
        ++at_;
        close(in_object ? TokenKind::object_end : TokenKind::array_end);
      }
    }
  }

 private:
  // ' ', '\t', '\n', '\r' as bits of one mask: a shift and a compare instead of four compares.
  static bool is_whitespace(char c) {
    constexpr std::uint64_t mask = (1ULL << ' ') | (1ULL << '\t') | (1ULL << '\n') | (1ULL << '\r');
    const auto byte = static_cast<unsigned char>(c);
    return byte <= ' ' && ((mask >> byte) & 1) != 0;
  }
  // Compact documents (what the encoders write) have no whitespace: one compare. Indented ones
  // (the seeds, hand-written clients) have runs of a newline and spaces, skipped 16 bytes at a
  // time: a byte-by-byte loop was a fifth of the pretty control message's decode.
  void skip_whitespace() {
    if (at_ == end_ || !is_whitespace(*at_)) return;
    ++at_;  // one blank, as after the colon in `"key": value`, is the usual run
    if (at_ == end_ || !is_whitespace(*at_)) return;
#if defined(__SSE2__)
    while (end_ - at_ >= 16) {
      const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at_));
      const __m128i space = _mm_or_si128(_mm_cmpeq_epi8(bytes, _mm_set1_epi8(' ')),
                                         _mm_cmpeq_epi8(bytes, _mm_set1_epi8('\n')));
      const __m128i other = _mm_or_si128(_mm_cmpeq_epi8(bytes, _mm_set1_epi8('\r')),
                                         _mm_cmpeq_epi8(bytes, _mm_set1_epi8('\t')));
      const auto not_space =
          ~static_cast<unsigned>(_mm_movemask_epi8(_mm_or_si128(space, other))) & 0xFFFFu;
      if (not_space != 0) {
        at_ += std::countr_zero(not_space);
        return;
      }
      at_ += 16;
    }
#endif
    while (at_ != end_ && is_whitespace(*at_)) ++at_;
  }
  std::uint32_t offset(const char* at) const { return static_cast<std::uint32_t>(at - begin_); }
  void push(TokenKind kind, const char* at, std::uint32_t text_begin = 0,
            std::uint32_t text_length = 0) {
    Token token;
    token.kind = kind;
    token.text_begin = text_begin;
    token.text_length = text_length;
    token.source_offset = offset(at);
    tape_.tokens.push_back(token);
  }
  void close(TokenKind kind) {
    const std::uint32_t begin_index = open_indexes_[static_cast<std::size_t>(--depth_)];
    tape_.tokens[begin_index].end_index = static_cast<std::uint32_t>(tape_.tokens.size());
    push(kind, at_);  // just past the bracket
  }
  bool open(TokenKind kind) {
    if (depth_ == max_json_depth) return false;
    const std::uint64_t bit = std::uint64_t{1} << depth_;
    object_depths_ = kind == TokenKind::object_begin ? object_depths_ | bit : object_depths_ & ~bit;
    open_indexes_[static_cast<std::size_t>(depth_++)] =
        static_cast<std::uint32_t>(tape_.tokens.size());
    push(kind, at_);
    ++at_;
    return true;
  }
  // A string without escapes: its text is the source between the quotes.
  bool string(TokenKind kind) {
    const char* const quote = at_;
    const char* at = skip_plain(quote + 1);
    for (;; ++at) {
      if (at == end_) return false;
      const auto c = static_cast<unsigned char>(*at);
      if (c == '"') break;
      if (c < 0x20 || c >= 0x80 || c == '\\') return false;
    }
    push(kind, quote, offset(quote + 1), static_cast<std::uint32_t>(at - quote - 1));
    at_ = at + 1;
    return true;
  }
  // Past plain printable ASCII, to the first '"', '\\', control or non-ASCII byte, or near the
  // end: sixteen bytes at a time (SSE2), then eight (the lowest address is the lowest bit only
  // on little-endian machines). Most keys ("ack_time_mac", "left_trigger") end within the first
  // sixteen bytes: one test instead of two or three words.
  const char* skip_plain(const char* at) const {
#if defined(__SSE2__)
    while (end_ - at >= 16) {
      const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
      // Signed compare: bytes >= 0x80 are negative, so "below 0x20" takes non-ASCII too.
      const __m128i special = _mm_or_si128(
          _mm_or_si128(_mm_cmpeq_epi8(bytes, _mm_set1_epi8('"')),
                       _mm_cmpeq_epi8(bytes, _mm_set1_epi8('\\'))),
          _mm_cmplt_epi8(bytes, _mm_set1_epi8(0x20)));
      const auto mask = static_cast<unsigned>(_mm_movemask_epi8(special));
      if (mask != 0) return at + std::countr_zero(mask);
      at += 16;
    }
#endif
    while (std::endian::native == std::endian::little && end_ - at >= 8) {
      std::uint64_t word;
      std::memcpy(&word, at, sizeof word);
      const std::uint64_t special = special_bytes(word);
      if (special != 0) return at + static_cast<unsigned>(std::countr_zero(special)) / 8;
      at += 8;
    }
    return at;
  }
  // High bit set in each byte of `word` that is '"', '\\', below 0x20 or above 0x7F (exact for
  // the lowest such byte, which is all the caller needs: borrows only run upwards).
  static std::uint64_t special_bytes(std::uint64_t word) {
    constexpr std::uint64_t ones = 0x0101010101010101ULL;
    constexpr std::uint64_t high = 0x8080808080808080ULL;
    const std::uint64_t quote = word ^ (ones * '"');
    const std::uint64_t backslash = word ^ (ones * '\\');
    const std::uint64_t zero_quote = (quote - ones) & ~quote;
    const std::uint64_t zero_backslash = (backslash - ones) & ~backslash;
    const std::uint64_t control = word - ones * 0x20;  // borrows into the high bit if < 0x20
    return (zero_quote | zero_backslash | control | word) & high;
  }
  // `"key" :` with the whitespace JSON allows around it.
  bool member_key() {
    skip_whitespace();
    if (at_ == end_ || *at_ != '"' || !string(TokenKind::key)) return false;
    skip_whitespace();
    if (at_ == end_ || *at_ != ':') return false;
    ++at_;
    return true;
  }
  static bool is_digit(char c) { return c >= '0' && c <= '9'; }
  bool number() {
    const char* const start = at_;
    const char* at = at_;
    if (*at == '-') ++at;
    if (at == end_) return false;
    if (*at == '0') {
      ++at;
    } else if (is_digit(*at)) {
      while (at != end_ && is_digit(*at)) ++at;
    } else {
      return false;
    }
    if (at != end_ && *at == '.') {
      ++at;
      if (at == end_ || !is_digit(*at)) return false;
      while (at != end_ && is_digit(*at)) ++at;
    }
    // Exponents and very long numbers carry RapidJSON's range checks: leave them to it.
    constexpr std::ptrdiff_t longest_plain_number = 40;
    if (at != end_ && (*at == 'e' || *at == 'E')) return false;
    if (at - start > longest_plain_number) return false;
    push(TokenKind::number, start, offset(start), static_cast<std::uint32_t>(at - start));
    at_ = at;
    return true;
  }
  bool literal(std::string_view text, TokenKind kind) {
    if (static_cast<std::size_t>(end_ - at_) < text.size() ||
        std::memcmp(at_, text.data(), text.size()) != 0) {
      return false;
    }
    push(kind, at_);
    at_ += text.size();
    return true;
  }
  // What value() left to do: nothing (a whole value was read), or a value inside the
  // container it opened (after the first member's key).
  enum class Step : std::uint8_t { failed, done, need_value };
  static Step done_if(bool ok) { return ok ? Step::done : Step::failed; }

  // One value, or the start of a container: an opened container is done at once when it is
  // empty, and otherwise wants its first value (after reading the first member's key).
  Step value() {
    if (at_ == end_) return Step::failed;
    switch (*at_) {
      case '{':
      case '[': {
        const bool object = *at_ == '{';
        if (!open(object ? TokenKind::object_begin : TokenKind::array_begin)) return Step::failed;
        skip_whitespace();
        if (at_ != end_ && *at_ == (object ? '}' : ']')) {
          ++at_;
          close(object ? TokenKind::object_end : TokenKind::array_end);
          return Step::done;
        }
        if (object && !member_key()) return Step::failed;
        return Step::need_value;
      }
      case '"': return done_if(string(TokenKind::string));
      case 't': return done_if(literal("true", TokenKind::true_value));
      case 'f': return done_if(literal("false", TokenKind::false_value));
      case 'n': return done_if(literal("null", TokenKind::null_value));
      default: return done_if(number());
    }
  }

  const char* const begin_;
  const char* at_;
  const char* const end_;
  Tape& tape_;
  int depth_ = 0;
  std::uint64_t object_depths_ = 0;  // bit d: the container open at depth d is an object
  static_assert(max_json_depth <= 64, "object_depths_ has a bit a level");
  // Written at each open before any read: not cleared for every document.
  std::array<std::uint32_t, max_json_depth> open_indexes_;
};

constexpr unsigned ascii_parse_flags =
    rapidjson::kParseInsituFlag | rapidjson::kParseNumbersAsStringsFlag;
constexpr unsigned validating_parse_flags =
    ascii_parse_flags | rapidjson::kParseValidateEncodingFlag;

// What a quick pass over the input tells the tokenizer. Encoding validation (RapidJSON checks
// every string byte through its UTF-8 decoder) only matters for bytes >= 0x80, and lone
// surrogates can only come from escapes or non-ASCII bytes; our messages are plain ASCII.
struct InputShape {
  bool ascii = true;
  bool has_backslash = false;
};

InputShape inspect(std::string_view json) {
  InputShape shape;
  const char* at = json.data();
  const char* const end = at + json.size();
  std::uint64_t high_bits = 0;
  for (; end - at >= 8; at += 8) {
    std::uint64_t word;
    std::memcpy(&word, at, sizeof word);
    high_bits |= word;
  }
  for (; at != end; ++at) high_bits |= static_cast<unsigned char>(*at);
  shape.ascii = (high_bits & 0x8080808080808080ULL) == 0;
  // memchr needs a non-null pointer even for zero bytes, and an empty frame's view has none.
  shape.has_backslash = !json.empty() && std::memchr(json.data(), '\\', json.size()) != nullptr;
  return shape;
}

Error malformed(std::string detail) {
  return Error{make_error_code(PeerError::malformed_json), std::move(detail)};
}

}  // namespace
}  // namespace ocp::json_detail

// RapidJSON's ParseNumber relies on the stream being copied (it reads the number through a
// copy and then asks the original for the number's start), exactly as for its own
// InsituStringStream.
namespace rapidjson {
template <bool Bounded>
struct StreamTraits<ocp::json_detail::InsituStream<Bounded>> {
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

namespace {

Status check_root(const Tape& tape, bool require_object) {
  if (require_object && tape.tokens.front().kind != TokenKind::object_begin) {
    return Error{make_error_code(PeerError::not_an_object),
                 "top-level value is not an object"};
  }
  return Ok{};
}

template <bool Bounded, unsigned Flags>
Status parse_tape(std::string_view json, Tape& tape, bool require_object,
                  bool check_surrogates) {
  rapidjson::Reader reader;
  InsituStream<Bounded> stream(tape.text.data(), tape.text.size());
  TapeHandler<InsituStream<Bounded>> handler(tape, stream, check_surrogates);
  const rapidjson::ParseResult result = reader.Parse<Flags>(stream, handler);
  if (handler.too_deep()) {
    return Error{make_error_code(PeerError::too_deep),
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
  return check_root(tape, require_object);
}

}  // namespace

Status tokenize(std::string_view json, Tape& tape, bool require_object) {
  tape.source = json;
  tape.tokens.clear();
  if (json.size() >= std::numeric_limits<std::uint32_t>::max()) {
    return malformed("document larger than 4 GiB");
  }
  if (tokenize_fast_path(json, tape)) return check_root(tape, require_object);
  return tokenize_with_rapidjson(json, tape, require_object);
}

bool tokenize_fast_path(std::string_view json, Tape& tape) {
  tape.source = json;
  tape.tokens.clear();
  if (json.size() >= std::numeric_limits<std::uint32_t>::max()) return false;
  tape.text.clear();  // the fast path reads texts from the source itself (Tape::text_of)
  if (FastTokenizer(json, tape).run()) return true;
  tape.tokens.clear();
  return false;
}

Status tokenize_with_rapidjson(std::string_view json, Tape& tape, bool require_object) {
  tape.source = json;
  tape.tokens.clear();
  if (json.size() >= std::numeric_limits<std::uint32_t>::max()) {
    return malformed("document larger than 4 GiB");
  }
  tape.text.assign(json);
  const InputShape shape = inspect(json);
  if (shape.ascii) {
    return parse_tape<false, ascii_parse_flags>(json, tape, require_object, shape.has_backslash);
  }
  return parse_tape<true, validating_parse_flags>(json, tape, require_object, true);
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
