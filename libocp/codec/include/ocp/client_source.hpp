#pragma once
// The three operator-side sources of client data (SPEC §4.3): a :4001 TCP client, the web
// view, a plugin. Here rather than in the Player so that events can name them.
#include <string_view>

namespace ocp {

enum class ClientSource { tcp, webview, plugin };
std::string_view client_source_name(ClientSource source);  // "tcp" | "webview" | "plugin"

}  // namespace ocp
