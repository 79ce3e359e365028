// tern flight console: the page's side of core/apps/console (console_commands.hpp lists the
// requests, telemetry.hpp the frames). One WebSocket to tern; charts with uPlot; the ground
// track and attitude on plain canvases; the 3-D view with view3d.js (the scene of tern plot's
// replay); sticks from the keyboard or the browser Gamepad API.
"use strict";

const DEG = 180 / Math.PI;
const WINDOW_S = 30;          // chart history, s
const PILOT_PERIOD_MS = 40;   // sticks to tern at 25 Hz
const $ = (id) => document.getElementById(id);

// ---- connection -------------------------------------------------------------------------------
const ws = new WebSocket(`ws://${location.host}/ws`);
const state = { hello: null, last: null, frames: 0, trail: [], waypoints: [], manual: false, traffic: {} };
// a multi-vehicle flight's other vehicles (telemetry "traffic", in this vehicle's frame): one colour each
const TRAFFIC_COLOURS = ["#27ae60", "#8e44ad", "#d4ac0d", "#16a085", "#e67e22", "#7f8c8d", "#c2185b", "#1abc9c", "#34495e"];
window.ternConsole = state;  // for tests and the curious

ws.onopen = () => { $("link").textContent = "up"; };
ws.onclose = () => { $("link").textContent = "closed"; $("link").classList.add("alert"); };
ws.onmessage = (ev) => {
  const m = JSON.parse(ev.data);
  if (m.type === "hello") onHello(m);
  else if (m.type === "telemetry") onTelemetry(m);
  else if (m.type === "param_ok") showStatus(`${m.name} = ${JSON.stringify(m.value)} (next tick, params.csv)`, "ok");
  else if (m.type === "error") showStatus(m.message, "error");
};
function send(obj) { if (ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(obj)); }
function showStatus(text, cls) { const s = $("status"); s.textContent = text; s.className = cls; }

// ---- charts: command vs estimate per loop -----------------------------------------------------
const LOOPS = [
  { key: "roll", title: "roll (deg)", cmd: (m) => m.internals && m.internals.phi_c * DEG, est: (m) => m.state && m.state.phi * DEG },
  { key: "pitch", title: "pitch (deg)", cmd: (m) => m.internals && m.internals.theta_c * DEG, est: (m) => m.state && m.state.theta * DEG },
  { key: "course", title: "course (deg)", cmd: (m) => m.command && m.command.chi_c * DEG, est: (m) => m.state && m.state.chi * DEG },
  { key: "altitude", title: "altitude (m)", cmd: (m) => m.command && m.command.h_c, est: (m) => m.state && m.state.h },
  { key: "airspeed", title: "airspeed (m/s)", cmd: (m) => m.command && m.command.Va_c, est: (m) => m.state && m.state.Va },
];
const SURFACES = ["delta_a", "delta_e", "delta_r", "delta_t"];
const charts = {};

function makeChart(key, title, series) {
  const div = document.createElement("div");
  div.className = "chart";
  div.id = `chart_${key}`;
  $("charts").appendChild(div);
  const width = Math.max(300, $("charts").clientWidth - 20);
  const opts = { title, width, height: 130, legend: { live: false }, scales: { x: { time: false } },
                 axes: [{ size: 24 }, { size: 60 }], series: [{ label: "t (s)" }, ...series] };
  const data = [[]].concat(series.map(() => []));
  charts[key] = { plot: new uPlot(opts, data, div), data, dirty: false };
}
LOOPS.forEach((l) => makeChart(l.key, l.title, [
  { label: "command", stroke: "#d35400", width: 1.5 }, { label: "estimate", stroke: "#2471a3", width: 1.5 }]));
makeChart("surfaces", "surfaces (rad) and throttle", SURFACES.map((s, i) => (
  { label: s, stroke: ["#8e44ad", "#16a085", "#7f8c8d", "#c0392b"][i], width: 1.2 })));

function push(key, t, values) {
  const c = charts[key];
  c.data[0].push(t);
  values.forEach((v, i) => c.data[i + 1].push(v === undefined || v === null || Number.isNaN(v) ? null : v));
  while (c.data[0].length && c.data[0][0] < t - WINDOW_S) c.data.forEach((a) => a.shift());
  c.dirty = true;
}
function redraw() {
  for (const c of Object.values(charts)) if (c.dirty) { c.plot.setData(c.data); c.dirty = false; }
  drawTrack();
  drawAttitude();
  render3d();
  requestAnimationFrame(redraw);
}
requestAnimationFrame(redraw);

// ---- telemetry --------------------------------------------------------------------------------
function onTelemetry(m) {
  state.last = m;
  state.frames += 1;
  LOOPS.forEach((l) => push(l.key, m.t, [l.cmd(m), l.est(m)]));
  if (m.actuators) push("surfaces", m.t, SURFACES.map((s) => m.actuators[s]));
  if (m.state) {
    state.trail.push([m.state.p_n, m.state.p_e]);
    if (state.trail.length > 25 * 600) state.trail.shift();
  }
  if (m.waypoints) state.waypoints = m.waypoints.items;
  for (const v of m.traffic || []) {
    const t = state.traffic[v.name] || (state.traffic[v.name] = { trail: [], colour: TRAFFIC_COLOURS[Object.keys(state.traffic).length % TRAFFIC_COLOURS.length] });
    t.trail.push([v.p_n, v.p_e]);
    if (t.trail.length > 25 * 600) t.trail.shift();
    t.last = v;
  }
  update3d(m);
  $("t").textContent = m.t.toFixed(1);
  $("phase").textContent = m.phase || "–";
  const s = m.safety || {};
  $("active").textContent = s.active || "–";
  $("safety").textContent = s.handovers ? `${s.handovers} handover(s): ${s.reason}` : "ok";
  $("safety").classList.toggle("alert", !!s.handovers);
  const rc = m.rc || {};
  $("mode").textContent = rc.failsafe ? "RC FAILSAFE" : rc.override ? "MANUAL" : "AUTO";
  $("mode").classList.toggle("alert", !!(rc.override || rc.failsafe));
  $("r_rc").textContent = rc.failsafe ? "failsafe" : rc.override ? "override" : "auto";
  if (m.state) {
    $("r_Va").textContent = m.state.Va.toFixed(1);
    $("r_h").textContent = m.state.h.toFixed(1);
    $("r_phi").textContent = (m.state.phi * DEG).toFixed(1);
    $("r_theta").textContent = (m.state.theta * DEG).toFixed(1);
    $("r_chi").textContent = (m.state.chi * DEG).toFixed(0);
  }
}

// ---- 3-D view: the estimate, its track, the commanded path and attitude, the wind, traffic ----
const live3d = { view: null, revision: null, next: 0 };
const VIEW3D_SHARE = 0.2;  // of the page's time at most for the 3-D view (a software renderer is slow)
const VIEW3D_PERIOD_MS = 40;   // the telemetry's 25 Hz: drawing more often shows nothing new
function render3d() {
  const t0 = performance.now();
  if (!live3d.view || !live3d.view.dirty || t0 < live3d.next) return;
  live3d.view.render();
  const took = performance.now() - t0;
  live3d.next = t0 + Math.max(VIEW3D_PERIOD_MS, took / VIEW3D_SHARE);
}
state.view3d = live3d;
function start3d(h) {
  if (!window.TernView3D) { $("view3d_note").textContent = "view3d.js did not load: no 3-D view"; return; }
  if (new URLSearchParams(location.search).get("view3d") === "0") { $("view3d_note").textContent = "3-D view off (view3d=0 in the URL)"; return; }
  let dims = h.aircraft;
  if (!dims || dims.error) {
    const span = 1;  // m: said on the page
    $("view3d_note").textContent = `aircraft: ${dims ? dims.error : "the mission names no aircraft file"}: the model drawn ${span} m across`;
    dims = { b: span, c: span / 8, nose: 0.3 * span, tail: 0.5 * span };
  }
  try {
    live3d.view = new TernView3D.View3D($("view3d_live"), { extent: 1000, center: [0, 0, 0], antialias: false });
  } catch (e) {  // no WebGL in this browser: the rest of the page works without the view
    $("view3d_note").textContent = `no 3-D view: ${e.message}`;
    return;
  }
  live3d.view.addVehicle(h.mission, "#c0392b", dims, 25 * 600);
  live3d.view.setFreeScale();
  live3d.view.setFollow($("follow3d").checked);
  $("follow3d").onchange = () => live3d.view.setFollow($("follow3d").checked);
}
function update3d(m) {
  const view = live3d.view;
  if (!view) return;
  const me = view.vehicles[0], s = m.state;
  if (m.waypoints && m.waypoints_revision !== live3d.revision && m.waypoints.items.length) {
    live3d.revision = m.waypoints_revision;  // the scene sized to the waypoints and home
    const pts = m.waypoints.items.concat([[0, 0, 0]]);
    const lo = [0, 1].map((i) => Math.min(...pts.map((p) => p[i]))), hi = [0, 1].map((i) => Math.max(...pts.map((p) => p[i])));
    view.setExtent(1.2 * Math.max(hi[0] - lo[0], hi[1] - lo[1], 100), [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, 0]);
    view.setFreeScale();
    view.setStatics({ waypoints: m.waypoints.items, home: [0, 0, 0] });
  }
  if (s) {
    me.estimate.push(s.p_n, s.p_e, s.p_d);
    me.pose([s.p_n, s.p_e, s.p_d], [s.phi, s.theta, s.psi], m.internals ? [m.internals.phi_c, m.internals.theta_c] : null);
    view.setWind(s.w || [NaN, NaN, NaN], 1);
  }
  me.setPath(m.path || null);
  for (const v of m.traffic || []) {
    let o = view.vehicles.find((x) => x.name === v.name);
    if (!o) { o = view.addVehicle(v.name, state.traffic[v.name].colour, me.dims, 25 * 600); o.scale(view.follow ? 1 : view.freeScale); }
    o.estimate.push(v.p_n, v.p_e, -v.h);
    o.pose([v.p_n, v.p_e, -v.h], [0, 0, v.psi], null);  // traffic: position and heading only
  }
  view.dirty = true;
}

// ---- ground track and attitude ----------------------------------------------------------------
function drawTrack() {
  const cv = $("track"), g = cv.getContext("2d"), m = state.last;
  const others = Object.entries(state.traffic);
  const pts = state.waypoints.map((w) => [w[0], w[1]]).concat(state.trail.slice(-2000), ...others.map(([, t]) => t.trail.slice(-2000)));
  if (m && m.path && m.path.type === "orbit") pts.push([m.path.c[0] + m.path.rho, m.path.c[1] + m.path.rho], [m.path.c[0] - m.path.rho, m.path.c[1] - m.path.rho]);
  if (!pts.length) return;
  let nmin = Math.min(...pts.map((p) => p[0])), nmax = Math.max(...pts.map((p) => p[0]));
  let emin = Math.min(...pts.map((p) => p[1])), emax = Math.max(...pts.map((p) => p[1]));
  const span = Math.max(nmax - nmin, emax - emin, 100) * 1.15, cn = (nmin + nmax) / 2, ce = (emin + emax) / 2;
  const k = cv.width / span;
  const xy = (n, e) => [cv.width / 2 + (e - ce) * k, cv.height / 2 - (n - cn) * k];
  g.clearRect(0, 0, cv.width, cv.height);
  g.fillStyle = "#555"; g.font = "11px sans-serif"; g.fillText(`${Math.round(span)} m across`, 6, cv.height - 6);
  g.strokeStyle = "#bbb"; g.setLineDash([4, 4]); g.beginPath();
  state.waypoints.forEach((w, i) => { const [x, y] = xy(w[0], w[1]); if (i) g.lineTo(x, y); else g.moveTo(x, y); });
  g.stroke(); g.setLineDash([]);
  state.waypoints.forEach((w, i) => { const [x, y] = xy(w[0], w[1]); g.fillStyle = "#2c3e50"; g.fillRect(x - 3, y - 3, 6, 6); g.fillText(`${i}`, x + 5, y - 5); });
  if (m && m.path) drawPath(g, m.path, xy, k);
  g.strokeStyle = "#2471a3"; g.lineWidth = 1.5; g.beginPath();
  state.trail.forEach((p, i) => { const [x, y] = xy(p[0], p[1]); if (i) g.lineTo(x, y); else g.moveTo(x, y); });
  g.stroke(); g.lineWidth = 1;
  for (const [name, t] of others) {
    g.strokeStyle = t.colour; g.lineWidth = 1.5; g.beginPath();
    t.trail.slice(-2000).forEach((p, i) => { const [x, y] = xy(p[0], p[1]); if (i) g.lineTo(x, y); else g.moveTo(x, y); });
    g.stroke(); g.lineWidth = 1;
    const [x, y] = xy(t.last.p_n, t.last.p_e);
    drawAircraft(g, [x, y], t.last.psi, t.colour);
    g.fillStyle = t.colour; g.fillText(`${name} ${Math.round(t.last.h)} m`, x + 10, y + 4);
  }
  if (m && m.state) drawAircraft(g, xy(m.state.p_n, m.state.p_e), m.state.psi);
}
function drawPath(g, p, xy, k) {
  g.strokeStyle = "#d35400"; g.beginPath();
  if (p.type === "orbit") { const [x, y] = xy(p.c[0], p.c[1]); g.arc(x, y, p.rho * k, 0, 2 * Math.PI); }
  else { const [x0, y0] = xy(p.r[0], p.r[1]); const [x1, y1] = xy(p.r[0] + 400 * p.q[0], p.r[1] + 400 * p.q[1]); g.moveTo(x0, y0); g.lineTo(x1, y1); }
  g.stroke();
}
function drawAircraft(g, [x, y], psi, colour = "#c0392b") {
  g.save(); g.translate(x, y); g.rotate(psi); g.fillStyle = colour;
  g.beginPath(); g.moveTo(0, -9); g.lineTo(6, 7); g.lineTo(0, 3); g.lineTo(-6, 7); g.closePath(); g.fill(); g.restore();
}
function drawAttitude() {
  const cv = $("attitude"), g = cv.getContext("2d"), m = state.last, r = cv.width / 2;
  const phi = m && m.state ? m.state.phi : 0, theta = m && m.state ? m.state.theta : 0;
  g.save(); g.clearRect(0, 0, cv.width, cv.height);
  g.beginPath(); g.arc(r, r, r - 2, 0, 2 * Math.PI); g.clip();
  g.translate(r, r); g.rotate(-phi); const dy = theta * DEG * 2.5;
  g.fillStyle = "#5dade2"; g.fillRect(-2 * r, -3 * r + dy, 4 * r, 3 * r);
  g.fillStyle = "#a0522d"; g.fillRect(-2 * r, dy, 4 * r, 3 * r);
  g.strokeStyle = "#fff"; g.beginPath(); g.moveTo(-2 * r, dy); g.lineTo(2 * r, dy); g.stroke();
  g.restore();
  g.strokeStyle = "#f1c40f"; g.lineWidth = 3; g.beginPath(); g.moveTo(r - 40, r); g.lineTo(r - 12, r); g.moveTo(r + 12, r); g.lineTo(r + 40, r); g.stroke(); g.lineWidth = 1;
}

// ---- parameters: one control per ParamSpec ----------------------------------------------------
function onHello(h) {
  state.hello = h;
  start3d(h);
  $("mission").textContent = h.mission;
  const gens = new Set((h.instances || []).filter((i) => i.plugin === "signal_generator").map((i) => i.name));
  const groups = {};
  for (const p of h.params) (groups[p.instance] = groups[p.instance] || []).push(p);
  for (const [inst, params] of Object.entries(groups)) {
    const box = gens.has(inst) ? $("siggen_params") : addGroup(inst);
    params.forEach((p) => box.appendChild(paramRow(p)));
    if (gens.has(inst)) $("siggen").hidden = false;
  }
  if (!h.pilot) { $("manual").disabled = true; $("pilot").title = "no instance reads the pilot topic (fly the simulator)"; }
}
function addGroup(inst) {
  const d = document.createElement("details");
  d.className = "group";
  d.open = /slc|tecs|control/.test(inst);
  d.innerHTML = `<summary></summary>`;
  d.firstChild.textContent = inst;
  $("params").appendChild(d);
  return d;
}
function paramRow(p) {
  const row = document.createElement("div");
  row.className = "param" + (p.live ? "" : " start-only");
  row.dataset.name = p.name;
  row.title = `${p.name}: ${p.description}${p.unit ? " [" + p.unit + "]" : ""}` +
              (p.min !== null ? ` range ${p.min} .. ${p.max}` : "") + (p.live ? "" : " (start-only: set it between flights)");
  const name = document.createElement("span");
  name.className = "name";
  name.textContent = p.name.slice(p.instance.length + 1);
  row.appendChild(name);
  const [control, box] = paramControl(p);
  row.appendChild(control);
  row.appendChild(box);
  if (!p.live) { control.disabled = true; box.disabled = true; }
  return row;
}
function paramControl(p) {
  const unit = document.createElement("span");
  unit.textContent = p.unit;
  if (p.choices.length) {
    const sel = document.createElement("select");
    p.choices.forEach((c) => { const o = document.createElement("option"); o.textContent = c; sel.appendChild(o); });
    sel.value = p.value;
    sel.onchange = () => send({ type: "param", name: p.name, value: sel.value });
    return [sel, unit];
  }
  if (p.kind === "bool") {
    const cb = document.createElement("input");
    cb.type = "checkbox"; cb.checked = p.value;
    cb.onchange = () => send({ type: "param", name: p.name, value: cb.checked });
    return [cb, unit];
  }
  if ((p.kind === "number" || p.kind === "integer") && p.min !== null && p.max !== null) return numberControl(p);
  const txt = document.createElement("input");
  txt.type = "text"; txt.value = JSON.stringify(p.value);
  txt.onchange = () => { try { send({ type: "param", name: p.name, value: JSON.parse(txt.value) }); } catch (e) { showStatus(`${p.name}: ${e.message}`, "error"); } };
  return [txt, unit];
}
function numberControl(p) {
  const slider = document.createElement("input"), box = document.createElement("input");
  slider.type = "range"; box.type = "number";
  for (const el of [slider, box]) { el.min = p.min; el.max = p.max; el.step = p.kind === "integer" ? 1 : "any"; }
  // the slider covers the range in 1000 steps (a whole range like 0..1e6 still gets a box)
  if (p.kind !== "integer") slider.step = (p.max - p.min) / 1000;
  slider.value = box.value = p.value;
  slider.setAttribute("aria-label", p.name);
  const commit = (v) => { const x = p.kind === "integer" ? Math.round(v) : v; slider.value = box.value = x; send({ type: "param", name: p.name, value: x }); };
  slider.oninput = () => { box.value = slider.value; };
  slider.onchange = () => commit(Number(slider.value));
  box.onchange = () => commit(Number(box.value));
  return [slider, box];
}

// ---- pilot: keyboard or gamepad sticks, manual and angle switches -----------------------------
const keys = new Set();
const sticks = { roll: 0, pitch: 0, yaw: 0, throttle: 0.5 };
const typing = (el) => ["INPUT", "SELECT", "TEXTAREA"].includes(el.tagName) && el.type !== "checkbox";
document.addEventListener("keydown", (ev) => {
  if (typing(ev.target)) return;
  if (ev.key === "m" || ev.key === "M") { setManual(!state.manual); return; }
  keys.add(ev.key.length === 1 ? ev.key.toLowerCase() : ev.key);
  if (ev.key.startsWith("Arrow")) ev.preventDefault();
});
document.addEventListener("keyup", (ev) => keys.delete(ev.key.length === 1 ? ev.key.toLowerCase() : ev.key));
window.addEventListener("blur", () => keys.clear());
$("manual").onclick = () => setManual(!state.manual);

function setManual(on) {
  state.manual = on;
  $("manual").textContent = `Manual: ${on ? "ON" : "off"}`;
  $("manual").classList.toggle("on", on);
  sendPilot();
}
/// A key-driven stick: towards +-1 while a key is held (full in 0.3 s), back to centre when let go.
function spring(v, plus, minus, dt) {
  const target = (keys.has(plus) ? 1 : 0) - (keys.has(minus) ? 1 : 0);
  const rate = dt / 0.3;
  return target === 0 ? Math.sign(v) * Math.max(0, Math.abs(v) - rate) : Math.max(-1, Math.min(1, v + Math.sign(target - v) * Math.min(rate, Math.abs(target - v))));
}
function keyboardSticks(dt) {
  sticks.roll = spring(sticks.roll, "ArrowRight", "ArrowLeft", dt);
  sticks.pitch = spring(sticks.pitch, "ArrowDown", "ArrowUp", dt);  // stick back (down arrow): nose up
  sticks.yaw = spring(sticks.yaw, "d", "a", dt);
  const dthr = (keys.has("w") ? 1 : 0) - (keys.has("s") ? 1 : 0);
  sticks.throttle = Math.max(0, Math.min(1, sticks.throttle + dthr * dt / 2));  // stays where it is left
}
function gamepadSticks(apply) {
  const pads = navigator.getGamepads ? Array.from(navigator.getGamepads()).filter((p) => p) : [];
  $("gamepad").textContent = pads.length ? `gamepad: ${pads[0].id}` : "no gamepad (press a button on it to wake it)";
  if (!pads.length || !apply) return false;
  const a = pads[0].axes, dz = (v) => (Math.abs(v) < 0.05 ? 0 : v);
  // mode 2: left stick throttle (up) and rudder, right stick roll and pitch (back: nose up)
  sticks.yaw = dz(a[0] || 0);
  sticks.throttle = Math.max(0, Math.min(1, (1 - (a[1] || 0)) / 2));
  sticks.roll = dz(a[2] || 0);
  sticks.pitch = dz(a[3] || 0);
  return true;
}
function sendPilot() {
  if (!state.hello || !state.hello.pilot) return;
  const r = (v) => Math.round(v * 1000) / 1000;
  send({ type: "pilot", manual: state.manual, angle: $("angle").checked,
         roll: r(sticks.roll), pitch: r(sticks.pitch), yaw: r(sticks.yaw), throttle: r(sticks.throttle) });
}
let lastPilot = performance.now();
setInterval(() => {
  const now = performance.now(), dt = (now - lastPilot) / 1000;
  lastPilot = now;
  if (!gamepadSticks($("source").value === "gamepad")) keyboardSticks(dt);
  for (const k of Object.keys(sticks)) $(`s_${k}`).textContent = sticks[k].toFixed(2);
  if (state.manual) sendPilot();
}, PILOT_PERIOD_MS);
$("angle").onchange = sendPilot;
