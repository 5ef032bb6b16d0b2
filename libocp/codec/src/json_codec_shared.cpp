// Decoding of the pieces several messages share: the controller and vehicle user data.
#include "json_codec_reader.hpp"

namespace ocp::json_detail {
namespace {

// Buttons, axes, the controller and a position need every field; vehicle user data needs
// user_data only (pos may be absent).
enum class ButtonField : std::uint8_t {
  a,
  b,
  x,
  y,
  left_bumper,
  right_bumper,
  back,
  start,
  guide,
  left_thumb,
  right_thumb,
  dpad_up,
  dpad_right,
  dpad_down,
  dpad_left,
  unknown
};
constexpr FieldTable<ButtonField> button_fields({
    {ButtonField::a, "a"},
    {ButtonField::b, "b"},
    {ButtonField::x, "x"},
    {ButtonField::y, "y"},
    {ButtonField::left_bumper, "left_bumper"},
    {ButtonField::right_bumper, "right_bumper"},
    {ButtonField::back, "back"},
    {ButtonField::start, "start"},
    {ButtonField::guide, "guide"},
    {ButtonField::left_thumb, "left_thumb"},
    {ButtonField::right_thumb, "right_thumb"},
    {ButtonField::dpad_up, "dpad_up"},
    {ButtonField::dpad_right, "dpad_right"},
    {ButtonField::dpad_down, "dpad_down"},
    {ButtonField::dpad_left, "dpad_left"},
});

enum class AxisField : std::uint8_t {
  left_x,
  left_y,
  right_x,
  right_y,
  left_trigger,
  right_trigger,
  unknown
};
constexpr FieldTable<AxisField> axis_fields({
    {AxisField::left_x, "left_x"},
    {AxisField::left_y, "left_y"},
    {AxisField::right_x, "right_x"},
    {AxisField::right_y, "right_y"},
    {AxisField::left_trigger, "left_trigger"},
    {AxisField::right_trigger, "right_trigger"},
});

enum class ControllerField : std::uint8_t { buttons, axes, unknown };
constexpr FieldTable<ControllerField> controller_fields({
    {ControllerField::buttons, "buttons"},
    {ControllerField::axes, "axes"},
});

enum class PositionField : std::uint8_t { lat, lon, unknown };
constexpr FieldTable<PositionField> position_fields({
    {PositionField::lat, "lat"},
    {PositionField::lon, "lon"},
});

enum class VehicleUserDataField : std::uint8_t { pos, user_data, unknown };
constexpr FieldTable<VehicleUserDataField> vehicle_user_data_fields({
    {VehicleUserDataField::pos, "pos"},
    {VehicleUserDataField::user_data, "user_data"},
});
constexpr std::array required_vehicle_user_data_fields{VehicleUserDataField::user_data};

// The member a field is read into: every button reads as a boolean and every axis or
// coordinate as a double, so one call serves each object. `unknown` has no member.
constexpr bool Buttons::*button_member(ButtonField field) {
  switch (field) {
    case ButtonField::a: return &Buttons::a;
    case ButtonField::b: return &Buttons::b;
    case ButtonField::x: return &Buttons::x;
    case ButtonField::y: return &Buttons::y;
    case ButtonField::left_bumper: return &Buttons::left_bumper;
    case ButtonField::right_bumper: return &Buttons::right_bumper;
    case ButtonField::back: return &Buttons::back;
    case ButtonField::start: return &Buttons::start;
    case ButtonField::guide: return &Buttons::guide;
    case ButtonField::left_thumb: return &Buttons::left_thumb;
    case ButtonField::right_thumb: return &Buttons::right_thumb;
    case ButtonField::dpad_up: return &Buttons::dpad_up;
    case ButtonField::dpad_right: return &Buttons::dpad_right;
    case ButtonField::dpad_down: return &Buttons::dpad_down;
    case ButtonField::dpad_left: return &Buttons::dpad_left;
    case ButtonField::unknown: break;
  }
  return nullptr;
}

constexpr double Axes::*axis_member(AxisField field) {
  switch (field) {
    case AxisField::left_x: return &Axes::left_x;
    case AxisField::left_y: return &Axes::left_y;
    case AxisField::right_x: return &Axes::right_x;
    case AxisField::right_y: return &Axes::right_y;
    case AxisField::left_trigger: return &Axes::left_trigger;
    case AxisField::right_trigger: return &Axes::right_trigger;
    case AxisField::unknown: break;
  }
  return nullptr;
}

constexpr double Position::*position_member(PositionField field) {
  switch (field) {
    case PositionField::lat: return &Position::lat;
    case PositionField::lon: return &Position::lon;
    case PositionField::unknown: break;
  }
  return nullptr;
}

bool read_buttons(Decoder& decoder, std::size_t index, Buttons& out) {
  FieldSet<ButtonField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const ButtonField field = button_fields.find(key, hint);
    if (field == ButtonField::unknown) return true;  // unknown fields are ignored
    seen.mark(field);
    return decoder.read_bool(value, out.*button_member(field));
  });
  return ok && require_fields<every_field<ButtonField>>(decoder, button_fields, seen);
}

bool read_axes(Decoder& decoder, std::size_t index, Axes& out) {
  FieldSet<AxisField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const AxisField field = axis_fields.find(key, hint);
    if (field == AxisField::unknown) return true;  // unknown fields are ignored
    seen.mark(field);
    return decoder.read_double(value, out.*axis_member(field));
  });
  return ok && require_fields<every_field<AxisField>>(decoder, axis_fields, seen);
}

bool read_position(Decoder& decoder, std::size_t index, Position& out) {
  FieldSet<PositionField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const PositionField field = position_fields.find(key, hint);
    if (field == PositionField::unknown) return true;  // unknown fields are ignored
    seen.mark(field);
    return decoder.read_double(value, out.*position_member(field));
  });
  return ok && require_fields<every_field<PositionField>>(decoder, position_fields, seen);
}

}  // namespace

bool read_controller(Decoder& decoder, std::size_t index, Controller& out) {
  FieldSet<ControllerField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const ControllerField field = controller_fields.find(key, hint);
    seen.mark(field);
    switch (field) {
      case ControllerField::buttons: return read_buttons(decoder, value, out.buttons);
      case ControllerField::axes: return read_axes(decoder, value, out.axes);
      case ControllerField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
  return ok && require_fields<every_field<ControllerField>>(decoder, controller_fields, seen);
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
  FieldSet<VehicleUserDataField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const VehicleUserDataField field = vehicle_user_data_fields.find(key, hint);
    seen.mark(field);
    switch (field) {
      case VehicleUserDataField::pos:
        if (decoder.is_null(value)) {
          out.pos.reset();
          return true;
        }
        return read_position(decoder, value, out.pos.emplace());
      case VehicleUserDataField::user_data: return decoder.read_raw(value, out.user_data);
      case VehicleUserDataField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
  return ok && require_fields<required_vehicle_user_data_fields>(decoder, vehicle_user_data_fields,
                                                                 seen);
}

}  // namespace ocp::json_detail
