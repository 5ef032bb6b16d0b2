// The com channel's body codec (com_datagram.hpp): every LinkMessage as little-endian bytes.
// The reader never trusts a length: each read checks what is left, and one failed read makes
// the whole decode fail.
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "ocp/com_datagram.hpp"
#include "ocp/json_codec.hpp"

namespace ocp::com {
namespace {

constexpr std::size_t max_list_items = 64;      // faults, missing cameras
constexpr std::size_t max_string_bytes = 1024;  // a camera name
constexpr std::size_t max_json_bytes = 64 * 1024;

class BodyWriter {
 public:
  explicit BodyWriter(std::string& out) : out_(out) {}
  template <typename T>
  void integer(T value) {
    using U = std::make_unsigned_t<T>;
    const U bits = static_cast<U>(value);
    for (std::size_t i = 0; i < sizeof(T); ++i) out_.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));
  }
  void real(double value) { integer(std::bit_cast<std::uint64_t>(value)); }
  void flag(bool value) { integer<std::uint8_t>(value ? 1 : 0); }
  void text(std::string_view value, std::size_t limit) {
    const std::size_t length = std::min(value.size(), limit);   // the sender's own data: capped, never refused
    integer(static_cast<std::uint32_t>(length));
    out_.append(value.substr(0, length));
  }

 private:
  std::string& out_;
};

class BodyReader {
 public:
  explicit BodyReader(std::string_view in) : in_(in) {}
  template <typename T>
  T integer() {
    using U = std::make_unsigned_t<T>;
    if (in_.size() < sizeof(T)) return fail<T>();
    U bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) bits |= static_cast<U>(static_cast<U>(static_cast<std::uint8_t>(in_[i])) << (8 * i));  // NOLINT
    in_.remove_prefix(sizeof(T));
    return static_cast<T>(bits);
  }
  double real() {
    const double value = std::bit_cast<double>(integer<std::uint64_t>());
    if (!std::isfinite(value)) ok_ = false;
    return value;
  }
  bool flag() {
    const auto value = integer<std::uint8_t>();
    if (value > 1) ok_ = false;
    return value == 1;
  }
  std::string text(std::size_t limit) {
    const auto length = integer<std::uint32_t>();
    if (length > limit || length > in_.size()) return fail<std::string>();
    std::string value(in_.substr(0, length));
    in_.remove_prefix(length);
    return value;
  }
  // A value read well but outside its range: the whole decode fails.
  void reject() { fail<int>(); }
  bool ok() const { return ok_; }
  bool at_end() const { return in_.empty(); }

 private:
  template <typename T>
  T fail() {
    ok_ = false;
    in_ = {};
    return T{};
  }
  std::string_view in_;
  bool ok_ = true;
};

// ---- the fields ----

constexpr std::size_t button_count = 15;
bool Buttons::* const button_fields[button_count] = {
    &Buttons::a, &Buttons::b, &Buttons::x, &Buttons::y, &Buttons::left_bumper, &Buttons::right_bumper,
    &Buttons::back, &Buttons::start, &Buttons::guide, &Buttons::left_thumb, &Buttons::right_thumb,
    &Buttons::dpad_up, &Buttons::dpad_right, &Buttons::dpad_down, &Buttons::dpad_left};
double Axes::* const axis_fields[] = {&Axes::left_x, &Axes::left_y, &Axes::right_x,
                                      &Axes::right_y, &Axes::left_trigger, &Axes::right_trigger};

void write_controller(BodyWriter& out, const Controller& controller) {
  std::uint16_t bits = 0;
  for (std::size_t i = 0; i < button_count; ++i) {
    if (controller.buttons.*button_fields[i]) bits = static_cast<std::uint16_t>(bits | (1u << i));
  }
  out.integer(bits);
  for (const auto field : axis_fields) out.real(controller.axes.*field);
}
Controller read_controller(BodyReader& in) {
  Controller controller;
  const auto bits = in.integer<std::uint16_t>();
  if (bits >> button_count) in.reject();   // a button we do not know
  for (std::size_t i = 0; i < button_count; ++i) controller.buttons.*button_fields[i] = (bits >> i) & 1u;
  for (const auto field : axis_fields) {
    const double value = in.real();
    if (!(value >= -1.0 && value <= 1.0)) in.reject();   // SPEC: axes are in [-1, 1]
    controller.axes.*field = value;
  }
  return controller;
}

void write_ack(BodyWriter& out, const AckPair& ack) {
  out.integer(ack.ack_time);
  out.integer(ack.ack_time_mac);
}
AckPair read_ack(BodyReader& in) {
  AckPair ack;
  ack.ack_time = in.integer<std::uint64_t>();
  ack.ack_time_mac = in.integer<std::uint32_t>();
  return ack;
}

void write_faults(BodyWriter& out, const std::vector<FaultId>& faults) {
  const std::size_t count = std::min(faults.size(), max_list_items);
  out.integer(static_cast<std::uint8_t>(count));
  for (std::size_t i = 0; i < count; ++i) out.integer(static_cast<std::uint8_t>(faults[i]));
}
std::optional<std::vector<FaultId>> read_faults(BodyReader& in) {
  const auto count = in.integer<std::uint8_t>();
  if (count > max_list_items) return std::nullopt;
  std::vector<FaultId> faults;
  for (std::size_t i = 0; i < count; ++i) {
    const auto id = in.integer<std::uint8_t>();
    if (id >= fault_count) return std::nullopt;
    faults.push_back(static_cast<FaultId>(id));
  }
  return faults;
}

std::optional<RawJson> read_json(BodyReader& in) {
  RawJson json{in.text(max_json_bytes)};
  if (!in.ok() || !validate_raw_json(json.text)) return std::nullopt;
  return json;
}

void write_vehicle_data(BodyWriter& out, const VehicleUserData& data) {
  out.flag(data.pos.has_value());
  if (data.pos) {
    out.real(data.pos->lat);
    out.real(data.pos->lon);
  }
  out.text(data.user_data.text, max_json_bytes);
}
std::optional<VehicleUserData> read_vehicle_data(BodyReader& in) {
  VehicleUserData data;
  if (in.flag()) data.pos = Position{in.real(), in.real()};
  auto json = read_json(in);
  if (!json) return std::nullopt;
  data.user_data = std::move(*json);
  return data;
}

// ---- the messages ----

void write(BodyWriter& out, const OperatorControl& message) {
  out.integer(message.sequence);
  out.flag(message.controller.has_value());
  if (message.controller) write_controller(out, *message.controller);
  out.flag(message.client_user_data.has_value());
  if (message.client_user_data) out.text(message.client_user_data->text, max_json_bytes);
  out.flag(message.returned_ack.has_value());
  if (message.returned_ack) write_ack(out, *message.returned_ack);
  write_faults(out, message.sender_faults);
}
std::optional<LinkMessage> read_operator_control(BodyReader& in) {
  OperatorControl message;
  message.sequence = in.integer<std::uint64_t>();
  if (in.flag()) message.controller = read_controller(in);
  if (in.flag()) {
    message.client_user_data = read_json(in);
    if (!message.client_user_data) return std::nullopt;
  }
  if (in.flag()) message.returned_ack = read_ack(in);
  auto faults = read_faults(in);
  if (!faults) return std::nullopt;
  message.sender_faults = std::move(*faults);
  return message;
}

void write(BodyWriter& out, const StreamerFeedback& message) {
  out.integer(message.sequence);
  write_faults(out, message.receiver_faults);
  out.flag(message.latency_ms.has_value());
  if (message.latency_ms) out.integer(*message.latency_ms);
  const std::size_t cameras = std::min(message.missing_cameras.size(), max_list_items);
  out.integer(static_cast<std::uint8_t>(cameras));
  for (std::size_t i = 0; i < cameras; ++i) out.text(message.missing_cameras[i], max_string_bytes);
  out.flag(message.vehicle_data.has_value());
  if (message.vehicle_data) write_vehicle_data(out, *message.vehicle_data);
  out.flag(message.vehicle_data_age.has_value());
  if (message.vehicle_data_age) out.integer(static_cast<std::int64_t>(message.vehicle_data_age->count()));
  out.flag(message.last_remote_input.has_value());
  if (message.last_remote_input) write_controller(out, *message.last_remote_input);
}
std::optional<LinkMessage> read_streamer_feedback(BodyReader& in) {
  StreamerFeedback message;
  message.sequence = in.integer<std::uint64_t>();
  auto faults = read_faults(in);
  if (!faults) return std::nullopt;
  message.receiver_faults = std::move(*faults);
  if (in.flag()) message.latency_ms = in.integer<std::uint64_t>();
  const auto cameras = in.integer<std::uint8_t>();
  if (cameras > max_list_items) return std::nullopt;
  for (std::size_t i = 0; i < cameras; ++i) message.missing_cameras.push_back(in.text(max_string_bytes));
  if (in.flag()) {
    message.vehicle_data = read_vehicle_data(in);
    if (!message.vehicle_data) return std::nullopt;
  }
  if (in.flag()) {
    const auto age = in.integer<std::int64_t>();
    if (age < 0) return std::nullopt;
    message.vehicle_data_age = Micros{age};
  }
  if (in.flag()) message.last_remote_input = read_controller(in);
  return message;
}

void write(BodyWriter& out, const VideoFrame& message) {
  out.text(message.camera, max_string_bytes);
  out.integer(message.frame_number);
  out.flag(message.sei.has_value());
  if (message.sei) write_ack(out, *message.sei);
  out.integer(message.size_bytes);
}
std::optional<LinkMessage> read_video_frame(BodyReader& in) {
  VideoFrame message;
  message.camera = in.text(max_string_bytes);
  message.frame_number = in.integer<std::uint64_t>();
  if (in.flag()) message.sei = read_ack(in);
  message.size_bytes = in.integer<std::uint32_t>();
  return message;
}

void write(BodyWriter& out, const Ping& message) {
  out.integer(message.id);
  out.integer(static_cast<std::int64_t>(message.sent_at.count()));
}
void write(BodyWriter& out, const Pong& message) {
  out.integer(message.id);
  out.integer(static_cast<std::int64_t>(message.ping_sent_at.count()));
}
std::optional<LinkMessage> read_ping(BodyReader& in) {
  Ping message;
  message.id = in.integer<std::uint64_t>();
  message.sent_at = SimTime{in.integer<std::int64_t>()};
  return message;
}
std::optional<LinkMessage> read_pong(BodyReader& in) {
  Pong message;
  message.id = in.integer<std::uint64_t>();
  message.ping_sent_at = SimTime{in.integer<std::int64_t>()};
  return message;
}

}  // namespace

LinkKind kind_of(const LinkMessage& message) {
  return static_cast<LinkKind>(message.index() + 1);   // the variant's order is LinkKind's
}

bool travels_to_streamer(LinkKind kind) { return kind == LinkKind::operator_control || kind == LinkKind::ping; }

std::string encode_body(const LinkMessage& message) {
  std::string body;
  BodyWriter out(body);
  std::visit([&](const auto& value) { write(out, value); }, message);
  if (const auto* frame = std::get_if<VideoFrame>(&message)) {
    // The frame's encoded bytes, so the wire carries its size (capped to one message).
    const std::size_t size = std::min<std::size_t>(frame->size_bytes, max_message_bytes);
    if (body.size() < size) body.resize(size, '\0');
  }
  return body;
}

std::optional<LinkMessage> decode_body(LinkKind kind, std::string_view body) {
  BodyReader in(body);
  std::optional<LinkMessage> message;
  switch (kind) {
    case LinkKind::operator_control: message = read_operator_control(in); break;
    case LinkKind::streamer_feedback: message = read_streamer_feedback(in); break;
    case LinkKind::video_frame: message = read_video_frame(in); break;
    case LinkKind::ping: message = read_ping(in); break;
    case LinkKind::pong: message = read_pong(in); break;
    default: return std::nullopt;
  }
  // Only a video frame carries bytes past its fields (its padding).
  if (!message || !in.ok() || (kind != LinkKind::video_frame && !in.at_end())) return std::nullopt;
  return message;
}

}  // namespace ocp::com
