#pragma once
// Typed reading of a tokenized document (see json_codec_tape.hpp), shared by the four message
// decoders. Every reader returns false after recording the first problem; callers add their
// path segment while unwinding, so the final detail reads "telemetry.fault: expected boolean".
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
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
  bool read_bool(std::size_t index, bool& out) {  // inline: 15 buttons a controller
    switch (kind(index)) {
      case TokenKind::true_value: out = true; return true;
      case TokenKind::false_value: out = false; return true;
      default: return fail(PeerError::wrong_type, "expected boolean");
    }
  }
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

// Named fields of a fixed object layout. Each object has a field enum listing its fields in
// the order encoders write them, ending in `unknown` (any key not in the table):
//
//   enum class ResponseField : std::uint8_t { ack_time, ack_time_mac, vehicle_user_data, unknown };
//
// The enum's values are the fields' positions in their FieldTable, checked at compile time.
template <class Field>
concept FieldEnum = std::is_enum_v<Field> && requires { Field::unknown; };

template <FieldEnum Field>
inline constexpr std::size_t field_count = static_cast<std::size_t>(Field::unknown);

// Every field of `Field`, in enum order (for objects whose fields are all required).
template <FieldEnum Field>
inline constexpr std::array<Field, field_count<Field>> every_field = [] {
  std::array<Field, field_count<Field>> fields{};
  for (std::size_t i = 0; i < fields.size(); ++i) fields[i] = static_cast<Field>(i);
  return fields;
}();

// Key → field lookup. Encoders write fields in table order, so the field after the last
// match is tried first and a canonical message needs one compare per key.
template <FieldEnum Field>
class FieldTable {
 public:
  static constexpr std::size_t size = field_count<Field>;
  struct Entry {
    Field field;
    std::string_view name;
  };

  // Entries in enum order, one per field: {ResponseField::ack_time, "ack_time"}, ...
  explicit consteval FieldTable(const Entry (&entries)[size]) : names_{} {
    for (std::size_t i = 0; i < size; ++i) {
      if (entries[i].field != static_cast<Field>(i) || entries[i].name.empty()) {
        throw "FieldTable: entries must list every field once, in enum order";
      }
      names_[i] = entries[i].name;
    }
  }

  // The field named `key`, or Field::unknown. `hint` is the position of the field expected
  // next (start at 0); a match moves it past the field found.
  Field find(std::string_view key, std::size_t& hint) const {
    if (hint < size && same_key(names_[hint], key)) return static_cast<Field>(hint++);
    for (std::size_t i = 0; i < size; ++i) {
      if (same_key(names_[i], key)) {
        hint = i + 1;
        return static_cast<Field>(i);
      }
    }
    return Field::unknown;
  }
  std::string_view name(Field field) const { return names_[static_cast<std::size_t>(field)]; }

 private:
  // name == key without a call to memcmp (a third of a key lookup): eight bytes at a time,
  // the last word overlapping the one before it.
  static bool same_key(std::string_view name, std::string_view key) {
    const std::size_t n = name.size();
    if (n != key.size()) return false;
    if (n >= 8) {
      for (std::size_t i = 0; i + 8 < n; i += 8) {
        if (load8(name.data() + i) != load8(key.data() + i)) return false;
      }
      return load8(name.data() + n - 8) == load8(key.data() + n - 8);
    }
    if (n >= 4) {
      return load4(name.data()) == load4(key.data()) &&
             load4(name.data() + n - 4) == load4(key.data() + n - 4);
    }
    // 0 to 3 bytes ("a", "pos"): first, middle and last cover them all.
    return n == 0 || (name[0] == key[0] && name[n / 2] == key[n / 2] && name[n - 1] == key[n - 1]);
  }
  static std::uint64_t load8(const char* at) {
    std::uint64_t word;
    std::memcpy(&word, at, sizeof word);
    return word;
  }
  static std::uint32_t load4(const char* at) {
    std::uint32_t word;
    std::memcpy(&word, at, sizeof word);
    return word;
  }

  std::array<std::string_view, size> names_;
};

// The fields an object has shown so far. Marking Field::unknown is allowed (it has a bit of
// its own) so callers can mark whatever find() returned.
template <FieldEnum Field>
class FieldSet {
  static_assert(field_count<Field> < 32, "one bit a field, unknown included");

 public:
  constexpr FieldSet() = default;
  template <std::size_t M>
  explicit constexpr FieldSet(const std::array<Field, M>& fields) {
    for (const Field field : fields) mark(field);
  }

  constexpr void mark(Field field) { bits_ |= bit(field); }
  constexpr bool has(Field field) const { return (bits_ & bit(field)) != 0; }
  constexpr bool has_all(FieldSet fields) const { return (bits_ & fields.bits_) == fields.bits_; }

 private:
  static constexpr std::uint32_t bit(Field field) {
    return std::uint32_t{1} << static_cast<unsigned>(field);
  }
  std::uint32_t bits_ = 0;
};

// Fails with the first field of `required` (a constexpr std::array of Field, in the order a
// missing field is reported) that `seen` lacks.
template <const auto& required, FieldEnum Field>
bool require_fields(Decoder& decoder, const FieldTable<Field>& table, FieldSet<Field> seen) {
  constexpr FieldSet<Field> all_required{required};
  if (seen.has_all(all_required)) return true;  // the usual case: one compare
  for (const Field field : required) {
    if (!seen.has(field)) return decoder.fail_missing(table.name(field));
  }
  return true;
}

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
