// Static file resolution and the wire-protocol helpers of the web view, without sockets.
#include <gtest/gtest.h>

#include "player_app/vehicle_tcp_option.hpp"
#include "player_app/webview/messages.hpp"
#include "player_app/webview/static_files.hpp"
#include "webview_fixture.hpp"

namespace ocp::webview {
namespace {

TEST(StaticFiles, FolderServesItsIndexAndQueriesAreIgnored) {
  testing::TempWebRoot web;
  auto file = resolve_static_file(web.root, "/");
  ASSERT_EQ(file.outcome, FileLookup::found);
  EXPECT_EQ(file.path.filename(), "index.html");
  file = resolve_static_file(web.root, "/app/main.js?x=1#top");
  ASSERT_EQ(file.outcome, FileLookup::found);
  EXPECT_EQ(file.path.filename(), "main.js");
  EXPECT_EQ(resolve_static_file(web.root, "/app/%6dain.js").outcome, FileLookup::found);   // %6d = m
  EXPECT_EQ(resolve_static_file(web.root, "/app").outcome, FileLookup::not_found);        // no index.html
  EXPECT_EQ(resolve_static_file(web.root, "/nope.js").outcome, FileLookup::not_found);
}

TEST(StaticFiles, TraversalIsRefusedBeforeTheFileSystemIsAsked) {
  testing::TempWebRoot web;
  for (const char* target : {"/../secret.txt", "/app/../../secret.txt", "/%2e%2e/secret.txt", "/%2E%2E%2Fsecret.txt",
                             "/./index.html", "/..\\secret.txt", "/a%00b", "/link.txt"}) {
    EXPECT_EQ(resolve_static_file(web.root, target).outcome, FileLookup::refused) << target;
  }
  EXPECT_EQ(resolve_static_file(web.root, "/%zz").outcome, FileLookup::bad_request);
  EXPECT_EQ(resolve_static_file(web.root, "/%2").outcome, FileLookup::bad_request);
  EXPECT_EQ(resolve_static_file(web.root, "index.html").outcome, FileLookup::bad_request);
}

TEST(StaticFiles, ContentTypes) {
  EXPECT_EQ(content_type_for("a/index.html"), "text/html; charset=utf-8");
  EXPECT_EQ(content_type_for("x.JS"), "text/javascript; charset=utf-8");
  EXPECT_EQ(content_type_for("x.css"), "text/css; charset=utf-8");
  EXPECT_EQ(content_type_for("x.svg"), "image/svg+xml");
  EXPECT_EQ(content_type_for("x.png"), "image/png");
  EXPECT_EQ(content_type_for("x.unknown"), "application/octet-stream");
  EXPECT_EQ(content_type_for("Makefile"), "application/octet-stream");
}

TEST(Envelope, ParsesNameAndKeepsIntegersExact) {
  auto message = parse_envelope(R"({"name":"ocp_client_user_data","data":{"n":18446744073709551615,"m":9007199254740993}})");
  ASSERT_TRUE(message.ok()) << message.error().message();
  EXPECT_EQ(message->name, "ocp_client_user_data");
  EXPECT_EQ(message->data_json, R"({"n":18446744073709551615,"m":9007199254740993})");
  EXPECT_FALSE(parse_envelope("nope").ok());
  EXPECT_FALSE(parse_envelope("[1]").ok());
  EXPECT_FALSE(parse_envelope(R"({"name":1,"data":{}})").ok());
  EXPECT_FALSE(parse_envelope(R"({"name":"x"})").ok());
  EXPECT_FALSE(parse_envelope(std::string(100'000, '[')).ok());   // deep nesting: an error, no crash
  EXPECT_EQ(make_envelope("a", "{}"), R"({"name":"a","data":{}})");
}

TEST(Envelope, KeepAliveIsAMessageThatNamesNoVehicle) {
  ClientOcpShared data;
  EXPECT_TRUE(is_keep_alive(data));
  data.client_user_data["truck-1"] = {};
  EXPECT_FALSE(is_keep_alive(data));   // SPEC §4.2 Decision: a bare entry still gets its pair
  data.client_user_data["truck-1"].ocp_disable_gamepad = false;
  EXPECT_FALSE(is_keep_alive(data));
  ClientOcpShared selecting;
  selecting.active_vehicle = "truck-1";
  EXPECT_FALSE(is_keep_alive(selecting));
}

TEST(Envelope, StatusJson) {
  Status status;
  status.vehicles = {"a", "b"};
  EXPECT_EQ(encode_status(status),
            R"({"locked_source":null,"client_data_stopped":false,"active_vehicle":null,"vehicles":["a","b"],"webview_clients":0,)"
            R"("loop_not_closed":{}})");
  status.locked_source = "webview";
  status.client_data_stopped = true;
  EXPECT_NE(encode_status(status).find(R"("locked_source":"webview","client_data_stopped":true)"), std::string::npos);
  // Why a vehicle's loop does not close (the Streamer's hint), escaped as JSON.
  status.loop_not_closed["a"] = R"(ack_time "differs" by 1)";
  EXPECT_NE(encode_status(status).find(R"("loop_not_closed":{"a":"ack_time \"differs\" by 1"})"), std::string::npos)
      << encode_status(status);
}

TEST(VehicleTcpOption, ParsesAndValidates) {
  const std::vector<std::string> vehicles{"truck-1", "truck-2"};
  auto ports = parse_vehicle_tcp({"truck-1=4000", "truck-2=0"}, vehicles);
  ASSERT_TRUE(ports.ok());
  EXPECT_EQ(ports->at("truck-1"), 4000);
  EXPECT_EQ(ports->at("truck-2"), 0);
  EXPECT_NE(parse_vehicle_tcp({"truck-9=4000"}, vehicles).error().detail.find("unknown vehicle 'truck-9'"),
            std::string::npos);
  for (const char* bad : {"truck-1", "=4000", "truck-1=", "truck-1=-1", "truck-1=65536", "truck-1=nan", "truck-1=40 00"}) {
    EXPECT_FALSE(parse_vehicle_tcp({bad}, vehicles).ok()) << bad;
  }
  EXPECT_NE(parse_vehicle_tcp({"truck-1=1", "truck-1=2"}, vehicles).error().detail.find("given twice"), std::string::npos);
}

}  // namespace
}  // namespace ocp::webview
