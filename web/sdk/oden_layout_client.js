// The Oden layout client, as the OCP simulator's web view provides it (seed 004; wire protocol
// in docs/webview.md). Load it with a plain <script> tag; it defines one global function:
//
//   const odenClient = getOrCreateOdenLayoutClient();
//   odenClient.registerUserMessageCallback("ocp_vehicle_user_data", (data) => { … });
//   odenClient.unregisterUserMessageCallback("ocp_vehicle_user_data", sameFunction);
//   odenClient.sendNamedUserMessage("ocp_client_user_data", {active_vehicle, client_user_data});
//
// Latency timestamps: the page never handles ack_time / ack_time_mac. While the page sends
// nothing, the latency loop is echoed for it (a listening page never locks the client-data
// source); once it calls sendNamedUserMessage("ocp_client_user_data", …), the Player stamps
// every such message with the latest timestamp pair itself — the exact u64 value, which a JS
// number could not hold above 2^53. So keep sending (e.g. on every ocp_vehicle_user_data)
// while the page is in control, or the vehicle sees the latency grow. A call that names a
// vehicle gets its pair even with a bare entry ({client_user_data: {"truck-1": {}}}) and
// takes the source lock; only a call naming nothing ({}) is a keep-alive.
//
// Extra, simulator-only message names: "ocp_webview_status" (who holds the client-data
// source lock, SPEC §4.3) and "ocp_webview_error" (why a message of this page was dropped).
// "ocp_webview_connection" is local to the shim: {connected: true|false} on every change.
(function () {
  "use strict";

  const RECONNECT_MIN_MS = 250;
  const RECONNECT_MAX_MS = 4000;
  const MAX_PENDING_SENDS = 64;   // sends made while disconnected; the oldest are dropped

  class OdenLayoutClient {
    constructor(url) {
      this._url = url;
      this._callbacks = new Map();   // name → Set of functions
      this._pending = [];
      this._socket = null;
      this._reconnectMs = RECONNECT_MIN_MS;
      this._connect();
    }

    registerUserMessageCallback(name, callback) {
      if (typeof callback !== "function") throw new TypeError("callback must be a function");
      if (!this._callbacks.has(name)) this._callbacks.set(name, new Set());
      this._callbacks.get(name).add(callback);
    }

    unregisterUserMessageCallback(name, callback) {
      const set = this._callbacks.get(name);
      if (set) set.delete(callback);
    }

    sendNamedUserMessage(name, data) {
      const text = JSON.stringify({ name: String(name), data: data === undefined ? null : data });
      if (this._socket && this._socket.readyState === WebSocket.OPEN) {
        this._socket.send(text);
        return;
      }
      this._pending.push(text);
      if (this._pending.length > MAX_PENDING_SENDS) this._pending.shift();
    }

    get connected() {
      return !!this._socket && this._socket.readyState === WebSocket.OPEN;
    }

    _connect() {
      const socket = new WebSocket(this._url);
      this._socket = socket;
      socket.onopen = () => {
        this._reconnectMs = RECONNECT_MIN_MS;
        this._dispatch("ocp_webview_connection", { connected: true });
        const pending = this._pending;
        this._pending = [];
        for (const text of pending) socket.send(text);
      };
      socket.onmessage = (event) => {
        let message;
        try {
          // Plain JSON.parse: numbers above 2^53 (ack_time) lose precision here, which is
          // why nothing in the page may echo them — the Player injects the exact pair.
          message = JSON.parse(event.data);
        } catch (error) {
          console.warn("oden web view: undecodable message dropped", error);
          return;
        }
        if (!message || typeof message.name !== "string") return;
        this._dispatch(message.name, message.data);
      };
      socket.onclose = () => {
        if (this._socket !== socket) return;
        this._dispatch("ocp_webview_connection", { connected: false });
        setTimeout(() => this._connect(), this._reconnectMs);
        this._reconnectMs = Math.min(this._reconnectMs * 2, RECONNECT_MAX_MS);
      };
      socket.onerror = () => {};   // onclose follows and reconnects
    }

    _dispatch(name, data) {
      const set = this._callbacks.get(name);
      if (!set) return;
      for (const callback of Array.from(set)) {
        try {
          callback(data);
        } catch (error) {
          console.error(`oden web view: callback for ${name} threw`, error);
        }
      }
    }
  }

  let instance = null;

  // The page's one client. The WebSocket is the page's own origin at /ws, unless the page sets
  // window.ODEN_WEBVIEW_URL (e.g. "ws://127.0.0.1:4002/ws") before the first call.
  function getOrCreateOdenLayoutClient() {
    if (!instance) {
      const scheme = location.protocol === "https:" ? "wss:" : "ws:";
      instance = new OdenLayoutClient(window.ODEN_WEBVIEW_URL || `${scheme}//${location.host}/ws`);
    }
    return instance;
  }

  window.getOrCreateOdenLayoutClient = getOrCreateOdenLayoutClient;
})();
