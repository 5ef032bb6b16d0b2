-- Wireshark dissector for the Oden Control Pipeline (OCP) simulator, for Wireshark/tshark 4.0
-- (Lua 5.2). Three protocols:
--   ocp_vehicle   the vehicle TCP API (Streamer, default :4000)   SPEC §2, §3
--   ocp_operator  the operator TCP API (Player, default :4001)    SPEC §2, §4
--   ocp_com       the com channel over UDP (issue #22)            libocp/com/include/ocp/com_datagram.hpp
-- Both TCP APIs are a 4-byte little-endian length prefix and a JSON payload: the payload goes to
-- Wireshark's own JSON dissector, and the OCP fields (ack_time, ack_time_mac, controller state,
-- faults, latency) are added beside it. ack_time is a u64 that must never pass through a double,
-- so the JSON numbers are read as text and converted digit by digit to UInt64.
-- Each protocol is registered on its default port (a preference) and as a heuristic, so it is
-- found on any port. Load it with `wireshark -X lua_script:scripts/wireshark/ocp.lua` or copy it
-- to ~/.local/lib/wireshark/plugins/ (docs/wireshark.md).

local MAX_PAYLOAD = 16384      -- SPEC §2: a longer frame is drained by the receiver
local COM_HEADER, COM_TAG, COM_MAX = 32, 32, 1200
local COM_MAX_FRAGMENTS = 256
local JSON_MAX_DEPTH = 64

local json_dissector = Dissector.get("json")

local p_vehicle = Proto("ocp_vehicle", "OCP vehicle API")
local p_operator = Proto("ocp_operator", "OCP operator API")
local p_com = Proto("ocp_com", "OCP com channel")

-- FaultId's order (libocp/codec/include/ocp/faults.hpp): the com channel sends the index.
local fault_names = {
  [0] = "VehicleNoResponse", [1] = "NoControlMessage", [2] = "CameraLost", [3] = "StreamerSlow",
  [4] = "HighLatency", [5] = "OperatorStationHasError", [6] = "InvalidMac", [7] = "ControlThreadChannelSlow",
  [8] = "InputLost", [9] = "NoFeedbackMessage", [10] = "VehicleControlInactive",
}
local button_names = { "a", "b", "x", "y", "left_bumper", "right_bumper", "back", "start", "guide",
  "left_thumb", "right_thumb", "dpad_up", "dpad_right", "dpad_down", "dpad_left" }
local axis_names = { "left_x", "left_y", "right_x", "right_y", "left_trigger", "right_trigger" }

---------------------------------------------------------------------------------------------
-- A small JSON reader that remembers where every value is (for highlighting) and keeps numbers
-- as their text. It returns nil for anything malformed or nested deeper than JSON_MAX_DEPTH.

local json_value   -- forward declaration: the readers are mutually recursive

local function json_skip(s, i)
  return s:find("[^ \t\r\n]", i) or (#s + 1)
end

local function json_string(s, i)
  local j = i + 1
  local parts = {}
  while j <= #s do
    local c = s:sub(j, j)
    if c == '"' then return { kind = "string", value = table.concat(parts), pos = i, last = j }, j + 1 end
    if c == "\\" then
      local e = s:sub(j + 1, j + 1)
      local simple = { ['"'] = '"', ["\\"] = "\\", ["/"] = "/", b = "\b", f = "\f", n = "\n", r = "\r", t = "\t" }
      if simple[e] then parts[#parts + 1] = simple[e]; j = j + 2
      elseif e == "u" and s:sub(j + 2, j + 5):match("^%x%x%x%x$") then parts[#parts + 1] = "?"; j = j + 6
      else return nil end
    else
      parts[#parts + 1] = c
      j = j + 1
    end
  end
  return nil
end

local function json_container(s, i, depth, closing)
  local node = { kind = closing == "}" and "object" or "array", pos = i, members = {}, items = {} }
  local j = json_skip(s, i + 1)
  if s:sub(j, j) == closing then node.last = j; return node, j + 1 end
  while true do
    local key
    if closing == "}" then
      if s:sub(j, j) ~= '"' then return nil end
      key, j = json_string(s, j)
      if not key then return nil end
      j = json_skip(s, j)
      if s:sub(j, j) ~= ":" then return nil end
      j = json_skip(s, j + 1)
    end
    local value
    value, j = json_value(s, j, depth + 1)
    if not value then return nil end
    if key then node.members[key.value] = value else node.items[#node.items + 1] = value end
    j = json_skip(s, j)
    local c = s:sub(j, j)
    if c == closing then node.last = j; return node, j + 1 end
    if c ~= "," then return nil end
    j = json_skip(s, j + 1)
  end
end

json_value = function(s, i, depth)
  if depth > JSON_MAX_DEPTH then return nil end
  local c = s:sub(i, i)
  if c == "{" then return json_container(s, i, depth, "}") end
  if c == "[" then return json_container(s, i, depth, "]") end
  if c == '"' then return json_string(s, i) end
  local number = s:match("^-?%d+%.?%d*[eE]?[-+]?%d*", i)
  if number and #number > 0 then
    return { kind = "number", value = number, pos = i, last = i + #number - 1 }, i + #number
  end
  for word, value in pairs({ ["true"] = true, ["false"] = false, null = "null" }) do
    if s:sub(i, i + #word - 1) == word then
      return { kind = word == "null" and "null" or "bool", value = value, pos = i, last = i + #word - 1 }, i + #word
    end
  end
  return nil
end

local function json_parse(s)
  local node, j = json_value(s, json_skip(s, 1), 0)
  if not node or json_skip(s, j) <= #s then return nil end
  return node
end

-- A non-negative JSON integer as UInt64, exactly; nil when it is not one or exceeds 2^64-1.
local function json_uint64(node)
  if not node or node.kind ~= "number" or not node.value:match("^%d+$") or #node.value > 20 then return nil end
  local value, max = UInt64.new(0), UInt64.max()
  for digit in node.value:gmatch("%d") do
    local d = tonumber(digit)
    if value > (max - d) / 10 then return nil end   -- past 2^64-1
    value = value * 10 + d
  end
  return value
end

---------------------------------------------------------------------------------------------
-- The fields of the two TCP APIs (one set per protocol: a field belongs to one protocol).

local function tcp_fields(abbr)
  local f = {
    length = ProtoField.uint32(abbr .. ".length", "Length prefix", base.DEC, nil, nil, "4-byte little-endian payload length"),
    message = ProtoField.string(abbr .. ".message", "Message"),
    oversized = ProtoField.bool(abbr .. ".oversized", "Oversized (> 16 KiB: the receiver drains it)"),
    vehicle = ProtoField.string(abbr .. ".vehicle", "Vehicle"),
    ack_time = ProtoField.uint64(abbr .. ".ack_time", "ack_time", base.DEC),
    ack_time_mac = ProtoField.uint32(abbr .. ".ack_time_mac", "ack_time_mac", base.DEC),
    ack_time_returned = ProtoField.uint64(abbr .. ".ack_time_returned", "ack_time_returned", base.DEC),
    ack_time_mac_returned = ProtoField.uint32(abbr .. ".ack_time_mac_returned", "ack_time_mac_returned", base.DEC),
    controller = ProtoField.string(abbr .. ".controller", "Controller state"),
    fault = ProtoField.bool(abbr .. ".fault", "Fault"),
    fault_reason = ProtoField.string(abbr .. ".fault_reason", "Fault reason"),
    sender_fault = ProtoField.string(abbr .. ".sender_fault", "Sender fault"),
    receiver_fault = ProtoField.string(abbr .. ".receiver_fault", "Receiver fault"),
    latency = ProtoField.uint32(abbr .. ".latency", "Latency (ms)"),
    missing_cameras = ProtoField.string(abbr .. ".missing_cameras", "Missing cameras"),
  }
  local list = {}
  for _, field in pairs(f) do list[#list + 1] = field end
  return f, list
end

local vf, vehicle_field_list = tcp_fields("ocp_vehicle")
local of, operator_field_list = tcp_fields("ocp_operator")
of.latency_roundtrip = ProtoField.uint32("ocp_operator.message_latency_roundtrip", "message_latency_roundtrip (ms)")
of.ping_latency = ProtoField.uint32("ocp_operator.ping_latency_ms", "ping_latency_ms")
of.active_vehicle = ProtoField.string("ocp_operator.active_vehicle", "active_vehicle")
of.is_monitor = ProtoField.bool("ocp_operator.is_monitor", "is_monitor")
operator_field_list[#operator_field_list + 1] = of.latency_roundtrip
operator_field_list[#operator_field_list + 1] = of.ping_latency
operator_field_list[#operator_field_list + 1] = of.active_vehicle
operator_field_list[#operator_field_list + 1] = of.is_monitor
p_vehicle.fields = vehicle_field_list
p_operator.fields = operator_field_list

-- The payload's range for a parsed node (offsets are 1-based in Lua, 0-based in a tvb).
local function node_range(payload_tvb, node)
  return payload_tvb(node.pos - 1, node.last - node.pos + 1)
end

-- "default (safe)", "null" or the pressed buttons and the axes that are not at rest.
local function controller_text(node)
  if not node or node.kind == "null" then return "null (no gamepad path)" end
  if node.kind ~= "object" then return "invalid" end
  local buttons, axes = node.members.buttons, node.members.axes
  local pressed, moved = {}, {}
  for _, name in ipairs(button_names) do
    local b = buttons and buttons.members and buttons.members[name]
    if b and b.value == true then pressed[#pressed + 1] = name end
  end
  for _, name in ipairs(axis_names) do
    local a = axes and axes.members and axes.members[name]
    local rest = name:match("trigger") and -1 or 0
    local value = a and a.kind == "number" and tonumber(a.value)
    if value and value ~= rest then moved[#moved + 1] = string.format("%s=%.3g", name, value) end
  end
  if #pressed == 0 and #moved == 0 then return "default (safe): no button, sticks 0, triggers -1" end
  return string.format("buttons [%s] axes [%s]", table.concat(pressed, " "), table.concat(moved, " "))
end

local function add_uint64(tree, field, payload_tvb, node)
  local value = json_uint64(node)
  if value then tree:add(field, node_range(payload_tvb, node), value) end
  return value
end

local function add_uint32(tree, field, payload_tvb, node)
  local value = json_uint64(node)
  if value and value <= UInt64.new(0xffffffff) then tree:add(field, node_range(payload_tvb, node), value:tonumber()) end
  return value
end

local function add_string_list(tree, field, payload_tvb, node)
  if not node or node.kind ~= "array" then return {} end
  local names = {}
  for _, item in ipairs(node.items) do
    if item.kind == "string" then
      tree:add(field, node_range(payload_tvb, item), item.value)
      names[#names + 1] = item.value
    end
  end
  return names
end

---------------------------------------------------------------------------------------------
-- The vehicle API: OcpControlMessage (Streamer → vehicle) and VehicleResponseMessage.

local function vehicle_fields(tree, payload_tvb, root, pinfo)
  local m = root.members
  local is_control = m.telemetry ~= nil or m.controller ~= nil
  local name = is_control and "OcpControlMessage" or "VehicleResponseMessage"
  tree:add(vf.message, name)
  local ack = add_uint64(tree, vf.ack_time, payload_tvb, m.ack_time)
  add_uint32(tree, vf.ack_time_mac, payload_tvb, m.ack_time_mac)
  local summary = name .. (ack and (" ack_time=" .. tostring(ack)) or "")
  if is_control then
    tree:add(vf.controller, m.controller and node_range(payload_tvb, m.controller) or payload_tvb(0, 0),
             controller_text(m.controller))
    local t = m.telemetry and m.telemetry.members or {}
    if t.latency then add_uint32(tree, vf.latency, payload_tvb, t.latency) end
    if t.fault then tree:add(vf.fault, node_range(payload_tvb, t.fault), t.fault.value == true) end
    if t.fault_reason and t.fault_reason.kind == "string" then
      tree:add(vf.fault_reason, node_range(payload_tvb, t.fault_reason), t.fault_reason.value)
      if t.fault_reason.value ~= "" then summary = summary .. " faults: " .. t.fault_reason.value end
    end
    add_string_list(tree, vf.missing_cameras, payload_tvb, t.missing_cameras)
  end
  return summary
end

---------------------------------------------------------------------------------------------
-- The operator API: VehicleOcpShared (Player → client) and ClientOcpShared (client → Player).

local function feedback_entry(tree, payload_tvb, vehicle, entry)
  local sub = tree:add(of.vehicle, node_range(payload_tvb, entry), vehicle)
  local m = entry.members or {}
  add_uint64(sub, of.ack_time, payload_tvb, m.ack_time)
  add_uint32(sub, of.ack_time_mac, payload_tvb, m.ack_time_mac)
  if m.message_latency_roundtrip and m.message_latency_roundtrip.kind == "number" then
    add_uint32(sub, of.latency_roundtrip, payload_tvb, m.message_latency_roundtrip)
  end
  if m.ping_latency_ms then add_uint32(sub, of.ping_latency, payload_tvb, m.ping_latency_ms) end
  local sender = add_string_list(sub, of.sender_fault, payload_tvb, m.sender_fault)
  local receiver = add_string_list(sub, of.receiver_fault, payload_tvb, m.receiver_fault)
  add_string_list(sub, of.missing_cameras, payload_tvb, m.missing_cameras)
  if m.last_remote_input then
    sub:add(of.controller, node_range(payload_tvb, m.last_remote_input), controller_text(m.last_remote_input))
  end
  if m.is_monitor and m.is_monitor.kind == "bool" then
    sub:add(of.is_monitor, node_range(payload_tvb, m.is_monitor), m.is_monitor.value)
  end
  local faults = {}
  for _, f in ipairs(sender) do faults[#faults + 1] = f end
  for _, f in ipairs(receiver) do faults[#faults + 1] = f end
  return #faults > 0 and (vehicle .. ": " .. table.concat(faults, ",")) or nil
end

local function client_entry(tree, payload_tvb, vehicle, entry)
  local sub = tree:add(of.vehicle, node_range(payload_tvb, entry), vehicle)
  local m = entry.members or {}
  add_uint64(sub, of.ack_time_returned, payload_tvb, m.ack_time_returned)
  add_uint32(sub, of.ack_time_mac_returned, payload_tvb, m.ack_time_mac_returned)
end

local function sorted_keys(members)
  local keys = {}
  for k in pairs(members or {}) do keys[#keys + 1] = k end
  table.sort(keys)
  return keys
end

local function operator_fields(tree, payload_tvb, root)
  local m = root.members
  if m.vehicle_feedback and m.vehicle_feedback.kind == "object" then
    tree:add(of.message, "VehicleOcpShared")
    local faults = {}
    for _, vehicle in ipairs(sorted_keys(m.vehicle_feedback.members)) do
      faults[#faults + 1] = feedback_entry(tree, payload_tvb, vehicle, m.vehicle_feedback.members[vehicle])
    end
    if m.last_input then
      tree:add(of.controller, node_range(payload_tvb, m.last_input), controller_text(m.last_input))
    end
    return "VehicleOcpShared" .. (#faults > 0 and (" faults: " .. table.concat(faults, "; ")) or "")
  end
  local keep_alive = m.active_vehicle == nil and m.client_user_data == nil
  tree:add(of.message, keep_alive and "ClientOcpShared (keep-alive)" or "ClientOcpShared")
  if m.active_vehicle and m.active_vehicle.kind == "string" then
    tree:add(of.active_vehicle, node_range(payload_tvb, m.active_vehicle), m.active_vehicle.value)
  end
  if m.client_user_data and m.client_user_data.kind == "object" then
    for _, vehicle in ipairs(sorted_keys(m.client_user_data.members)) do
      client_entry(tree, payload_tvb, vehicle, m.client_user_data.members[vehicle])
    end
  end
  return keep_alive and "ClientOcpShared (keep-alive)" or "ClientOcpShared"
end

---------------------------------------------------------------------------------------------
-- One length-prefixed frame of either TCP API, and TCP reassembly around it.

local function frame_length(tvb, pinfo, offset)
  return 4 + tvb(offset, 4):le_uint()
end

local function make_frame_dissector(proto, fields, add_message_fields, label)
  return function(tvb, pinfo, tree)
    pinfo.cols.protocol = label
    local length = tvb(0, 4):le_uint()
    local subtree = tree:add(proto, tvb(), string.format("%s, %d bytes", proto.description, length))
    subtree:add_le(fields.length, tvb(0, 4))
    if length > MAX_PAYLOAD then subtree:add(fields.oversized, true) end
    if length == 0 then return tvb:len() end
    local payload_tvb = tvb(4, length):tvb()
    local root = json_parse(payload_tvb:raw())
    local summary
    if root and root.kind == "object" then
      summary = add_message_fields(subtree, payload_tvb, root, pinfo)
    else
      subtree:add_expert_info(PI_MALFORMED, PI_ERROR, "not a JSON object: the receiver closes the connection")
      summary = "malformed"
    end
    local info = tostring(pinfo.cols.info)
    json_dissector:call(payload_tvb, pinfo, subtree)
    pinfo.cols.protocol = label     -- the JSON dissector set its own name and info
    pinfo.cols.info = info .. (info == "" and "" or "; ") .. summary
    return tvb:len()
  end
end

local dissect_vehicle_frame = make_frame_dissector(p_vehicle, vf, vehicle_fields, "OCP-VEH")
local dissect_operator_frame = make_frame_dissector(p_operator, of, operator_fields, "OCP-OPR")

p_vehicle.dissector = function(tvb, pinfo, tree)
  pinfo.cols.info = ""
  dissect_tcp_pdus(tvb, tree, 4, frame_length, dissect_vehicle_frame, true)
  return tvb:len()
end
p_operator.dissector = function(tvb, pinfo, tree)
  pinfo.cols.info = ""
  dissect_tcp_pdus(tvb, tree, 4, frame_length, dissect_operator_frame, true)
  return tvb:len()
end

-- Which API a segment that starts a frame belongs to, from the keys it shows (nil: not OCP, or
-- not telling yet: a keep-alive {} says nothing).
local function classify_tcp(tvb)
  if tvb:len() < 6 then return nil end
  local length = tvb(0, 4):le_uint()
  if length < 2 or length > MAX_PAYLOAD then return nil end
  local head = tvb:raw(4, math.min(tvb:len() - 4, length))
  if not head:match("^%s*{") then return nil end
  if head:find('"vehicle_feedback"', 1, true) then return "operator" end
  if head:find('"telemetry"', 1, true) or head:find('"ack_time_mac"', 1, true) then return "vehicle" end
  if head:find('"active_vehicle"', 1, true) or head:find('"ack_time_returned"', 1, true) then return "operator" end
  return nil
end

local function heuristic_for(proto, kind)
  return function(tvb, pinfo, tree)
    if classify_tcp(tvb) ~= kind then return false end
    pinfo.conversation = proto     -- the rest of this connection, both directions
    proto.dissector(tvb, pinfo, tree)
    return true
  end
end

---------------------------------------------------------------------------------------------
-- The com channel over UDP: header, tag, reassembly, and the body of every LinkMessage.

-- 6 and 7: the session handshake (libocp/com/include/ocp/com_session.hpp): a Hello with the Player's
-- nonce, a Welcome with both; the session's keys come from them and the key file (HKDF).
local kind_names = { [1] = "OperatorControl", [2] = "StreamerFeedback", [3] = "VideoFrame", [4] = "Ping", [5] = "Pong",
                     [6] = "Hello (handshake)", [7] = "Welcome (handshake)" }
local cf = {
  magic = ProtoField.string("ocp_com.magic", "Magic"),
  version = ProtoField.uint8("ocp_com.version", "Version"),
  kind = ProtoField.uint8("ocp_com.kind", "Kind", base.DEC, kind_names),
  session = ProtoField.uint64("ocp_com.session", "Session", base.HEX),
  sequence = ProtoField.uint64("ocp_com.sequence", "Sequence", base.DEC),
  message = ProtoField.uint32("ocp_com.message", "Message number"),
  fragment = ProtoField.uint16("ocp_com.fragment", "Fragment index"),
  fragments = ProtoField.uint16("ocp_com.fragments", "Fragments"),
  body_length = ProtoField.uint16("ocp_com.body_length", "Body length"),
  reserved = ProtoField.uint16("ocp_com.reserved", "Reserved"),
  body = ProtoField.bytes("ocp_com.body", "Body"),
  tag = ProtoField.bytes("ocp_com.tag", "HMAC-SHA256 tag (not verified: the key is not known here)"),
  reassembled_in = ProtoField.framenum("ocp_com.reassembled_in", "Reassembled in"),
  fragment_frames = ProtoField.string("ocp_com.fragment_frames", "Fragments in frames"),
  reassembled_length = ProtoField.uint32("ocp_com.reassembled_length", "Reassembled length"),
  link_sequence = ProtoField.uint64("ocp_com.link_sequence", "Message sequence"),
  controller = ProtoField.string("ocp_com.controller", "Controller state"),
  buttons = ProtoField.uint16("ocp_com.buttons", "Buttons", base.HEX),
  axis = ProtoField.double("ocp_com.axis", "Axis"),
  client_user_data = ProtoField.string("ocp_com.client_user_data", "client_user_data"),
  ack_time = ProtoField.uint64("ocp_com.ack_time", "ack_time", base.DEC),
  ack_time_mac = ProtoField.uint32("ocp_com.ack_time_mac", "ack_time_mac", base.DEC),
  fault = ProtoField.uint8("ocp_com.fault", "Fault", base.DEC, fault_names),
  latency = ProtoField.uint64("ocp_com.latency_ms", "Latency (ms)"),
  missing_camera = ProtoField.string("ocp_com.missing_camera", "Missing camera"),
  lat = ProtoField.double("ocp_com.lat", "lat"),
  lon = ProtoField.double("ocp_com.lon", "lon"),
  vehicle_user_data = ProtoField.string("ocp_com.vehicle_user_data", "vehicle user_data"),
  vehicle_data_age = ProtoField.int64("ocp_com.vehicle_data_age_us", "Vehicle data age (µs)"),
  camera = ProtoField.string("ocp_com.camera", "Camera"),
  frame_number = ProtoField.uint64("ocp_com.frame_number", "Frame number"),
  size_bytes = ProtoField.uint32("ocp_com.size_bytes", "Frame size (bytes)"),
  ping_id = ProtoField.uint64("ocp_com.ping_id", "Ping id"),
  sent_at = ProtoField.int64("ocp_com.sent_at_us", "Ping sent at (µs, sender's clock)"),
  player_nonce = ProtoField.bytes("ocp_com.player_nonce", "Player's nonce"),
  streamer_nonce = ProtoField.bytes("ocp_com.streamer_nonce", "Streamer's nonce"),
}
local com_field_list = {}
for _, field in pairs(cf) do com_field_list[#com_field_list + 1] = field end
p_com.fields = com_field_list

p_com.prefs.udp_port = Pref.uint("UDP port", 5000, "the com channel's port (it is also found by heuristic)")

-- A cursor over a body tvb; every read checks what is left and raises an error otherwise (the
-- caller catches it with pcall and marks the body malformed).
local function reader(tvb)
  local r = { tvb = tvb, at = 0 }
  function r.take(n)
    if r.at + n > tvb:len() then error("body too short", 0) end
    local range = tvb(r.at, n)
    r.at = r.at + n
    return range
  end
  function r.flag(tree, name)
    local range = r.take(1)
    local value = range:uint()
    if value > 1 then error("flag " .. name .. " is " .. value, 0) end
    return value == 1
  end
  function r.text(tree, field)
    local length = r.take(4):le_uint()
    local range = r.take(length)
    tree:add(field, range, length > 0 and range:raw() or "")
    return length > 0 and range:raw() or ""
  end
  return r
end

local function read_controller(r, tree)
  local buttons_range = r.take(2)
  local bits = buttons_range:le_uint()
  local pressed, moved, axes = {}, {}, {}
  for i, name in ipairs(button_names) do
    if bit32.band(bits, bit32.lshift(1, i - 1)) ~= 0 then pressed[#pressed + 1] = name end
  end
  for i, name in ipairs(axis_names) do
    axes[i] = r.take(8)
    local value = axes[i]:le_float()
    local rest = name:match("trigger") and -1 or 0
    if value ~= rest then moved[#moved + 1] = string.format("%s=%.3g", name, value) end
  end
  local text = (#pressed == 0 and #moved == 0) and "default (safe): no button, sticks 0, triggers -1"
    or string.format("buttons [%s] axes [%s]", table.concat(pressed, " "), table.concat(moved, " "))
  local whole = r.tvb(buttons_range:offset(), 2 + 8 * #axis_names)
  local sub = tree:add(cf.controller, whole, text)
  sub:add_le(cf.buttons, buttons_range)
  for i, name in ipairs(axis_names) do
    sub:add_le(cf.axis, axes[i]):set_text(string.format("%s: %g", name, axes[i]:le_float()))
  end
  return text
end

local function read_ack(r, tree)
  local time_range, mac_range = r.take(8), r.take(4)
  tree:add_le(cf.ack_time, time_range)
  tree:add_le(cf.ack_time_mac, mac_range)
  return time_range:le_uint64()
end

local function read_faults(r, tree, label)
  local count = r.take(1):uint()
  local names = {}
  for _ = 1, count do
    local range = r.take(1)
    local item = tree:add(cf.fault, range)
    item:prepend_text(label .. " ")
    names[#names + 1] = fault_names[range:uint()] or ("unknown " .. range:uint())
  end
  return names
end

local function body_operator_control(r, tree)
  tree:add_le(cf.link_sequence, r.take(8))
  local summary = "OperatorControl"
  if r.flag(tree, "controller") then summary = summary .. " controller: " .. read_controller(r, tree) end
  if r.flag(tree, "client_user_data") then r.text(tree, cf.client_user_data) end
  if r.flag(tree, "returned_ack") then summary = summary .. " returned ack_time=" .. tostring(read_ack(r, tree)) end
  local faults = read_faults(r, tree, "Sender")
  if #faults > 0 then summary = summary .. " sender faults: " .. table.concat(faults, ",") end
  return summary
end

local function body_streamer_feedback(r, tree)
  tree:add_le(cf.link_sequence, r.take(8))
  local faults = read_faults(r, tree, "Receiver")
  local summary = "StreamerFeedback"
  if r.flag(tree, "latency") then
    local range = r.take(8)
    tree:add_le(cf.latency, range)
    summary = summary .. " latency=" .. tostring(range:le_uint64()) .. " ms"
  end
  for _ = 1, r.take(1):uint() do r.text(tree, cf.missing_camera) end
  if r.flag(tree, "vehicle_data") then
    if r.flag(tree, "pos") then
      tree:add_le(cf.lat, r.take(8))
      tree:add_le(cf.lon, r.take(8))
    end
    r.text(tree, cf.vehicle_user_data)
  end
  if r.flag(tree, "vehicle_data_age") then tree:add_le(cf.vehicle_data_age, r.take(8)) end
  if r.flag(tree, "last_remote_input") then read_controller(r, tree) end
  if #faults > 0 then summary = summary .. " receiver faults: " .. table.concat(faults, ",") end
  return summary
end

local function body_video_frame(r, tree)
  local camera = r.text(tree, cf.camera)
  local number_range = r.take(8)
  tree:add_le(cf.frame_number, number_range)
  local summary = string.format("VideoFrame %s #%s", camera, tostring(number_range:le_uint64()))
  if r.flag(tree, "sei") then summary = summary .. " SEI ack_time=" .. tostring(read_ack(r, tree)) end
  local size_range = r.take(4)
  tree:add_le(cf.size_bytes, size_range)
  return summary .. string.format(" %d bytes", size_range:le_uint())
end

local function body_ping(r, tree, name)
  local id = r.take(8)
  tree:add_le(cf.ping_id, id)
  tree:add_le(cf.sent_at, r.take(8))
  return name .. " " .. tostring(id:le_uint64())
end

local function body_handshake(r, tree, name)
  tree:add(cf.player_nonce, r.take(32))
  if name == "Welcome" then tree:add(cf.streamer_nonce, r.take(32)) end
  return name .. " (session handshake)"
end

local body_readers = {
  [1] = body_operator_control,
  [2] = body_streamer_feedback,
  [3] = body_video_frame,
  [4] = function(r, tree) return body_ping(r, tree, "Ping") end,
  [5] = function(r, tree) return body_ping(r, tree, "Pong") end,
  [6] = function(r, tree) return body_handshake(r, tree, "Hello") end,
  [7] = function(r, tree) return body_handshake(r, tree, "Welcome") end,
}

local function dissect_body(kind, body_tvb, tree)
  local r = reader(body_tvb)
  local ok, summary = pcall(body_readers[kind], r, tree)
  if not ok then
    tree:add_expert_info(PI_MALFORMED, PI_ERROR, "malformed body: " .. tostring(summary))
    return "malformed " .. (kind_names[kind] or "?")
  end
  if kind ~= 3 and r.at ~= body_tvb:len() then
    tree:add_expert_info(PI_MALFORMED, PI_WARN, "bytes after the message's fields")
  end
  return summary
end

-- Reassembly state, rebuilt on every (re)load of a capture: the first pass records each
-- fragment, later passes (the GUI, tshark -2) find the result by frame number.
-- At most MAX_PARTIALS messages wait for their missing pieces (junk or heavy loss cannot grow
-- this without bound); past that the oldest is forgotten, as the programs do.
local MAX_PARTIALS = 256
local partials, partial_order, reassembled, reassembled_in, fragment_frames = {}, {}, {}, {}, {}
p_com.init = function()
  partials, partial_order, reassembled, reassembled_in, fragment_frames = {}, {}, {}, {}, {}
end

local function remember_fragment(pinfo, key, index, count, piece)
  local partial = partials[key]
  if not partial or partial.count ~= count then
    partial = { count = count, pieces = {}, received = 0, frames = {} }
    partials[key] = partial
    partial_order[#partial_order + 1] = key
    if #partial_order > MAX_PARTIALS then partials[table.remove(partial_order, 1)] = nil end
  end
  if partial.pieces[index] then return end            -- a duplicate
  partial.pieces[index] = piece
  partial.received = partial.received + 1
  partial.frames[#partial.frames + 1] = pinfo.number
  if partial.received < count then return end
  local ordered = {}
  for i = 0, count - 1 do ordered[#ordered + 1] = partial.pieces[i] end
  reassembled[pinfo.number] = table.concat(ordered)
  fragment_frames[pinfo.number] = table.concat(partial.frames, ",")
  for _, frame in ipairs(partial.frames) do reassembled_in[frame] = pinfo.number end
  partials[key] = nil
end

local function com_header(tvb, tree)
  tree:add(cf.magic, tvb(0, 2))
  tree:add(cf.version, tvb(2, 1))
  tree:add(cf.kind, tvb(3, 1))
  tree:add_le(cf.session, tvb(4, 8))
  tree:add_le(cf.sequence, tvb(12, 8))
  tree:add_le(cf.message, tvb(20, 4))
  tree:add_le(cf.fragment, tvb(24, 2))
  tree:add_le(cf.fragments, tvb(26, 2))
  tree:add_le(cf.body_length, tvb(28, 2))
  tree:add_le(cf.reserved, tvb(30, 2))
end

local function com_looks_valid(tvb)
  local length = tvb:len()
  if length < COM_HEADER + COM_TAG or length > COM_MAX then return false end
  if tvb:raw(0, 2) ~= "OC" or tvb(2, 1):uint() ~= 2 then return false end
  local kind = tvb(3, 1):uint()
  local fragment, fragments = tvb(24, 2):le_uint(), tvb(26, 2):le_uint()
  return kind >= 1 and kind <= 7 and fragments >= 1 and fragments <= COM_MAX_FRAGMENTS and fragment < fragments
    and tvb(30, 2):le_uint() == 0 and COM_HEADER + tvb(28, 2):le_uint() + COM_TAG == length
end

p_com.dissector = function(tvb, pinfo, tree)
  if not com_looks_valid(tvb) then return 0 end
  pinfo.cols.protocol = "OCP-COM"
  local kind = tvb(3, 1):uint()
  local fragment, fragments, body_length = tvb(24, 2):le_uint(), tvb(26, 2):le_uint(), tvb(28, 2):le_uint()
  local subtree = tree:add(p_com, tvb(), "OCP com channel, " .. (kind_names[kind] or "?"))
  com_header(tvb, subtree)
  subtree:add(cf.body, tvb(COM_HEADER, body_length))
  subtree:add(cf.tag, tvb(COM_HEADER + body_length, COM_TAG))
  local info
  if fragments == 1 then
    info = dissect_body(kind, tvb(COM_HEADER, body_length):tvb(), subtree)
  else
    if not pinfo.visited then
      local key = tostring(tvb(4, 8):le_uint64()) .. ":" .. tvb(20, 4):le_uint()
      remember_fragment(pinfo, key, fragment, fragments, tvb:raw(COM_HEADER, body_length))
    end
    info = string.format("%s fragment %d/%d of message %d", kind_names[kind], fragment + 1, fragments,
                         tvb(20, 4):le_uint())
    local whole = reassembled[pinfo.number]
    if whole then
      local whole_tvb = ByteArray.new(whole, true):tvb("Reassembled OCP message")
      subtree:add(cf.reassembled_length, whole_tvb(), whole_tvb:len())
      subtree:add(cf.fragment_frames, fragment_frames[pinfo.number])
      info = dissect_body(kind, whole_tvb, subtree) .. string.format(" (reassembled from %d datagrams)", fragments)
    elseif reassembled_in[pinfo.number] and reassembled_in[pinfo.number] ~= pinfo.number then
      subtree:add(cf.reassembled_in, reassembled_in[pinfo.number])
    end
  end
  pinfo.cols.info = info
  return tvb:len()
end

local function com_heuristic(tvb, pinfo, tree)
  if not com_looks_valid(tvb) then return false end
  p_com.dissector(tvb, pinfo, tree)
  return true
end

---------------------------------------------------------------------------------------------
-- Registration: default ports (preferences) and heuristics.

p_vehicle.prefs.tcp_port = Pref.uint("TCP port", 4000, "the vehicle API port (it is also found by heuristic)")
p_operator.prefs.tcp_port = Pref.uint("TCP port", 4001, "the operator API port (it is also found by heuristic)")

local registered = {}
local function register_port(table_name, proto, port)
  local key = table_name .. proto.name
  local dissectors = DissectorTable.get(table_name)
  if registered[key] then dissectors:remove(registered[key], proto) end
  if port > 0 then dissectors:add(port, proto) end
  registered[key] = port > 0 and port or nil
end

p_vehicle.prefs_changed = function() register_port("tcp.port", p_vehicle, p_vehicle.prefs.tcp_port) end
p_operator.prefs_changed = function() register_port("tcp.port", p_operator, p_operator.prefs.tcp_port) end
p_com.prefs_changed = function() register_port("udp.port", p_com, p_com.prefs.udp_port) end

register_port("tcp.port", p_vehicle, 4000)
register_port("tcp.port", p_operator, 4001)
register_port("udp.port", p_com, 5000)
p_vehicle:register_heuristic("tcp", heuristic_for(p_vehicle, "vehicle"))
p_operator:register_heuristic("tcp", heuristic_for(p_operator, "operator"))
p_com:register_heuristic("udp", com_heuristic)
