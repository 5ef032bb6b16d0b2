#!/usr/bin/env node
// A minimal OCP vehicle client: Node.js standard library only, written from docs/protocol.md.
//
// It connects to the Streamer's vehicle API (default 127.0.0.1:4000), reads the control messages
// and answers each one at once with its ack_time/ack_time_mac pair; when it has sent nothing for
// RESPONSE_PERIOD_MS it repeats the latest pair as a keep-alive. It reconnects when the
// connection ends. Where a real vehicle would act on the controller, it only counts messages.
//
//     node examples/vehicle_client.js [HOST:PORT]
//     ocp_conformance vehicle -- node examples/vehicle_client.js 127.0.0.1:{port}
//
// ack_time is a u64 and may be above 2^53, where JSON.parse rounds it (protocol.md §2). This
// client never lets it become a Number: it keeps the digits of the two top-level members as
// they came off the wire and writes them back unchanged.
'use strict';
const net = require('net');

const MAX_PAYLOAD = 16384;      // bytes; a longer frame is read and skipped (protocol.md §2)
const RESPONSE_PERIOD_MS = 10;  // keep-alive after this long without a response (§3.3, §8)

function frame(text) {
  const payload = Buffer.from(text, 'utf8');
  const prefix = Buffer.alloc(4);
  prefix.writeUInt32LE(payload.length);   // 4-byte little-endian length prefix
  return Buffer.concat([prefix, payload]);
}

// The raw text of the top-level members named in `names` (JSON already checked by JSON.parse):
// strings and nested values are skipped whole, so a nested "ack_time" is never taken.
function topLevelMembers(text, names) {
  let i = 0;
  const found = {};
  const space = () => { while (' \t\n\r'.includes(text[i])) i++; };
  const skipString = () => { for (i++; text[i] !== '"'; i++) if (text[i] === '\\') i++; i++; };
  const skipValue = () => {
    if (text[i] === '"') return skipString();
    if (text[i] === '{' || text[i] === '[') {
      let depth = 0;
      do {
        if (text[i] === '"') { skipString(); continue; }
        if (text[i] === '{' || text[i] === '[') depth++;
        else if (text[i] === '}' || text[i] === ']') depth--;
        i++;
      } while (depth > 0);
      return;
    }
    while (i < text.length && !',}] \t\n\r'.includes(text[i])) i++;   // a number, true, false, null
  };
  space();
  i++;                                    // {
  for (space(); text[i] !== '}'; space()) {
    const keyStart = i;
    skipString();
    const key = JSON.parse(text.slice(keyStart, i));
    space();
    i++;                                  // :
    space();
    const valueStart = i;
    skipValue();
    if (names.includes(key)) found[key] = text.slice(valueStart, i);
    space();
    if (text[i] === ',') i++;
  }
  return found;
}

function session(socket, onEnd) {
  let buffer = Buffer.alloc(0);
  let skip = 0;                           // bytes of an oversized frame still to throw away
  let pair = null;                        // no response before the first control message
  let received = 0;
  let keepAlive = null;

  const respond = () => {
    const userData = `{"pos":null,"user_data":{"messages_received":${received}}}`;
    socket.write(frame(`{"ack_time":${pair.ackTime},"ack_time_mac":${pair.mac},"vehicle_user_data":${userData}}`));
    clearTimeout(keepAlive);              // an idle timer, re-armed by every response
    keepAlive = setTimeout(respond, RESPONSE_PERIOD_MS);
  };

  const onData = (data) => {
    buffer = Buffer.concat([buffer, data]);
    let fresh = false;
    for (;;) {
      if (skip > 0) {
        const dropped = Math.min(skip, buffer.length);
        buffer = buffer.subarray(dropped);
        skip -= dropped;
        if (skip > 0) break;
      }
      if (buffer.length < 4) break;
      const length = buffer.readUInt32LE(0);
      if (length > MAX_PAYLOAD) {
        console.error(`warning: skipping an oversized frame of ${length} bytes`);
        buffer = buffer.subarray(4);
        skip = length;
        continue;
      }
      if (buffer.length < 4 + length) break;
      const text = buffer.subarray(4, 4 + length).toString('utf8');
      buffer = buffer.subarray(4 + length);
      const message = JSON.parse(text);   // the controller and telemetry, for a real vehicle
      if (message === null || typeof message !== 'object' || Array.isArray(message)) throw new Error('not an object');
      const members = topLevelMembers(text, ['ack_time', 'ack_time_mac']);
      pair = { ackTime: members.ack_time, mac: members.ack_time_mac };
      received++;
      fresh = true;
    }
    if (fresh) respond();                 // one answer for the latest pair of this read
  };
  socket.on('data', (data) => {
    try {
      onData(data);
    } catch (error) {
      console.error(`bad frame (${error.message}): closing the connection`);
      socket.destroy();
    }
  });
  socket.on('close', () => {
    clearTimeout(keepAlive);
    onEnd('closed by the Streamer');
  });
  socket.on('error', () => {});           // 'close' follows and says it
}

function main() {
  const address = process.argv[2] || '127.0.0.1:4000';
  const colon = address.lastIndexOf(':');
  const host = address.slice(0, colon);
  const port = Number(address.slice(colon + 1));
  let backoff = 100;
  const connect = () => {
    const socket = net.createConnection({ host, port, noDelay: true });
    let connected = false;
    socket.on('connect', () => {
      connected = true;
      backoff = 100;
      console.error(`connected to ${host}:${port}`);
    });
    session(socket, (reason) => {
      console.error(`disconnected (${connected ? reason : 'connect failed'}); reconnecting in ${backoff / 1000} s`);
      setTimeout(connect, backoff);
      backoff = Math.min(backoff * 2, 2000);
    });
  };
  connect();
}

process.on('SIGTERM', () => process.exit(0));
process.on('SIGINT', () => process.exit(0));
main();
