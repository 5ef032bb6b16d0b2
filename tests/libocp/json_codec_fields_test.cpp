// The decoders' named fields (json_codec_reader.hpp): FieldTable finds a key's field (trying
// the one after the last match first), FieldSet records what an object showed, and
// require_fields reports the first missing required field in the order it lists them.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "json_codec_reader.hpp"

namespace ocp {
namespace {

using json_detail::Decoder;
using json_detail::FieldSet;
using json_detail::FieldTable;
using json_detail::require_fields;

enum class FieldsTestField : std::uint8_t { first, second, third, unknown };
constexpr FieldTable<FieldsTestField> fields_test_table({
    {FieldsTestField::first, "first"},
    {FieldsTestField::second, "second"},
    {FieldsTestField::third, "third"},
});
constexpr std::array fields_test_required{FieldsTestField::third, FieldsTestField::first};

static_assert(json_detail::field_count<FieldsTestField> == 3);
static_assert(json_detail::every_field<FieldsTestField> ==
              std::array{FieldsTestField::first, FieldsTestField::second, FieldsTestField::third});

TEST(JsonCodecFields, FindReturnsTheNamedFieldInAnyOrderAndUnknownOtherwise) {
  std::size_t hint = 0;
  EXPECT_EQ(fields_test_table.find("first", hint), FieldsTestField::first);
  EXPECT_EQ(hint, 1U);  // table order: "second" is tried first next
  EXPECT_EQ(fields_test_table.find("third", hint), FieldsTestField::third);
  EXPECT_EQ(hint, 3U);
  EXPECT_EQ(fields_test_table.find("second", hint), FieldsTestField::second);
  EXPECT_EQ(hint, 2U);
  EXPECT_EQ(fields_test_table.find("fourth", hint), FieldsTestField::unknown);
  EXPECT_EQ(hint, 2U);  // an unknown key leaves the hint alone
  EXPECT_EQ(fields_test_table.find("", hint), FieldsTestField::unknown);
  EXPECT_EQ(fields_test_table.name(FieldsTestField::third), "third");
}

TEST(JsonCodecFields, FieldSetMarksEachFieldOnItsOwn) {
  FieldSet<FieldsTestField> seen;
  EXPECT_FALSE(seen.has(FieldsTestField::first));
  seen.mark(FieldsTestField::second);
  seen.mark(FieldsTestField::unknown);
  EXPECT_TRUE(seen.has(FieldsTestField::second));
  EXPECT_FALSE(seen.has(FieldsTestField::first));
  EXPECT_FALSE(seen.has(FieldsTestField::third));
  EXPECT_TRUE(seen.has_all(FieldSet<FieldsTestField>(std::array{FieldsTestField::second})));
  EXPECT_FALSE(seen.has_all(FieldSet<FieldsTestField>(fields_test_required)));
}

TEST(JsonCodecFields, RequireFieldsReportsTheFirstMissingInListedOrder) {
  const json_detail::Tape tape;
  {
    Decoder decoder(tape);
    FieldSet<FieldsTestField> seen;
    seen.mark(FieldsTestField::second);
    EXPECT_FALSE(require_fields<fields_test_required>(decoder, fields_test_table, seen));
    const Error error = decoder.take_error();
    EXPECT_EQ(error.code, PeerError::missing_field);
    EXPECT_EQ(error.detail, "third: required field missing");  // listed first, not table order
  }
  {
    Decoder decoder(tape);
    FieldSet<FieldsTestField> seen;
    seen.mark(FieldsTestField::third);
    EXPECT_FALSE(require_fields<fields_test_required>(decoder, fields_test_table, seen));
    EXPECT_EQ(decoder.take_error().detail, "first: required field missing");
  }
  {
    Decoder decoder(tape);
    FieldSet<FieldsTestField> seen;
    seen.mark(FieldsTestField::first);
    seen.mark(FieldsTestField::third);
    EXPECT_TRUE(require_fields<fields_test_required>(decoder, fields_test_table, seen));
  }
}

}  // namespace
}  // namespace ocp
