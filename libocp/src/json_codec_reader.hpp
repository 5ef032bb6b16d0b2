#pragma once
// Typed reading of a tokenized document (see json_codec_tape.hpp), shared by the four message
// decoders. Every reader returns false after recording the first problem; callers add their
// path segment while unwinding, so the final detail reads "telemetry.fault: expected boolean".
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "json_codec_tape.hpp"
#include "ocp/error.hpp"
#include "ocp/messages.hpp"

namespace ocp::json_detail {

class Decoder {
 public:
  explicit Decoder(const Tape& tape) : tape_(tape) {}

  const Tape& tape() const { return tape_; }
  TokenKind kind(std::size_t index) const { return tape_.tokens[index].kind; }
  bool is_null(std::size_t index) const { return kind(index) == TokenKind::null_value; }

  // Records the first problem; always returns false so callers can `return fail(...)`.
  bool fail(PeerError code, std::string_view message);
  bool fail_missing(std::string_view field);
  // Adds one path segment while an error unwinds.
  bool in_field(std::string_view field, bool ok);
  bool in_element(std::size_t position, bool ok);
  // "a.b[2].c: message" — valid once a reader returned false.
  Error take_error() const;

  bool expect_object(std::size_t index);
  bool read_bool(std::size_t index, bool& out);
  bool read_u64(std::size_t index, std::uint64_t& out);
  bool read_u32(std::size_t index, std::uint32_t& out);
  // A non-negative integral number: integer text, or a fraction/exponent whose value is whole.
  bool read_integral(std::size_t index, std::uint64_t& out);
  bool read_double(std::size_t index, double& out);
  bool read_string(std::size_t index, std::string& out);
  bool read_string_array(std::size_t index, std::vector<std::string>& out);
  // Any JSON value, kept as its exact source bytes.
  bool read_raw(std::size_t index, RawJson& out);

  // Calls on_member(key, value_index) for every member of the object at `index` (which must
  // be an object); the key is added to the path when on_member fails.
  template <class OnMember>
  bool for_each_member(std::size_t index, OnMember&& on_member) {
    if (!expect_object(index)) return false;
    const std::size_t end = tape_.tokens[index].end_index;
    std::size_t position = index + 1;
    while (position < end) {
      const std::string_view key = tape_.text_of(tape_.tokens[position]);
      const std::size_t value = position + 1;
      if (!on_member(key, value)) return in_field(key, false);
      position = tape_.next(value);
    }
    return true;
  }

 private:
  const Tape& tape_;
  PeerError code_ = PeerError::malformed_json;
  std::string message_;
  std::vector<std::string> path_reversed_;
};

// Field lookup for a fixed object layout. Encoders write fields in table order, so the field
// after the last match is tried first and a canonical message needs one compare per key.
template <std::size_t N>
class FieldTable {
 public:
  explicit constexpr FieldTable(std::array<std::string_view, N> names) : names_(names) {}

  // Index of `key`, or N when it is not a known field. `hint` carries the expected position.
  std::size_t find(std::string_view key, std::size_t& hint) const {
    if (hint < N && names_[hint] == key) return hint++;
    for (std::size_t i = 0; i < N; ++i) {
      if (names_[i] == key) {
        hint = i + 1;
        return i;
      }
    }
    return N;
  }
  std::string_view name(std::size_t i) const { return names_[i]; }

 private:
  std::array<std::string_view, N> names_;
};

// Shared pieces: the controller (control message, feedback) and vehicle user data
// (response, feedback).
bool read_controller(Decoder& decoder, std::size_t index, Controller& out);
bool read_optional_controller(Decoder& decoder, std::size_t index,
                              std::optional<Controller>& out);
bool read_vehicle_user_data(Decoder& decoder, std::size_t index, VehicleUserData& out);

// Runs `decode_root(decoder, root_index, message)` over an already tokenized document.
template <class Message, class DecodeRoot>
Result<Message> decode_tape(const Tape& tape, DecodeRoot&& decode_root) {
  Decoder decoder(tape);
  Message message;
  if (!decode_root(decoder, std::size_t{0}, message)) return decoder.take_error();
  return message;
}

// Tokenizes `json` with the thread's tape and runs `decode_root(decoder, root_index)`.
template <class Message, class DecodeRoot>
Result<Message> decode_document(std::string_view json, DecodeRoot&& decode_root) {
  Tape& tape = thread_tape();
  // One hostile megabyte must not stay pinned in the thread's tape for good.
  struct TrimLargeTape {
    Tape& tape;
    ~TrimLargeTape() {
      constexpr std::size_t kept_bytes = std::size_t{1} << 20;
      if (tape.text.capacity() > kept_bytes) {
        tape.text = std::string();
        tape.tokens = std::vector<Token>();
      }
    }
  } trim{tape};
  Status status = tokenize(json, tape);
  if (!status) return status.error();
  return decode_tape<Message>(tape, decode_root);
}

}  // namespace ocp::json_detail
