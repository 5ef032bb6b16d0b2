// The operator dashboard: one card per vehicle from ocp_vehicle_user_data (SPEC §4.1), the
// source-lock banner from ocp_webview_status, and on-screen controls that send commands as
// user data through ocp_client_user_data (seed 004). Uses only the Oden SDK shim.
(function () {
  "use strict";

  const CHART_WINDOW_S = 60;
  const CHART_SAMPLE_MS = 100;      // frames arrive at 100 Hz; the chart needs 10
  const PULSE_MS = 300;             // how long a one-shot "enable" flag is sent
  const client = getOrCreateOdenLayoutClient();

  const state = {
    vehicles: new Map(),            // name → card state
    status: null,
    selected: "",                   // this page's choice of active vehicle
    onScreen: false,                // on-screen commands instead of the gamepad
    inControl: false,               // this page has sent client data: keep sending every frame
    command: { throttle: 0, brake: 0, steer: 0 },
    pulse: null,                    // {enable, until}
    frames: 0,
    lastSent: null,
    dirty: false,
  };
  window.dashboard = state;         // for the browser test and for poking around in devtools

  const $ = (id) => document.getElementById(id);
  const el = {
    connection: $("connection"), source: $("source"), select: $("vehicle-select"), banner: $("banner"),
    vehicles: $("vehicles"), lastSent: $("last-sent"), template: $("vehicle-card"),
  };

  // ---- receiving -------------------------------------------------------------------------

  client.registerUserMessageCallback("ocp_webview_connection", ({ connected }) => {
    el.connection.textContent = connected ? "web view connected" : "web view disconnected — retrying";
    el.connection.className = "pill " + (connected ? "good" : "bad");
  });

  client.registerUserMessageCallback("ocp_webview_status", (status) => {
    state.status = status;
    renderStatus();
  });

  client.registerUserMessageCallback("ocp_webview_error", (error) => {
    console.warn(`web view dropped a message of this page (${error.kind}): ${error.detail}`);
  });

  client.registerUserMessageCallback("ocp_vehicle_user_data", (data) => {
    state.frames += 1;
    const now = Date.now();
    for (const [name, feedback] of Object.entries(data.vehicle_feedback || {})) {
      updateVehicle(vehicleCard(name), feedback, now);
    }
    state.lastInput = data.last_input;
    if (state.inControl) send();
    if (!state.dirty) {
      state.dirty = true;
      requestAnimationFrame(render);
    }
  });

  function vehicleCard(name) {
    let card = state.vehicles.get(name);
    if (card) return card;
    const root = el.template.content.firstElementChild.cloneNode(true);
    root.dataset.vehicle = name;
    root.querySelector(".name").textContent = name;
    el.vehicles.appendChild(root);
    const find = (selector) => root.querySelector(selector);
    card = {
      name, root, feedback: null, lastSample: 0,
      series: [[], [], []],   // time s, latency ms, ping ms
      chart: null, chartBox: find(".chart"),
      plot: new PositionPlot(find(".map")),
      latency: find(".latency"), ping: find(".ping"), age: find(".age"), coords: find(".coords"),
      receiver: find(".receiver-faults"), sender: find(".sender-faults"), cameras: find(".missing-cameras"),
      userData: find(".user-data"), input: find(".input"),
    };
    card.chart = makeChart(card);
    state.vehicles.set(name, card);
    const option = document.createElement("option");
    option.value = name;
    option.textContent = name;
    el.select.appendChild(option);
    renderStatus();
    return card;
  }

  function updateVehicle(card, feedback, now) {
    card.feedback = feedback;
    if (feedback.vehicle_data) card.plot.add(feedback.vehicle_data.pos);
    if (now - card.lastSample >= CHART_SAMPLE_MS) {
      card.lastSample = now;
      const [times, latency, ping] = card.series;
      times.push(now / 1000);
      latency.push(feedback.message_latency_roundtrip ?? null);
      ping.push(feedback.ping_latency_ms);
      while (times.length && times[0] < now / 1000 - CHART_WINDOW_S) {
        times.shift(); latency.shift(); ping.shift();
      }
    }
  }

  function makeChart(card) {
    if (typeof uPlot === "undefined") {
      card.chartBox.textContent = "chart library missing (web/vendor/uPlot.iife.min.js was not served)";
      return null;
    }
    const axis = { stroke: "#8aa0b4", grid: { stroke: "#1f2d3a", width: 1 }, ticks: { stroke: "#1f2d3a" } };
    return new uPlot({
      width: Math.max(card.chartBox.clientWidth, 300), height: 170,
      scales: { x: { time: true }, y: { range: (u, min, max) => [0, Math.max(100, max * 1.2)] } },
      series: [{}, { label: "latency ms", stroke: "#38bdf8", width: 2, fill: "rgba(56,189,248,0.08)", points: { show: false } },
               { label: "ping ms", stroke: "#a78bfa", width: 1.5, points: { show: false } }],
      axes: [axis, { ...axis, size: 58 }],
      legend: { live: false },
    }, card.series, card.chartBox);
  }

  // ---- rendering (at most once per animation frame) --------------------------------------

  function render() {
    state.dirty = false;
    for (const card of state.vehicles.values()) renderVehicle(card);
  }

  function renderVehicle(card) {
    const f = card.feedback;
    if (!f) return;
    const active = state.status && state.status.active_vehicle === card.name;
    card.root.classList.toggle("active", !!active);
    card.root.classList.toggle("monitor", !!f.is_monitor);
    card.latency.textContent = f.message_latency_roundtrip == null ? "—" : `${f.message_latency_roundtrip} ms`;
    card.ping.textContent = `${f.ping_latency_ms} ms`;
    card.age.textContent = `${f.ms_since_last_vehicle_data} ms`;
    const faulty = (f.receiver_fault || []).length > 0;
    card.root.classList.toggle("faulty", faulty);
    renderFaults(card.receiver, f.receiver_fault);
    renderFaults(card.sender, f.sender_fault);
    renderList(card.cameras, f.missing_cameras || [], "all cameras fine");
    const pos = f.vehicle_data && f.vehicle_data.pos;
    card.coords.textContent = pos ? `${pos.lat.toFixed(6)}, ${pos.lon.toFixed(6)}` : "no position";
    card.userData.textContent = f.vehicle_data ? JSON.stringify(f.vehicle_data.user_data, null, 1) : "—";
    renderInput(card.input, f.last_remote_input);
    card.plot.draw();
    if (card.chart) {
      const width = Math.max(card.chartBox.clientWidth, 300);
      if (card.chart.width !== width) card.chart.setSize({ width, height: 170 });
      card.chart.setData(card.series);
    }
  }

  function renderFaults(list, ids) {
    list.replaceChildren();
    if (!ids || ids.length === 0) {
      list.appendChild(item("none", "none"));
      return;
    }
    for (const id of ids) {
      const li = item(OCP_FAULT_DISPLAY[id] || id, "fault");
      const code = document.createElement("code");
      code.textContent = id;
      li.append(" ", code);
      list.appendChild(li);
    }
  }

  function renderList(list, names, empty) {
    list.replaceChildren();
    if (names.length === 0) list.appendChild(item(empty, "none"));
    for (const name of names) list.appendChild(item(name, "fault"));
  }

  function item(text, className) {
    const li = document.createElement("li");
    li.className = className;
    li.textContent = text;
    return li;
  }

  function renderInput(box, controller) {
    box.replaceChildren();
    if (!controller) {
      box.textContent = "none (controller null: commands come from user data)";
      return;
    }
    for (const [axis, value] of Object.entries(controller.axes)) {
      const row = document.createElement("div");
      row.className = "axis";
      const bar = document.createElement("span");
      bar.className = "bar";
      const fill = document.createElement("span");
      fill.style.width = `${((value + 1) / 2) * 100}%`;
      bar.appendChild(fill);
      row.append(`${axis} `, bar, ` ${value.toFixed(2)}`);
      box.appendChild(row);
    }
    const pressed = Object.entries(controller.buttons).filter(([, down]) => down).map(([name]) => name);
    const buttons = document.createElement("div");
    buttons.textContent = `buttons: ${pressed.length ? pressed.join(", ") : "none"}`;
    box.appendChild(buttons);
  }

  function renderStatus() {
    const status = state.status;
    if (!status) return;
    if (!state.selected && status.active_vehicle && el.select.value !== status.active_vehicle) {
      el.select.value = status.active_vehicle;
    }
    const source = status.locked_source;
    el.source.textContent = source
      ? `client data source: ${source}${source === "webview" && state.inControl ? " (this page)" : ""}`
      : "client data source: none (Player echoes)";
    el.source.className = "pill " + (status.client_data_stopped ? "bad" : source && source !== "webview" ? "warn" : "good");
    let banner = "";
    let kind = "";
    if (status.client_data_stopped) {
      banner = `Client data STOPPED: two sources sent client data (source conflict; the locked source was ` +
               `${source}). User data and the timestamp echo stay off until the Player restarts — vehicles ` +
               `will report "Latency Loop Not Closed".`;
      kind = "bad";
    } else if (source && source !== "webview") {
      banner = `Client data source is locked by the ${source} client. This page's vehicle selection and ` +
               `commands would be a source conflict — the controls are disabled.`;
      kind = "warn";
    }
    // The :4001 TCP client gets no VehicleOcpShared while it is over 16 KiB (SPEC §2); this
    // page still does, so say it here.
    const tooLarge = status.client_frame_too_large;
    if (tooLarge) {
      banner = (banner ? banner + " " : "") + tooLarge.text;
      kind = kind || "warn";
    }
    el.banner.textContent = banner;
    el.banner.className = `banner ${kind}` + (banner ? "" : " hidden");
    const blocked = status.client_data_stopped || (source && source !== "webview");
    for (const control of document.querySelectorAll(".controls button, .controls input, #vehicle-select")) {
      control.disabled = !!blocked;
    }
  }

  // ---- sending ---------------------------------------------------------------------------

  function send() {
    const vehicle = state.selected;
    const message = { client_user_data: {} };
    if (vehicle) {
      message.active_vehicle = vehicle;
      const entry = { ocp_disable_gamepad: state.onScreen };
      if (state.onScreen) {
        entry.user_data = { ...state.command };
        if (state.pulse && Date.now() < state.pulse.until) entry.user_data.enable = state.pulse.enable;
      }
      message.client_user_data[vehicle] = entry;
    }
    client.sendNamedUserMessage("ocp_client_user_data", message);
    state.lastSent = message;
  }

  function takeControl() {
    state.inControl = true;
    send();
    renderStatus();
  }

  function commandControl(change) {
    if (!state.selected) {
      const first = state.vehicles.keys().next().value;
      if (!first) return;
      state.selected = first;
      el.select.value = first;
    }
    state.onScreen = true;
    change();
    syncSliders();
    takeControl();
  }

  function pulse(enable) {
    state.pulse = { enable, until: Date.now() + PULSE_MS };
  }

  function syncSliders() {
    for (const name of ["throttle", "brake", "steer"]) {
      $(name).value = state.command[name];
      $(`${name}-value`).textContent = Number(state.command[name]).toFixed(2);
    }
  }

  el.select.addEventListener("change", () => {
    state.selected = el.select.value;
    takeControl();
  });
  $("btn-enable").addEventListener("click", () => commandControl(() => {
    state.command = { throttle: 0, brake: 0, steer: 0 };   // the interlock wants neutral input
    pulse(true);
  }));
  $("btn-stop").addEventListener("click", () => commandControl(() => {
    state.command = { throttle: 0, brake: 1, steer: 0 };
    pulse(false);
  }));
  $("btn-forward").addEventListener("click", () => commandControl(() => {
    state.command.throttle = 0.3;
    state.command.brake = 0;
  }));
  $("btn-left").addEventListener("click", () => commandControl(() => {
    state.command.steer = Math.max(-1, state.command.steer - 0.25);
  }));
  $("btn-right").addEventListener("click", () => commandControl(() => {
    state.command.steer = Math.min(1, state.command.steer + 0.25);
  }));
  $("btn-gamepad").addEventListener("click", () => {
    state.onScreen = false;
    state.command = { throttle: 0, brake: 0, steer: 0 };
    syncSliders();
    if (state.inControl) send();
  });
  for (const name of ["throttle", "brake", "steer"]) {
    $(name).addEventListener("input", () => commandControl(() => {
      state.command[name] = Number($(name).value);
    }));
  }

  // The "last sent" box refreshes a few times a second, not at the 100 Hz send rate.
  setInterval(() => {
    el.lastSent.textContent = state.lastSent ? JSON.stringify(state.lastSent, null, 1) : "nothing yet";
  }, 250);
})();
