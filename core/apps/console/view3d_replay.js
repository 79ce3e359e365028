// tern plot's 3-D replay (issue 65): the scene of view3d.js over a run's data, written by tern plot
// (core/apps/plot/tern_plot_view3d.py) into view3d_data.js beside index.html as
// `window.TERN_VIEW3D = {...}`; a time slider, play/pause, the replay's speed, camera follow/free,
// and `#t=SECONDS` in the URL opening the replay at that time (the page writes it back when
// paused). window.ternView3d exposes the time, the frames drawn and where each aircraft is, for
// tests and benchmarks.
import { View3D } from "./view3d.js";

export { View3D, nedToThree, attitudeToThree, SKY, GROUND } from "./view3d.js";

/// The last index k with t[k] <= x (-1 before the first).
function before(t, x) {
  let lo = 0, hi = t.length;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (t[mid] <= x) lo = mid + 1; else hi = mid;
  }
  return lo - 1;
}
/// The series' sample at x: flat rows of `width`, linear between rows (angles: along the shorter
/// arc when `angles`), the first/last row up to 1 s outside; null without rows, further outside,
/// or where a value is not logged (null: NaN in the log).
function sample(series, x, field, width, angles = false) {
  if (!series || !series.t.length) return null;
  const t = series.t, v = series[field];
  const k = before(t, x);
  if (k < 0 || k >= t.length - 1) {
    const j = k < 0 ? 0 : t.length - 1;
    const row = v.slice(width * j, width * j + width);
    return Math.abs(t[j] - x) > 1 || row.some((a) => a === null) ? null : row;
  }
  const f = (x - t[k]) / (t[k + 1] - t[k]);
  const out = [];
  for (let i = 0; i < width; ++i) {
    const a = v[width * k + i], b = v[width * (k + 1) + i];
    if (a === null || b === null) return null;
    let d = b - a;
    if (angles) d = Math.atan2(Math.sin(d), Math.cos(d));
    out.push(a + f * d);
  }
  return out;
}

/// The replay of data (window.TERN_VIEW3D) in the element `root`: canvas, controls, status lines.
export function startReplay(root, data) {
  const el = (tag, attrs = {}, text = "") => {
    const e = Object.assign(document.createElement(tag), attrs);
    if (text) e.textContent = text;
    return e;
  };
  const stage = el("div", { className: "view3d-stage" });
  const bar = el("div", { className: "view3d-bar" });
  const play = el("button", { type: "button" }, "play");
  const slider = el("input", { type: "range", min: data.t0, max: data.t1, step: 0.05, value: data.t0 });
  const clock = el("span", { className: "view3d-clock" });
  const speed = el("select");
  [1, 5, 20, 60].forEach((s) => speed.appendChild(el("option", { value: s, selected: s === 5 }, `${s}x`)));
  const follow = el("input", { type: "checkbox" });
  const followLabel = el("label", {}, " follow");
  followLabel.prepend(follow);
  bar.append(play, slider, clock, speed, followLabel);
  const hud = el("div", { className: "view3d-hud" });
  root.append(stage, bar, hud);
  for (const line of data.missing || []) root.appendChild(el("div", { className: "warning view3d-missing" }, line));

  const view = new View3D(stage, { extent: data.extent, center: data.center });
  view.setStatics({ waypoints: data.waypoints, home: data.home, runway: data.runway });
  const vehicles = data.vehicles.map((d) => {
    const v = view.addVehicle(d.name, d.colour, d.dims, Math.max(d.truth ? d.truth.t.length : 0, d.state ? d.state.t.length : 0, 1));
    if (d.truth) v.truth.set(d.truth.ned);
    if (d.state) v.estimate.set(d.state.ned);
    return { v, d };
  });
  view.setFreeScale();
  view.setFollow(false);

  const st = { t: data.t0, drawnT: null, playing: false, view, fps: 0, where: [], firstFrameMs: 0, speed };
  window.ternView3d = st;
  function show(t) {
    st.t = Math.min(data.t1, Math.max(data.t0, t));
    slider.value = st.t;
    clock.textContent = `t ${st.t.toFixed(1)} s / ${data.t1.toFixed(0)} s`;
    const lines = [];
    for (const { v, d } of vehicles) {
      const pose = d.truth || d.state;  // the aircraft where it truly was, else where it thought it was
      const ned = sample(pose, st.t, "ned", 3), euler = sample(pose, st.t, "euler", 3, true);
      const ghost = sample(d.ghost, st.t, "a", 2, true);
      v.pose(ned || [NaN, NaN, NaN], euler || [NaN, NaN, NaN], ghost);
      if (d.truth) v.truth.show(before(d.truth.t, st.t) + 1);
      if (d.state) v.estimate.show(before(d.state.t, st.t) + 1);
      const k = d.path ? before(d.path.t, st.t) : -1;
      v.setPath(k >= 0 ? d.path.items[d.path.k[k]] : null);
      const w = sample(d.wind, st.t, "w", 3);
      if (v === view.vehicles[0]) view.setWind(w || [NaN, NaN, NaN], data.wind_gain);
      if (ned) lines.push(`${d.name}: h ${(-ned[2]).toFixed(1)} m` + (w ? `, wind ${Math.hypot(w[0], w[1]).toFixed(1)} m/s from ${((Math.atan2(-w[1], -w[0]) * 180 / Math.PI + 360) % 360).toFixed(0)} deg` : ""));
    }
    hud.textContent = lines.join(" | ");
    view.dirty = true;
  }
  function fromHash() {
    const m = /(?:^|[#&])t=([0-9.eE+-]+)/.exec(location.hash);
    if (m && Number.isFinite(Number(m[1]))) show(Number(m[1]));
  }
  function toHash() {
    history.replaceState(null, "", `#t=${st.t.toFixed(1)}`);
  }
  play.onclick = () => {
    st.playing = !st.playing;
    play.textContent = st.playing ? "pause" : "play";
    if (!st.playing) toHash();
  };
  slider.oninput = () => show(Number(slider.value));
  slider.onchange = toHash;
  follow.onchange = () => { view.setFollow(follow.checked); show(st.t); };
  window.addEventListener("hashchange", fromHash);

  let last = performance.now(), fpsFrames = 0, fpsSince = last;
  function frame(now) {
    if (st.playing) {
      const t = st.t + ((now - last) / 1000) * Number(speed.value);
      show(t);
      if (t >= data.t1) play.onclick();
    }
    last = now;
    if (view.dirty || st.playing) {
      view.render();
      if (!st.firstFrameMs) st.firstFrameMs = performance.now();  // ms since the page's navigation began
      st.where = view.vehicles.map((_, k) => view.where(k));
      st.drawnT = st.t;  // the time the canvas shows
      fpsFrames += 1;
    }
    if (now - fpsSince >= 1000) { st.fps = (1000 * fpsFrames) / (now - fpsSince); fpsFrames = 0; fpsSince = now; }
    requestAnimationFrame(frame);
  }
  show(data.t0);
  fromHash();
  requestAnimationFrame(frame);
  return st;
}

if (typeof window !== "undefined" && window.TERN_VIEW3D && document.getElementById("view3d")) {
  startReplay(document.getElementById("view3d"), window.TERN_VIEW3D);
}
