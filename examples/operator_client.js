#!/usr/bin/env node
// A minimal OCP operator client: Node.js standard library only, written from docs/protocol.md.
//
// It connects to the Player's operator API (default 127.0.0.1:4001), reads VehicleOcpShared and
// answers with a ClientOcpShared that returns every control vehicle's latest ack_time/ack_time_mac
// pair (as ack_time_returned/ack_time_mac_returned), selects a control vehicle as active_vehicle
// and sends it a little user_data. When it has sent nothing for KEEP_ALIVE_PERIOD_MS it sends the
// keep-alive {}. It reconnects when the connection ends.
//
//     node examples/operator_client.js [HOST:PORT]
//     ocp_conformance operator -- node examples/operator_client.js 127.0.0.1:{port}
//
// ack_time is a u64 and may be above 2^53, where JSON.parse rounds it (protocol.md §2). Before
// parsing, this client turns the number after every "ack_time" / "ack_time_mac" key into a
// string of the same digits, and writes those digits back unchanged.
'use strict';
const net = require('net');

const MAX_PAYLOAD = 16384;          // bytes; a longer frame is read and skipped (protocol.md §2)
const KEEP_ALIVE_PERIOD_MS = 500;   // the Player closes a connection after 2 s without a byte (§4.2)
const EXACT_KEYS = ['ack_time', 'ack_time_mac'];

function frame(text) {
  const payload = Buffer.from(text, 'utf8');   // the prefix counts UTF-8 bytes, not characters
  const prefix = Buffer.alloc(4);
  prefix.writeUInt32LE(payload.length);         // 4-byte little-endian length prefix
  return Buffer.concat([prefix, payload]);
}

// `text` with the number after each key in `keys` (at any depth) quoted, so that JSON.parse
// gives its exact digits as a string. Strings are copied whole, so nothing inside them changes.
function quoteNumbersOf(text, keys) {
  const space = ' \t\n\r';
  let out = '';
  let from = 0;
  let key = null;                     // the string just read, when a ':' follows it
  for (let i = 0; i < text.length;) {
    if (text[i] === '"') {
      const start = i;
      for (i++; text[i] !== '"'; i++) if (text[i] === '\\') i++;
      i++;
      let next = i;
      while (space.includes(text[next])) next++;
      key = text[next] === ':' ? JSON.parse(text.slice(start, i)) : null;
      continue;
    }
    if (text[i] === ':' && key !== null) {
      const wanted = keys.includes(key);
      key = null;
      for (i++; space.includes(text[i]); i++);
      if (wanted && /[-0-9]/.test(text[i])) {
        let end = i;
        while (end < text.length && /[-+0-9.eE]/.test(text[end])) end++;
        out += `${text.slice(from, i)}"${text.slice(i, end)}"`;
        from = i = end;
      }
      continue;
    }
    i++;
  }
  return out + text.slice(from);
}

// The ClientOcpShared text for the latest VehicleOcpShared, and the vehicle now active.
function answer(shared, active) {
  const feedback = shared.vehicle_feedback || {};
  const control = Object.keys(feedback).filter((name) => !feedback[name].is_monitor).sort();
  if (control.length === 0) return { reply: null, active: null };   // monitors only: keep-alives suffice
  if (!control.includes(active)) active = control[0];
  const entries = control.map((name) => {   // each entry is that vehicle's whole client state
    const { ack_time: ackTime, ack_time_mac: mac } = feedback[name];   // digits, as they came
    const pair = typeof ackTime === 'string' && typeof mac === 'string'
      ? `,"ack_time_returned":${ackTime},"ack_time_mac_returned":${mac}` : '';
    return `${JSON.stringify(name)}:{"user_data":{"hello_from":"examples/operator_client.js"}${pair}}`;
  });
  return { reply: `{"active_vehicle":${JSON.stringify(active)},"client_user_data":{${entries.join(',')}}}`, active };
}

function session(socket, onEnd) {
  let buffer = Buffer.alloc(0);
  let skip = 0;                       // bytes of an oversized frame still to throw away
  let active = null;
  let keepAlive = null;

  const send = (text) => {
    socket.write(frame(text));
    clearTimeout(keepAlive);          // an idle timer, re-armed by everything sent
    keepAlive = setTimeout(() => send('{}'), KEEP_ALIVE_PERIOD_MS);   // keep-alive: locks nothing
  };

  const onData = (data) => {
    buffer = Buffer.concat([buffer, data]);
    let latest = null;
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
      latest = buffer.subarray(4, 4 + length).toString('utf8');
      buffer = buffer.subarray(4 + length);
    }
    if (latest === null) return;      // the latest frame of this read is enough
    const shared = JSON.parse(quoteNumbersOf(latest, EXACT_KEYS));
    if (shared === null || typeof shared !== 'object' || Array.isArray(shared)) throw new Error('not an object');
    const next = answer(shared, active);
    active = next.active;
    if (next.reply !== null) send(next.reply);
  };
  socket.on('connect', () => send('{}'));
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
    onEnd('closed by the Player');
  });
  socket.on('error', () => {});       // 'close' follows and says it
}

function main() {
  const address = process.argv[2] || '127.0.0.1:4001';
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
