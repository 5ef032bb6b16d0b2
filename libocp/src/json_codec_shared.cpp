// Decoding of the pieces several messages share: the controller and vehicle user data.
#include "json_codec_reader.hpp"

namespace ocp::json_detail {
namespace {

constexpr FieldTable<15> button_fields({"a", "b", "x", "y", "left_bumper", "right_bumper",
                                        "back", "start", "guide", "left_thumb", "right_thumb",
                                        "dpad_up", "dpad_right", "dpad_down", "dpad_left"});
constexpr FieldTable<6> axis_fields(
    {"left_x", "left_y", "right_x", "right_y", "left_trigger", "right_trigger"});
constexpr FieldTable<2> controller_fields({"buttons", "axes"});
constexpr FieldTable<2> position_fields({"lat", "lon"});
constexpr FieldTable<2> vehicle_user_data_fields({"pos", "user_data"});

template <std::size_t N>
bool first_missing(Decoder& decoder, const FieldTable<N>& fields, unsigned seen) {
  for (std::size_t i = 0; i < N; ++i) {
    if ((seen & (1U << i)) == 0) return decoder.fail_missing(fields.name(i));
  }
  return true;
}

bool read_buttons(Decoder& decoder, std::size_t index, Buttons& out) {
  bool* const targets[] = {&out.a,          &out.b,          &out.x,           &out.y,
                           &out.left_bumper, &out.right_bumper, &out.back,      &out.start,
                           &out.guide,      &out.left_thumb, &out.right_thumb, &out.dpad_up,
                           &out.dpad_right, &out.dpad_down,  &out.dpad_left};
  unsigned seen = 0;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = button_fields.find(key, hint);
    if (field == 15) return true;  // unknown fields are ignored
    seen |= 1U << field;
    return decoder.read_bool(value, *targets[field]);
  });
  return ok && first_missing(decoder, button_fields, seen);
}

bool read_axes(Decoder& decoder, std::size_t index, Axes& out) {
  double* const targets[] = {&out.left_x,  &out.left_y,       &out.right_x,
                             &out.right_y, &out.left_trigger, &out.right_trigger};
  unsigned seen = 0;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = axis_fields.find(key, hint);
    if (field == 6) return true;
    seen |= 1U << field;
    return decoder.read_double(value, *targets[field]);
  });
  return ok && first_missing(decoder, axis_fields, seen);
}

bool read_position(Decoder& decoder, std::size_t index, Position& out) {
  unsigned seen = 0;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = position_fields.find(key, hint);
    if (field == 2) return true;
    seen |= 1U << field;
    return decoder.read_double(value, field == 0 ? out.lat : out.lon);
  });
  return ok && first_missing(decoder, position_fields, seen);
}

}  // namespace

bool read_controller(Decoder& decoder, std::size_t index, Controller& out) {
  unsigned seen = 0;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = controller_fields.find(key, hint);
    if (field == 2) return true;
    seen |= 1U << field;
    return field == 0 ? read_buttons(decoder, value, out.buttons)
                      : read_axes(decoder, value, out.axes);
  });
  return ok && first_missing(decoder, controller_fields, seen);
}

bool read_optional_controller(Decoder& decoder, std::size_t index,
                              std::optional<Controller>& out) {
  if (decoder.is_null(index)) {
    out.reset();
    return true;
  }
  return read_controller(decoder, index, out.emplace());
}

bool read_vehicle_user_data(Decoder& decoder, std::size_t index, VehicleUserData& out) {
  unsigned seen = 0;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = vehicle_user_data_fields.find(key, hint);
    if (field == 2) return true;
    if (field == 1) {
      seen |= 2U;
      return decoder.read_raw(value, out.user_data);
    }
    if (decoder.is_null(value)) {
      out.pos.reset();
      return true;
    }
    return read_position(decoder, value, out.pos.emplace());
  });
  // Only user_data is required; pos may be absent.
  if (!ok) return false;
  if ((seen & 2U) == 0) return decoder.fail_missing("user_data");
  return true;
}

}  // namespace ocp::json_detail
