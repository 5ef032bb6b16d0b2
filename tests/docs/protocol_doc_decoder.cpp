// Test helper for tests/docs/check_protocol_doc.py: decodes documents with the libocp codec.
// Reads documents from stdin, each a line "MESSAGE LENGTH" and then LENGTH bytes of JSON
// (newlines and all), MESSAGE one of control_message, vehicle_response, vehicle_ocp_shared,
// client_ocp_shared; writes one line per document: "ok", or "error: <detail>".
#include <iostream>
#include <string>
#include <string_view>

#include "ocp/json_codec.hpp"

namespace {

template <typename T>
std::string verdict(const ocp::Result<T>& result) {
  if (result) return "ok";
  return "error: " + result.error().message();
}

std::string decode(std::string_view message, std::string_view json) {
  if (message == "control_message") return verdict(ocp::decode_control_message(json));
  if (message == "vehicle_response") return verdict(ocp::decode_vehicle_response(json));
  if (message == "vehicle_ocp_shared") return verdict(ocp::decode_vehicle_ocp_shared(json));
  if (message == "client_ocp_shared") return verdict(ocp::decode_client_ocp_shared(json));
  return "error: unknown message kind '" + std::string(message) + "'";
}

}  // namespace

int main() {
  std::string message;
  std::size_t length = 0;
  while (std::cin >> message >> length) {
    std::cin.ignore(1);  // the newline after LENGTH
    std::string json(length, '\0');
    if (!std::cin.read(json.data(), static_cast<std::streamsize>(length))) {
      std::cout << "error: input ends inside a document\n";
      return 1;
    }
    std::cout << decode(message, json) << '\n';
  }
  return 0;
}
