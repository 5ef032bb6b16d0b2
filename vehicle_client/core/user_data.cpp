#include "vehicle_client/user_data.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>

namespace ocp {
namespace {

// This runs once per model sample (100 Hz) and used to cost ~8.5 k instructions through fmt's
// precision formatting and a buffer copy. Now: integer arithmetic into small stack buffers,
// collected in one stack buffer and appended to `out` in one go (≈ 1 k instructions).

// Collects text in a stack buffer; appends to `out` when full and at the end.
class TextWriter {
 public:
  explicit TextWriter(std::string& out) : out_(out) { out_.clear(); }
  TextWriter(const TextWriter&) = delete;
  TextWriter& operator=(const TextWriter&) = delete;
  ~TextWriter() { flush(); }

  void put(std::string_view text) {
    if (text.size() > sizeof buffer_ - used_) {
      flush();
      if (text.size() > sizeof buffer_) {
        out_.append(text);
        return;
      }
    }
    std::memcpy(buffer_ + used_, text.data(), text.size());
    used_ += text.size();
  }
  void put(char c) { put(std::string_view(&c, 1)); }

 private:
  void flush() {
    out_.append(buffer_, used_);  // `out` keeps its capacity: no allocation in the steady state
    used_ = 0;
  }

  std::string& out_;
  char buffer_[512];
  std::size_t used_ = 0;
};

template <typename Integer>
void put_integer(Integer value, TextWriter& writer) {
  char digits[24];
  const auto result = std::to_chars(digits, digits + sizeof digits, value);
  writer.put(std::string_view(digits, static_cast<std::size_t>(result.ptr - digits)));
}

constexpr double power_of_ten(int exponent) {
  double value = 1.0;
  for (int index = 0; index < exponent; ++index) value *= 10.0;
  return value;
}

// `value` with exactly `Decimals` digits after the point, rounded half away from zero.
// Never "-0.000" (a negative value that rounds to zero prints as zero) and never the
// non-JSON "nan"/"inf" (printed as null). The rounding can differ from exact decimal rounding
// by one unit in the last place at exact binary ties — irrelevant at this resolution.
template <int Decimals>
void put_fixed(double value, TextWriter& writer) {
  static_assert(Decimals > 0 && Decimals <= 9);
  constexpr double scale = power_of_ten(Decimals);
  constexpr auto integer_scale = static_cast<std::uint64_t>(scale);
  // From 2^53 units on the integer path would lose digits. Never expected from the model;
  // the shortest round-trip form is still a bounded, valid JSON number.
  constexpr double integer_limit = 9007199254740992.0;
  if (!std::isfinite(value)) {
    writer.put("null");
    return;
  }
  const double scaled = std::fabs(value) * scale + 0.5;
  if (scaled >= integer_limit) {
    char digits[32];
    const auto result = std::to_chars(digits, digits + sizeof digits, value);
    writer.put(std::string_view(digits, static_cast<std::size_t>(result.ptr - digits)));
    return;
  }
  const auto units = static_cast<std::uint64_t>(scaled);
  if (units != 0 && value < 0.0) writer.put('-');
  put_integer(units / integer_scale, writer);
  char fraction[Decimals + 1];
  fraction[0] = '.';
  std::uint64_t rest = units % integer_scale;
  for (int index = Decimals; index > 0; --index) {
    fraction[index] = static_cast<char>('0' + rest % 10);
    rest /= 10;
  }
  writer.put(std::string_view(fraction, sizeof fraction));
}

}  // namespace

void encode_user_data(const UserDataSample& sample, std::string& out) {
  const VehicleState& vehicle = sample.vehicle;
  const SafetyOutput& safety = sample.safety;
  TextWriter writer(out);
  writer.put(R"({"speed_mps":)");
  put_fixed<3>(vehicle.speed_mps, writer);
  writer.put(R"(,"heading_deg":)");
  put_fixed<2>(vehicle.heading_deg(), writer);
  writer.put(R"(,"drive_state":")");
  writer.put(drive_state_name(safety.drive_state));
  writer.put(safety.safe_state ? R"(","safe_state":true,"safety_reasons":[)"
                               : R"(","safe_state":false,"safety_reasons":[)");
  bool first = true;
  for (std::size_t index = 0; index < safety_reason_count; ++index) {
    const auto reason = static_cast<SafetyReason>(index);
    if (!safety.reasons.contains(reason)) continue;
    // Reason names are fixed identifiers without characters that need escaping.
    writer.put(first ? "\"" : ",\"");
    writer.put(safety_reason_name(reason));
    writer.put('"');
    first = false;
  }
  writer.put(R"(],"throttle":)");
  put_fixed<3>(safety.command.throttle, writer);
  writer.put(R"(,"brake":)");
  put_fixed<3>(safety.command.brake, writer);
  writer.put(R"(,"steer":)");
  put_fixed<3>(safety.command.steer, writer);
  writer.put(R"(,"odometer_m":)");
  put_fixed<2>(vehicle.odometer_m, writer);
  writer.put(R"(,"last_latency_ms":)");
  put_integer(sample.last_latency_ms, writer);
  writer.put(R"(,"sequence":)");
  put_integer(sample.sequence, writer);
  writer.put(R"(,"timestamp_ms":)");
  put_integer(to_whole_ms(sample.timestamp), writer);
  if (sample.misbehave != nullptr && sample.misbehave->any()) {
    // describe() yields switch names and digits only: safe inside a JSON string.
    writer.put(R"(,"misbehave":")");
    writer.put(sample.misbehave->describe());
    writer.put('"');
  }
  writer.put('}');
}

}  // namespace ocp
