// The operator dashboard: a fleet overview (one row per vehicle, the active one first) and one
// card per vehicle from ocp_vehicle_user_data (SPEC §4.1), the source-lock banner and why loops
// do not close from ocp_webview_status, and on-screen controls that send commands as user data
// through ocp_client_user_data (seed 004). Uses only the Oden SDK shim.
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
    overview: document.querySelector("#fleet-overview tbody"), noActive: $("no-active-hint"),
  };
  let shownOrder = "";              // the vehicle order last laid out, to re-lay only on change

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
    const row = overviewRow(name);
    card = {
      name, root, row, feedback: null, lastSample: 0, loopNote: find(".loop-note"),
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

  // One overview row: name, latency, ping, faults of both sides and the loop, in a few pixels.
  function overviewRow(name) {
    const row = document.createElement("tr");
    row.dataset.vehicle = name;
    row.title = `${name}: click to see its card`;
    for (const cell of ["name", "latency", "ping", "receiver", "sender", "loop"]) {
      const td = document.createElement("td");
      td.className = cell;
      row.appendChild(td);
    }
    row.querySelector(".name").textContent = name;
    row.addEventListener("click", () => {
      const card = state.vehicles.get(name);
      if (card) card.root.scrollIntoView({ behavior: "smooth", block: "start" });
    });
    el.overview.appendChild(row);
    return row;
  }

  // The active vehicle first, then the others by name.
  function vehicleOrder() {
    const active = state.status && state.status.active_vehicle;
    return [...state.vehicles.keys()].sort((a, b) => (b === active) - (a === active) || a.localeCompare(b));
  }

  function layOut() {
    const order = vehicleOrder();
    const key = order.join("\n");
    if (key === shownOrder) return;
    shownOrder = key;
    for (const name of order) {
      const card = state.vehicles.get(name);
      el.overview.appendChild(card.row);    // appending an attached node moves it
      el.vehicles.appendChild(card.root);
    }
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
    const axis = { stroke: "#8aa0b4", grid: { stroke: "#1f2d3a", width: 1 }, ticks: { stroke: "#1f2d3a" },
                   font: "12px system-ui, sans-serif", labelFont: "12px system-ui, sans-serif" };
    return new uPlot({
      width: Math.max(card.chartBox.clientWidth, 300), height: 170,
      scales: { x: { time: true }, y: { range: (u, min, max) => [0, Math.max(100, max * 1.2)] } },
      series: [{ label: "time" },
               { label: "latency ms", stroke: "#38bdf8", width: 2, fill: "rgba(56,189,248,0.08)", points: { show: false } },
               { label: "ping ms", stroke: "#a78bfa", width: 1.5, points: { show: false } }],
      // Wall-clock labels (14:03:25) every 10 s or more, never the date or am/pm uPlot picks
      // for a 60 s window; the y axis says its unit.
      axes: [{ ...axis, space: 70, incrs: [1, 2, 5, 10, 15, 30, 60], values: (u, splits) => splits.map(clockLabel) },
             { ...axis, size: 58, label: "ms", labelSize: 18 }],
      legend: { live: false },
    }, card.series, card.chartBox);
  }

  function clockLabel(seconds) {
    const time = new Date(seconds * 1000);
    return [time.getHours(), time.getMinutes(), time.getSeconds()].map((n) => String(n).padStart(2, "0")).join(":");
  }

  // ---- rendering (at most once per animation frame) --------------------------------------

  function render() {
    state.dirty = false;
    layOut();
    for (const card of state.vehicles.values()) {
      renderVehicle(card);
      renderRow(card);
    }
  }

  function renderRow(card) {
    const f = card.feedback;
    if (!f) return;
    const cells = card.row.children;
    card.row.classList.toggle("active", !!(state.status && state.status.active_vehicle === card.name));
    cells[1].textContent = f.message_latency_roundtrip == null ? "—" : `${f.message_latency_roundtrip} ms`;
    cells[2].textContent = `${f.ping_latency_ms} ms`;
    renderFaultNames(cells[3], f.receiver_fault);
    renderFaultNames(cells[4], f.sender_fault);
    const note = loopNote(card.name);
    // The Streamer's hint comes with the status, the fault with the next feedback: either says it.
    const open = !!note || (f.receiver_fault || []).includes("InvalidMac");
    cells[5].textContent = open ? "not closed" : "closed";
    cells[5].className = `loop ${open ? "fault" : "none"}`;
    cells[5].title = note || "";
  }

  function renderFaultNames(cell, ids) {
    const names = (ids || []).map((id) => OCP_FAULT_DISPLAY[id] || id);
    cell.textContent = names.length ? names.join(", ") : "none";
    cell.className = `${cell.className.split(" ")[0]} ${names.length ? "fault" : "none"}`;
    cell.title = (ids || []).join(", ");
  }

  // Why this vehicle's returned pairs are rejected (the Streamer's hint), while they are.
  function loopNote(name) {
    return (state.status && state.status.loop_not_closed && state.status.loop_not_closed[name]) || "";
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
    const note = loopNote(card.name);
    card.loopNote.textContent = note ? `Latency loop not closed: ${note}` : "";
    card.loopNote.classList.toggle("hidden", !note);
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

  // Where an axis's fill starts and how wide it is, in % of its bar. A stick rests at 0, so its
  // fill grows from the middle, left or right; a trigger rests at -1 (released), so its fill
  // grows from the left edge. [-1, 1] spans the bar either way.
  function axisFill(axis, value) {
    const v = Math.max(-1, Math.min(1, Number(value) || 0));
    if (axis.endsWith("_trigger")) return [0, ((v + 1) / 2) * 100];
    return v >= 0 ? [50, v * 50] : [50 + v * 50, -v * 50];
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
      const [left, width] = axisFill(axis, value);
      fill.style.marginLeft = `${left}%`;
      fill.style.width = `${width}%`;
      if (!axis.endsWith("_trigger")) bar.classList.add("centred");
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
    if (status.tcp_lock_without_client) {
      // SPEC §4.3 Decision, in its own words; then what the user can do about it.
      banner = `${status.tcp_lock_without_client}. The lock stays with the tcp source: a new TCP client on the ` +
               `operator API may take over, this page may not (its controls stay disabled).`;
      kind = "warn";
    } else if (status.client_data_stopped) {
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
    // A fleet with no active vehicle: none gets gamepad input and all raise Vehicle Control
    // Inactive (SPEC §7) — tell the user what to do rather than only showing the fault.
    const fleet = (status.vehicles || []).length > 1;
    const noActive = fleet && !status.active_vehicle;
    el.noActive.textContent = noActive
      ? (blocked ? "No vehicle is active: the client-data source that holds the lock must select one."
                 : "No vehicle is active — select an active vehicle (“Active vehicle” above) to drive it; " +
                   "until then every vehicle reports Vehicle Control Inactive.")
      : "";
    el.noActive.classList.toggle("hidden", !noActive);
    if (!state.dirty) {
      state.dirty = true;
      requestAnimationFrame(render);
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
