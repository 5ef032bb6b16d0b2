// End-to-end test of the web view in a real browser (Debian's chromium, driven by
// playwright-core; no browser download). Run by ctest:
//   node web/tests/browser_test.mjs --player-sim build/bin/player_sim --artifacts build/artifacts
// 1. player_sim with a fleet (truck-1 on an external vehicle TCP port, truck-2 in-process) and
//    a fake vehicle on truck-1's port; the fleet overview has one row per vehicle, the "select
//    an active vehicle" hint shows until one is selected, and the active vehicle comes first
//    (rows and cards); the time axis reads hh:mm:ss; the dashboard shows latency, selects
//    truck-1, sends on-screen commands that arrive at the vehicle as client_user_data; a vehicle
//    that rounds ack_time through a double gets the Streamer's hint on its card; screenshots.
// 2. A fresh player_sim: a minimal page using only the SDK shim listens, the loop closes by the
//    auto-echo and the source stays unlocked; then a :4001 client takes the source and the
//    dashboard shows the lock banner; when that client leaves, the banner and the log say SPEC
//    §4.3's Decision ("source tcp locked, no client connected: no pair is returned"); screenshots.
// Every page of 1 and 2 must load without a console error, a failed request or an HTTP error
// (a favicon 404 included). Screenshots go to --artifacts (ctest: build/artifacts); their
// paths are printed.
// 3. Other origins: a page served by a tiny node server on another 127.0.0.1 port cannot open
//    the web view's WebSocket (403), one from an origin given with --webview-allow-origin can,
//    the dashboard still can (from 127.0.0.1 and from localhost), and a DNS-rebound name
//    (evil.example mapped to 127.0.0.1 by Chromium's resolver rules) gets 421.
// Every port is chosen by the system (0) and read from player_sim's log; every wait is bounded;
// child processes are killed on every path.
import { spawn } from "node:child_process";
import fs from "node:fs";
import http from "node:http";
import net from "node:net";
import path from "node:path";
import { chromium } from "playwright-core";
import { FakeVehicle } from "./fake_vehicle.mjs";

const TEST_TIMEOUT_MS = 120_000;
const WAIT_MS = 20_000;
const CHROMIUM = process.env.OCP_CHROMIUM || "/usr/bin/chromium";

const args = Object.fromEntries(process.argv.slice(2).reduce((pairs, value, index, all) =>
  (index % 2 === 0 ? [...pairs, [value.replace(/^--/, ""), all[index + 1]]] : pairs), []));
const playerSimPath = args["player-sim"];
const artifacts = args.artifacts || "artifacts";
if (!playerSimPath) {
  console.error("usage: browser_test.mjs --player-sim PATH [--artifacts DIR]");
  process.exit(2);
}

const children = new Set();
const cleanups = [];
function killChildren() {
  for (const child of children) child.kill("SIGKILL");
  children.clear();
}
process.on("exit", killChildren);
for (const signal of ["SIGINT", "SIGTERM"]) process.on(signal, () => { killChildren(); process.exit(1); });
const watchdog = setTimeout(() => {
  console.error(`browser test: timed out after ${TEST_TIMEOUT_MS} ms`);
  killChildren();
  process.exit(1);
}, TEST_TIMEOUT_MS);

let passed = 0;
function check(condition, what) {
  if (!condition) throw new Error(`check failed: ${what}`);
  passed += 1;
  console.log(`ok ${passed} - ${what}`);
}

// Collects what a user would see as red in the devtools console: page errors, console errors,
// failed requests and HTTP errors (a missing favicon is a 404 there too).
function watchPage(page) {
  const problems = [];
  page.on("pageerror", (error) => problems.push(`page error: ${error}`));
  page.on("console", (message) => {
    if (message.type() === "error") problems.push(`console error: ${message.text()}`);
  });
  page.on("requestfailed", (request) => {
    // A page closed mid-request aborts it: not a problem of the page.
    const reason = request.failure() ? request.failure().errorText : "";
    if (!/ERR_ABORTED/.test(reason)) problems.push(`request failed: ${request.url()} (${reason})`);
  });
  page.on("response", (response) => {
    if (response.status() >= 400) problems.push(`HTTP ${response.status()} for ${response.url()}`);
  });
  return problems;
}

async function screenshot(page, name, options = {}) {
  fs.mkdirSync(artifacts, { recursive: true });
  const file = path.resolve(artifacts, name);
  await page.screenshot({ path: file, ...options });
  console.log(`screenshot: ${file}`);
}

// The vehicles in the order the overview rows and the cards show them.
function shownOrder(page) {
  return page.evaluate(() => ({
    rows: [...document.querySelectorAll("#fleet-overview tbody tr")].map((row) => row.dataset.vehicle),
    cards: [...document.querySelectorAll("#vehicles .card")].map((card) => card.dataset.vehicle),
  }));
}

async function waitFor(what, predicate, timeoutMs = WAIT_MS) {
  const deadline = Date.now() + timeoutMs;
  while (Date.now() < deadline) {
    const value = await predicate();
    if (value) return value;
    await new Promise((resolve) => setTimeout(resolve, 50));
  }
  throw new Error(`timed out waiting for: ${what}`);
}

// Starts player_sim on system-chosen ports; resolves once it listens, with the ports it logged.
async function startPlayerSim(extraArgs) {
  const child = spawn(playerSimPath, ["--plugin-param", "ocp_player_tcp_port", "0", "--webview-port", "0", ...extraArgs],
                      { stdio: ["ignore", "pipe", "pipe"] });
  children.add(child);
  let output = "";
  child.stdout.on("data", (chunk) => { output += chunk; });
  child.stderr.on("data", (chunk) => { output += chunk; });
  child.on("exit", () => children.delete(child));
  await waitFor("player_sim to listen", () => /simulated vehicles:/.test(output) || child.exitCode !== null);
  if (child.exitCode !== null) throw new Error(`player_sim exited ${child.exitCode}:\n${output}`);
  const port = (pattern) => Number((pattern.exec(output) || [])[1]);
  return {
    child,
    output: () => output,
    webview: port(/web view on http:\/\/127\.0\.0\.1:(\d+)\//),
    operator: port(/operator API listening on 127\.0\.0\.1:(\d+)/),
    vehicle: port(/vehicle API listening on 127\.0\.0\.1:(\d+) for vehicle 'truck-1'/),
  };
}

async function stopPlayerSim(sim) {
  sim.child.kill("SIGTERM");
  await waitFor("player_sim to exit", () => sim.child.exitCode !== null, 10_000);
  return sim.child.exitCode;
}

// A :4001 operator client that sends one ClientOcpShared with user data (locks the tcp source),
// then keep-alives (SPEC §4.2) so that the 2 s read timeout does not close it before it leaves.
function lockWithTcpClient(port) {
  const frame = (message) => {
    const body = Buffer.from(JSON.stringify(message));
    const header = Buffer.alloc(4);
    header.writeUInt32LE(body.length, 0);
    return Buffer.concat([header, body]);
  };
  return new Promise((resolve, reject) => {
    const socket = net.connect({ host: "127.0.0.1", port }, () => {
      socket.write(frame({ client_user_data: { "truck-1": { user_data: { from: "tcp" } } } }));
      const keepAlive = setInterval(() => socket.write(frame({})), 500);
      socket.on("close", () => clearInterval(keepAlive));
      resolve(socket);
    });
    socket.on("data", () => {});
    socket.on("error", () => {});
    socket.once("error", reject);
  });
}

async function dashboardScenario(browser) {
  // A high ack_time offset, so that the fake vehicle's rounding through a double shows.
  const sim = await startPlayerSim(["--vehicle", "truck-1", "--vehicle", "truck-2", "--vehicle-tcp", "truck-1=0",
                                    "--ack-time-offset", "high"]);
  const vehicle = new FakeVehicle(sim.vehicle);
  cleanups.push(() => vehicle.close());
  await vehicle.connect();

  const page = await browser.newPage({ viewport: { width: 1500, height: 1300 } });
  const problems = watchPage(page);
  await page.goto(`http://127.0.0.1:${sim.webview}/dashboard/`);
  const latency = page.locator('#vehicles [data-vehicle="truck-1"] .latency');
  await waitFor("a latency on truck-1's card", async () => /^\d+ ms$/.test(await latency.textContent()));
  const first = await latency.textContent();
  check(true, `dashboard shows truck-1 latency (${first})`);
  check(await page.locator('#vehicles [data-vehicle="truck-2"]').count() === 1, "dashboard has a card for truck-2");
  await waitFor("the chart to gather samples",
                () => page.evaluate(() => window.dashboard.vehicles.get("truck-1").series[0].length > 20));
  check(true, "latency chart is being fed");
  // uPlot is vendored (web/vendor): the chart is drawn by it, not replaced by the "missing" note.
  check(await page.locator('#vehicles [data-vehicle="truck-1"] .uplot canvas').count() === 1,
        "latency chart drawn by the vendored uPlot");
  const receiverFaults = await page.locator('#vehicles [data-vehicle="truck-1"] .receiver-faults').textContent();
  check(/none|Vehicle Control Inactive|No Control Message/.test(receiverFaults) || receiverFaults.length > 0,
        `fault list rendered (${receiverFaults.trim()})`);
  check(await page.locator('#vehicles [data-vehicle="truck-1"] .sender-faults').textContent().then((t) => t.includes("VehicleControlInactive")),
        "before a selection, truck-1 shows the operator fault Vehicle Control Inactive with its id");

  // The fleet overview: one row per vehicle with its latency and faults; no vehicle is active yet.
  await waitFor("both overview rows to show a latency", () => page.evaluate(() =>
    [...document.querySelectorAll("#fleet-overview tbody tr")].filter((row) => /^\d+ ms$/.test(row.children[1].textContent)).length === 2));
  let order = await shownOrder(page);
  check(JSON.stringify(order.rows) === '["truck-1","truck-2"]', `overview has one row per vehicle (${order.rows})`);
  const row1 = await page.locator('#fleet-overview tr[data-vehicle="truck-1"]').textContent();
  check(row1.includes("Vehicle Control Inactive"), `truck-1's row shows its operator fault (${row1})`);
  const hint = page.locator("#no-active-hint");
  check(await hint.isVisible() && /select an active vehicle/.test(await hint.textContent()),
        `with no active vehicle the page says so (${await hint.textContent()})`);
  const labels = await page.evaluate(() => window.dashboard.vehicles.get("truck-1").chart.axes[0]._values || []);
  check(labels.length >= 2 && labels.every((label) => /^\d\d:\d\d:\d\d$/.test(label)),
        `the time axis reads hh:mm:ss (${labels.join(" ")})`);
  await screenshot(page, "dashboard_no_active.png");

  // The active vehicle comes first, in the overview and in the cards.
  await page.selectOption("#vehicle-select", "truck-2");
  await waitFor("truck-2 first once it is active", async () => {
    order = await shownOrder(page);
    return order.rows[0] === "truck-2" && order.cards[0] === "truck-2";
  });
  check(true, `the active vehicle comes first (rows ${order.rows}, cards ${order.cards})`);
  check(await page.locator('#fleet-overview tr.active').getAttribute("data-vehicle") === "truck-2",
        "the active vehicle's row is marked");
  check(await hint.isHidden(), "the no-active hint is gone once a vehicle is active");

  await page.selectOption("#vehicle-select", "truck-1");
  await waitFor("truck-1 to become the active vehicle", () =>
    page.evaluate(() => window.dashboard.status && window.dashboard.status.active_vehicle === "truck-1"));
  check(true, "selecting truck-1 sets active_vehicle");
  await waitFor("the web view to hold the source",
                () => page.evaluate(() => window.dashboard.status.locked_source === "webview"));
  check(true, "the page is the locked client-data source (webview)");

  await page.click("#btn-enable");
  await page.click("#btn-forward");
  await page.click("#btn-left");
  const command = await waitFor("the command at the vehicle", () =>
    vehicle.clientUserData.find((data) => data.throttle === 0.3 && data.steer === -0.25));
  check(command.brake === 0, `vehicle received client_user_data ${JSON.stringify(command)}`);
  check(vehicle.clientUserData.some((data) => data.enable === true), "the Enable pulse reached the vehicle");
  await waitFor("InvalidMac to stay clear while the page echoes", async () => {
    const text = await page.locator('#vehicles [data-vehicle="truck-1"] .receiver-faults').textContent();
    return !text.includes("InvalidMac") && /^\d+ ms$/.test(await latency.textContent());
  });
  check(true, "the latency loop stays closed through the page's messages");
  check(await page.locator("#banner").isHidden(), "no lock banner while this page holds the source");

  order = await shownOrder(page);
  check(order.rows[0] === "truck-1" && order.cards[0] === "truck-1", `truck-1 first once it is active (${order.rows})`);

  // The input bars: a stick's fill grows from the bar's centre (rest 0), a trigger's from its
  // left edge (rest -1), so a centred stick does not look half pressed.
  await waitFor("truck-2's input bars", () => page.evaluate(() =>
    document.querySelectorAll('#vehicles [data-vehicle="truck-2"] .input .axis').length === 6));
  const bars = await page.evaluate(() => [...document.querySelectorAll('#vehicles [data-vehicle="truck-2"] .input .axis')]
    .map((row) => ({ text: row.textContent, left: parseFloat(row.querySelector(".bar span").style.marginLeft),
                     width: parseFloat(row.querySelector(".bar span").style.width) })));
  for (const bar of bars) {
    const centre = Math.abs(bar.left - 50) < 0.01 || Math.abs(bar.left + bar.width - 50) < 0.01;
    check(/_trigger/.test(bar.text) ? bar.left === 0 : centre,
          `input bar ${bar.text.trim()}: ${/_trigger/.test(bar.text) ? "from the left edge" : "from the centre"} (left ${bar.left}%, width ${bar.width}%)`);
  }

  await page.waitForTimeout(2500);   // let the chart and the track grow for the screenshot
  await screenshot(page, "dashboard.png", { fullPage: true });

  // A vehicle that rounds ack_time through a double: the Streamer's hint reaches the card.
  vehicle.roundAckTime = true;
  const note = page.locator('#vehicles [data-vehicle="truck-1"] .loop-note');
  await waitFor("the loop note on truck-1's card", async () => /rounded through a double\?/.test(await note.textContent()));
  check(await note.isVisible(), `truck-1's card says why its loop does not close (${await note.textContent()})`);
  check(/ack_time differs by \d+ from issued pair \(ack_time \d+/.test(await note.textContent()),
        "the note names the pair the Streamer issued");
  const loopCell = page.locator('#fleet-overview tr[data-vehicle="truck-1"] .loop');
  await waitFor("truck-1's overview row to show the loop not closed", async () => /not closed/.test(await loopCell.textContent()));
  check(/not closed/.test(await loopCell.textContent()), "truck-1's overview row shows the loop not closed");
  check(/latency loop not closed \(InvalidMac\): returned pair/.test(sim.output()), "player_sim logs the same hint");
  await screenshot(page, "dashboard_loop_not_closed.png", { fullPage: true });
  vehicle.roundAckTime = false;
  await waitFor("the loop note to go once the echo is exact", () => note.isHidden());
  check(true, "the note goes when the loop closes again");

  check(problems.length === 0, `no console errors, failed requests or HTTP errors (${problems.join("; ")})`);
  await page.close();
  vehicle.close();
  check(await stopPlayerSim(sim) === 0, "player_sim exits 0 on SIGTERM");
}

async function minimalPageScenario(browser) {
  const sim = await startPlayerSim(["--vehicle", "truck-1"]);
  const page = await browser.newPage();
  const problems = watchPage(page);
  await page.goto(`http://127.0.0.1:${sim.webview}/minimal/`);
  const feedback = await waitFor("a measured latency without InvalidMac on the minimal page", () => page.evaluate(() => {
    const truck = window.latest && window.latest.vehicle_feedback["truck-1"];
    return truck && truck.message_latency_roundtrip !== null && !truck.receiver_fault.includes("InvalidMac") ? truck : null;
  }));
  check(true, `minimal SDK page: loop closed by the auto-echo, latency ${feedback.message_latency_roundtrip} ms`);
  check(!/client data source locked/.test(sim.output()), "a listening page never locks the client-data source");

  const tcp = await lockWithTcpClient(sim.operator);
  cleanups.push(() => tcp.destroy());
  await waitFor("the tcp source to lock", () => /client data source locked: tcp/.test(sim.output()));
  const dashboard = await browser.newPage({ viewport: { width: 1500, height: 1100 } });
  const dashboardProblems = watchPage(dashboard);
  await dashboard.goto(`http://127.0.0.1:${sim.webview}/dashboard/`);
  const banner = dashboard.locator("#banner");
  await waitFor("the lock banner", async () => /locked by the tcp client/.test(await banner.textContent()));
  check(await banner.isVisible(), "dashboard shows the banner: source locked by the tcp client");
  check(await dashboard.locator("#btn-forward").isDisabled(), "controls are disabled while another source holds the lock");
  check(await dashboard.locator("#no-active-hint").isHidden(), "one vehicle is active by itself: no hint");
  await screenshot(dashboard, "dashboard_locked.png");

  // SPEC §4.3 Decision: the tcp client leaves, the lock stays, nobody returns pairs.
  tcp.destroy();
  const decision = "source tcp locked, no client connected: no pair is returned";
  await waitFor("the banner to say the Decision", async () => (await banner.textContent()).includes(decision));
  check(await banner.isVisible(), `after the tcp client left the banner says "${decision}"`);
  await waitFor("the log line", () => sim.output().includes(decision));
  check(true, `player_sim logs "${decision}"`);
  check(await dashboard.locator("#btn-forward").isDisabled(), "the controls stay disabled: the lock stays with tcp");
  await screenshot(dashboard, "dashboard_tcp_client_left.png");
  check(problems.length === 0 && dashboardProblems.length === 0,
        `no console errors, failed requests or HTTP errors (${[...problems, ...dashboardProblems].join("; ")})`);
  await page.close();
  await dashboard.close();
  check(await stopPlayerSim(sim) === 0, "player_sim exits 0 on SIGTERM");
}

// A page that tries the WebSocket named in its ?ws= query and records what happened in
// window.result: "open" (and the first message), or "error"/"closed" (never opened).
const WEBSOCKET_PROBE_PAGE = `<!doctype html><title>probe</title><script>
  window.result = "pending";
  const socket = new WebSocket(new URLSearchParams(location.search).get("ws"));
  socket.onopen = () => { window.result = "open"; };
  socket.onmessage = (event) => { if (!window.firstMessage) window.firstMessage = String(event.data); };
  socket.onerror = () => { if (window.result === "pending") window.result = "error"; };
  socket.onclose = (event) => { window.closeCode = event.code; if (window.result === "pending") window.result = "closed"; };
</script>`;

// Serves WEBSOCKET_PROBE_PAGE on 127.0.0.1, on a port chosen by the system.
function startProbeServer() {
  return new Promise((resolve, reject) => {
    const server = http.createServer((request, response) => {
      response.writeHead(200, { "content-type": "text/html; charset=utf-8" });
      response.end(WEBSOCKET_PROBE_PAGE);
    });
    server.once("error", reject);
    server.listen(0, "127.0.0.1", () => {
      cleanups.push(() => server.close());
      resolve(server.address().port);
    });
  });
}

async function probe(browser, pageUrl, webviewPort) {
  const page = await browser.newPage();
  await page.goto(`${pageUrl}/?ws=${encodeURIComponent(`ws://127.0.0.1:${webviewPort}/ws`)}`);
  const result = await waitFor(`the WebSocket from ${pageUrl} to open or fail`,
                               () => page.evaluate(() => (window.result !== "pending" ? window.result : null)));
  const firstMessage = result !== "open" ? null
    : await waitFor("the first message", () => page.evaluate(() => window.firstMessage || null));
  await page.close();
  return { result, firstMessage };
}

async function originScenario(browser) {
  const foreignPort = await startProbeServer();
  const allowedPort = await startProbeServer();
  const sim = await startPlayerSim(["--vehicle", "truck-1", "--webview-allow-origin", `http://127.0.0.1:${allowedPort}`]);

  const foreign = await probe(browser, `http://127.0.0.1:${foreignPort}`, sim.webview);
  check(foreign.result !== "open", `a page from another origin cannot open the WebSocket (${foreign.result})`);
  await waitFor("the refusal in the log", () =>
    sim.output().includes(`refused with 403: Origin 'http://127.0.0.1:${foreignPort}' is not this web view's`));
  check(true, "player_sim logs the refused Origin");

  const allowed = await probe(browser, `http://127.0.0.1:${allowedPort}`, sim.webview);
  check(allowed.result === "open", `a page from an origin given with --webview-allow-origin connects (${allowed.result})`);
  check(allowed.firstMessage.includes("ocp_webview_status"), "the allowed page is served like the dashboard");

  for (const host of ["127.0.0.1", "localhost"]) {
    const dashboard = await browser.newPage();
    await dashboard.goto(`http://${host}:${sim.webview}/dashboard/`);
    await waitFor(`the dashboard at ${host} to get the status`,
                  () => dashboard.evaluate(() => !!(window.dashboard && window.dashboard.status)));
    check(true, `the dashboard served from http://${host}:${sim.webview} still connects`);
    await dashboard.close();
  }

  const rebound = await browser.newPage();
  const response = await rebound.goto(`http://evil.example:${sim.webview}/dashboard/`);
  check(response.status() === 421, `a DNS-rebound name (evil.example → 127.0.0.1) gets ${response.status()}, not the page`);
  await rebound.close();
  check(await stopPlayerSim(sim) === 0, "player_sim exits 0 on SIGTERM");
}

let browser = null;
let failed = 0;
try {
  // evil.example resolves to 127.0.0.1 in this browser only: a DNS rebinding without a DNS server.
  browser = await chromium.launch({ executablePath: CHROMIUM, headless: true,
                                    args: ["--no-sandbox", "--host-resolver-rules=MAP evil.example 127.0.0.1"] });
  await dashboardScenario(browser);
  await minimalPageScenario(browser);
  await originScenario(browser);
} catch (error) {
  failed = 1;
  console.error(`not ok - ${error.stack || error}`);
} finally {
  for (const cleanup of cleanups) cleanup();
  if (browser) await browser.close().catch(() => {});
  killChildren();
  clearTimeout(watchdog);
}
console.log(`browser: ${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
