// A tiny vehicle integration for the browser test, speaking the vehicle-side TCP API (SPEC §2,
// §3): 4-byte little-endian length + JSON. It echoes every control message's ack pair at once
// (copied as text, so u64 values above 2^53 stay exact), reports a position that moves with
// the commanded throttle and steer, and records every client_user_data it receives.
import net from "node:net";

export class FakeVehicle {
  constructor(port) {
    this.port = port;
    this.controls = 0;
    this.clientUserData = [];      // parsed client_user_data objects, in arrival order
    this.position = { lat: 57.7089, lon: 11.9746 };
    this.heading = 0;
    this.socket = null;
    this.buffer = Buffer.alloc(0);
    this.roundAckTime = false;     // echo ack_time as a double would hold it (a client's bug)
  }

  connect() {
    return new Promise((resolve, reject) => {
      this.socket = net.connect({ host: "127.0.0.1", port: this.port }, resolve);
      this.socket.setNoDelay(true);
      this.socket.once("error", reject);
      this.socket.on("data", (chunk) => this.onData(chunk));
    });
  }

  close() {
    if (this.socket) this.socket.destroy();
  }

  onData(chunk) {
    this.buffer = Buffer.concat([this.buffer, chunk]);
    while (this.buffer.length >= 4) {
      const length = this.buffer.readUInt32LE(0);
      if (this.buffer.length < 4 + length) return;
      const payload = this.buffer.subarray(4, 4 + length).toString("utf8");
      this.buffer = this.buffer.subarray(4 + length);
      this.onControl(payload);
    }
  }

  onControl(text) {
    this.controls += 1;
    const exactAckTime = /"ack_time":(\d+)/.exec(text)[1];
    const ackTime = this.roundAckTime ? BigInt(Number(exactAckTime)).toString() : exactAckTime;
    const ackMac = /"ack_time_mac":(\d+)/.exec(text)[1];
    const message = JSON.parse(text);
    let command = null;
    if (message.client_user_data) {
      this.clientUserData.push(message.client_user_data);
      command = message.client_user_data;
    }
    this.drive(command);
    const userData = JSON.stringify({ speed_mps: this.speed ?? 0, heading_deg: Math.round(this.heading * 10) / 10, source: "fake_vehicle" });
    const response = `{"ack_time":${ackTime},"ack_time_mac":${ackMac},"vehicle_user_data":` +
      `{"pos":{"lat":${this.position.lat},"lon":${this.position.lon}},"user_data":${userData}}}`;
    const body = Buffer.from(response, "utf8");
    const header = Buffer.alloc(4);
    header.writeUInt32LE(body.length, 0);
    this.socket.write(Buffer.concat([header, body]));
  }

  // 10 ms per control message; a lazy circle when idle so the track is visible either way.
  drive(command) {
    const throttle = command && typeof command.throttle === "number" ? command.throttle : 0.05;
    const steer = command && typeof command.steer === "number" ? command.steer : 0.3;
    this.speed = throttle * 10;
    this.heading = (this.heading + steer * 0.6) % 360;
    const metres = this.speed * 0.01;
    const radians = (this.heading * Math.PI) / 180;
    this.position.lat += (metres * Math.cos(radians)) / 111320;
    this.position.lon += (metres * Math.sin(radians)) / (111320 * Math.cos((this.position.lat * Math.PI) / 180));
  }
}
