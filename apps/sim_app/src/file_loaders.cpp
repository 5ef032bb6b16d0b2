#include "sim_app/file_loaders.hpp"

#include "ocp/bounded_file.hpp"

namespace ocp::sim_app {

Result<DeliveryTrace> load_delivery_trace(const std::string& path) {
  auto text = read_bounded_file(path, file_kinds::delivery_trace);
  if (!text) return text.error();
  return DeliveryTrace::parse(*text, path);
}

Result<LinkRecording> load_link_recording(const std::string& path) {
  auto text = read_bounded_file(path, file_kinds::link_recording);
  if (!text) return text.error();
  return LinkRecording::parse(*text, path);
}

Result<Recording> load_gamepad_recording(const std::string& path) {
  auto text = read_bounded_file(path, file_kinds::gamepad_script);
  if (!text) return text.error();
  return parse_recording(*text);
}

}  // namespace ocp::sim_app
