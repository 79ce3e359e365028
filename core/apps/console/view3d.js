// tern's 3-D view of a flight (issue 65), one scene for the console's live view (console.js) and
// tern plot's replay (view3d_replay.js): a ground grid, each vehicle's aircraft model (fuselage,
// wing, tail scaled from its span b, chord c and length), its true and estimated tracks, the
// commanded path (path_manager's line or orbit), the waypoints, home, the landing runway, the wind
// arrow and a ghost of the commanded attitude (phi_c, theta_c). three.js (npm) draws it; the build
// bundles this file with three.js into one script (CMakeLists.txt beside it), loaded without a
// server and without fetching anything.
//
// Frames: every position given to this module is NED in m about the vehicle's origin (north, east,
// down) and every attitude the 3-2-1 Euler angles (phi, theta, psi) in rad of the body FRD axes
// against NED (Beard & McLain ch. 2). nedToThree and attitudeToThree below are the one place these
// become three.js's right-handed y-up frame: x = east, y = up (-down), z = south (-north).
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";

// ---- NED -> three.js (the one place) ------------------------------------------------------------
/// NED (m) -> three.js world (x east, y up, z south).
export function nedToThree(n, e, d, out = new THREE.Vector3()) {
  return out.set(e, -d, -n);
}
// M maps NED (and body FRD) axes to three.js axes: its rows are x = e, y = -d, z = -n.
const M = new THREE.Matrix4().set(0, 1, 0, 0, 0, 0, -1, 0, -1, 0, 0, 0, 0, 0, 0, 1);
const MT = M.clone().transpose();
const _R = new THREE.Matrix4(), _E = new THREE.Euler();
/// The body's attitude (3-2-1 Euler, rad: R = Rz(psi) Ry(theta) Rx(phi), body FRD -> NED) as the
/// three.js quaternion of a model built in bodyToThree's axes: M R M^T.
export function attitudeToThree(phi, theta, psi, out = new THREE.Quaternion()) {
  _R.makeRotationFromEuler(_E.set(phi, theta, psi, "ZYX"));  // three's "ZYX": Rz * Ry * Rx
  return out.setFromRotationMatrix(_R.premultiply(M).multiply(MT));
}
/// A point of the model in body FRD (m: x forward, y right, z down) -> the model's three.js axes.
function bodyToThree(x, y, z) {
  return new THREE.Vector3(y, -z, -x);
}

// ---- the aircraft model -------------------------------------------------------------------------
/// dims: {b: span m, c: mean chord m, nose: m ahead of the CG, tail: m behind it (> 0)}. The
/// fuselage runs from nose to tail; the wing at the CG; the tail surfaces at the tail, sized
/// against the wing as a drawing (a third of its span, its chord).
function aircraftModel(dims, colour, ghost) {
  const g = new THREE.Group();
  const mat = ghost ? new THREE.MeshBasicMaterial({ color: colour, transparent: true, opacity: 0.28, depthWrite: false })
    : new THREE.MeshLambertMaterial({ color: colour });
  const length = dims.nose + dims.tail, body = length / 12, skin = dims.c / 6;
  const box = (sx, sy, sz, x, y, z) => {  // a box of sizes along body FRD x, y, z centred at (x, y, z)
    const m = new THREE.Mesh(new THREE.BoxGeometry(sy, sz, sx), mat);
    m.position.copy(bodyToThree(x, y, z));
    g.add(m);
  };
  box(length, body, body, (dims.nose - dims.tail) / 2, 0, 0);          // fuselage
  box(dims.c, dims.b, skin, 0, 0, 0);                                  // wing
  box(dims.c, dims.b / 3, skin, -dims.tail + dims.c / 2, 0, 0);        // horizontal tail
  box(dims.c, skin, dims.b / 6, -dims.tail + dims.c / 2, 0, -dims.b / 12);  // fin (up: -z)
  return g;
}

// ---- lines --------------------------------------------------------------------------------------
/// A polyline of NED points (flat [n, e, d, n, e, d, ...]); NaN points are dropped.
function nedLine(flat, colour, opacity = 1) {
  const pts = [];
  const v = new THREE.Vector3();
  for (let k = 0; k + 2 < flat.length; k += 3) {
    if (Number.isFinite(flat[k]) && Number.isFinite(flat[k + 1]) && Number.isFinite(flat[k + 2])) {
      nedToThree(flat[k], flat[k + 1], flat[k + 2], v);
      pts.push(v.x, v.y, v.z);
    }
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute("position", new THREE.Float32BufferAttribute(pts, 3));
  return new THREE.Line(geo, new THREE.LineBasicMaterial({ color: colour, transparent: opacity < 1, opacity }));
}

/// A track that grows (live) or is shown up to an index (replay): a preallocated line of `capacity` points.
class Track {
  constructor(scene, colour, capacity, opacity = 1) {
    this.capacity = capacity;
    this.count = 0;
    this.positions = new Float32Array(capacity * 3);
    this.geo = new THREE.BufferGeometry();
    this.geo.setAttribute("position", new THREE.BufferAttribute(this.positions, 3));
    this.geo.setDrawRange(0, 0);
    this.line = new THREE.Line(this.geo, new THREE.LineBasicMaterial({ color: colour, transparent: opacity < 1, opacity }));
    this.line.frustumCulled = false;
    scene.add(this.line);
  }
  /// Sets all points (flat NED; null: not logged, drawn at the point before) at once; shown up to show(k).
  set(flat) {
    const n = Math.min(this.capacity, Math.floor(flat.length / 3));
    const v = new THREE.Vector3();
    for (let k = 0; k < n; ++k) {
      const p = flat.slice(3 * k, 3 * k + 3);
      if (p.every(Number.isFinite)) nedToThree(p[0], p[1], p[2], v);  // else v keeps the point before
      this.positions.set([v.x, v.y, v.z], 3 * k);
    }
    this.count = n;
    this.geo.attributes.position.needsUpdate = true;
  }
  /// Appends one point (live); the oldest half is dropped when full.
  push(n, e, d) {
    if (![n, e, d].every(Number.isFinite)) return;
    if (this.count === this.capacity) {
      const half = Math.floor(this.capacity / 2);
      this.positions.copyWithin(0, 3 * half);
      this.count -= half;
    }
    const v = nedToThree(n, e, d);
    this.positions.set([v.x, v.y, v.z], 3 * this.count);
    this.count += 1;
    this.geo.attributes.position.needsUpdate = true;
    this.show(this.count);
  }
  show(k) { this.geo.setDrawRange(0, Math.max(0, Math.min(k, this.count))); }
}

// ---- one vehicle --------------------------------------------------------------------------------
class Vehicle {
  constructor(view, name, colour, dims, capacity) {
    this.name = name;
    this.view = view;
    this.dims = dims;
    this.model = aircraftModel(dims, colour, false);
    this.ghost = aircraftModel(dims, "#f39c12", true);
    this.ghost.visible = false;
    this.truth = new Track(view.scene, colour, capacity);
    this.estimate = new Track(view.scene, colour, capacity, 0.45);
    this.path = null;
    this.pathKey = "";
    this.ned = [NaN, NaN, NaN];
    this.euler = [0, 0, 0];
    view.scene.add(this.model, this.ghost);
  }
  /// The aircraft at NED (m) with 3-2-1 Euler angles (rad); ghost: [phi_c, theta_c] or null.
  pose(ned, euler, ghost) {
    this.ned = ned;
    this.euler = euler;
    this.model.visible = ned.every(Number.isFinite) && euler.every(Number.isFinite);
    if (!this.model.visible) return;
    nedToThree(ned[0], ned[1], ned[2], this.model.position);
    attitudeToThree(euler[0], euler[1], euler[2], this.model.quaternion);
    this.ghost.visible = !!ghost && ghost.every(Number.isFinite);
    if (this.ghost.visible) {
      this.ghost.position.copy(this.model.position);
      attitudeToThree(ghost[0], ghost[1], euler[2], this.ghost.quaternion);  // the commanded roll and pitch at today's heading
    }
  }
  /// The commanded path: {type: "line"|"orbit", r, q, c: NED, rho: m, lambda: +1 cw / -1 ccw} or null.
  setPath(p) {
    const key = p ? JSON.stringify(p) : "";
    if (key === this.pathKey) return;
    this.pathKey = key;
    if (this.path) { this.view.scene.remove(this.path); this.path.geometry.dispose(); }
    this.path = null;
    if (!p) return;
    const flat = [];
    if (p.type === "orbit" && p.rho > 0) {
      for (let k = 0; k <= 96; ++k) {
        const a = (2 * Math.PI * k) / 96;
        flat.push(p.c[0] + p.rho * Math.cos(a), p.c[1] + p.rho * Math.sin(a), p.c[2]);
      }
    } else if (p.type === "line") {
      const reach = this.view.extent;  // the line through r over the whole scene (below ground: hidden)
      flat.push(...[-1, 1].flatMap((s) => [0, 1, 2].map((i) => p.r[i] + s * reach * p.q[i])));
    }
    this.path = nedLine(flat, "#d35400");
    this.view.scene.add(this.path);
  }
  scale(s) {
    this.model.scale.setScalar(s);
    this.ghost.scale.setScalar(s);
  }
}

// ---- the view -----------------------------------------------------------------------------------
export const SKY = "#dfe8f0", GROUND = "#d5dccb";  // what is drawn differs from both (test_plot_view3d.py)
/// A 3-D view in `container` (a sized element). opts.extent: the scene's size in m (grid, camera);
/// opts.antialias: false to spare a software renderer the multisampling (default true).
export class View3D {
  constructor(container, opts = {}) {
    this.container = container;
    this.extent = opts.extent || 1000;
    this.center = opts.center || [0, 0, 0];
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(SKY);
    this.scene.add(new THREE.HemisphereLight("#ffffff", "#6b7a5a", 2.2), new THREE.AmbientLight("#ffffff", 0.4));
    this.renderer = new THREE.WebGLRenderer({ antialias: opts.antialias !== false });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    container.appendChild(this.renderer.domElement);
    this.camera = new THREE.PerspectiveCamera(50, 1, 0.5, 50 * this.extent);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener("change", () => { this.dirty = true; });
    this.vehicles = [];
    this.follow = false;
    this.freeScale = 1;  // set by setFreeScale
    this.dirty = true;
    this.frames = 0;
    this.grid = null;
    this.statics = new THREE.Group();
    this.scene.add(this.statics);
    this.wind = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 1, "#16a085");
    this.wind.visible = false;
    this.scene.add(this.wind);
    this.setExtent(this.extent, this.center);
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }
  /// The ground grid and the free camera over a square of `extent` m about center (NED).
  setExtent(extent, center) {
    this.extent = extent;
    this.center = center;
    if (this.grid) this.scene.remove(this.grid);
    const cell = 10 ** Math.floor(Math.log10(extent / 5));  // 5 to 50 cells across
    const cells = Math.ceil(extent / cell);
    this.grid = new THREE.Group();
    const lines = new THREE.GridHelper(cells * cell, cells, "#7f8c8d", "#a9b4a0");
    const ground = new THREE.Mesh(new THREE.PlaneGeometry(3 * cells * cell, 3 * cells * cell), new THREE.MeshBasicMaterial({ color: GROUND }));
    ground.rotation.x = -Math.PI / 2;  // the plane into the ground (y up)
    ground.position.y = -0.05;         // under the grid's lines
    this.grid.add(ground, lines);
    nedToThree(center[0], center[1], 0, this.grid.position);
    this.scene.add(this.grid);
    this.camera.far = 50 * extent;
    this.camera.updateProjectionMatrix();
    this.home();
  }
  /// The free camera: the whole scene seen from the south-west, above.
  home() {
    const c = nedToThree(this.center[0], this.center[1], this.center[2]);
    this.controls.target.copy(c);
    this.camera.position.copy(c).add(nedToThree(-0.45 * this.extent, -0.3 * this.extent, -0.35 * this.extent));
    this.controls.update();
    this.dirty = true;
  }
  /// A vehicle: dims as aircraftModel's; capacity: the most track points kept.
  addVehicle(name, colour, dims, capacity) {
    const v = new Vehicle(this, name, colour, dims, capacity);
    this.vehicles.push(v);
    v.scale(this.follow ? 1 : this.freeScale);
    return v;
  }
  /// The free camera's models drawn so that the largest span is 1/25 of the scene (at least their size).
  setFreeScale() {
    const b = Math.max(...this.vehicles.map((v) => v.dims.b));
    this.freeScale = Math.max(1, this.extent / (25 * b));
    this.vehicles.forEach((v) => v.scale(this.follow ? 1 : this.freeScale));
  }
  /// Follow the first vehicle (chase camera, the model at its size) or fly the camera freely (the
  /// models drawn freeScale times their size to be seen across the scene).
  setFollow(on) {
    this.follow = on;
    this.controls.enabled = !on;
    this.vehicles.forEach((v) => v.scale(on ? 1 : this.freeScale));
    if (!on) this.home();
    this.dirty = true;
  }
  /// Waypoints (NED list), home (NED or null) and the runway ({td: NED aim point, heading: rad,
  /// length: m along the heading, width: m} or null): drawn once.
  setStatics({ waypoints = [], home = null, runway = null }) {
    this.statics.clear();
    const mark = this.extent / 150;
    for (const w of waypoints) {
      if (!w.every(Number.isFinite)) continue;
      const m = new THREE.Mesh(new THREE.OctahedronGeometry(mark), new THREE.MeshLambertMaterial({ color: "#2c3e50" }));
      nedToThree(w[0], w[1], w[2], m.position);
      this.statics.add(m, nedLine([w[0], w[1], w[2], w[0], w[1], 0], "#2c3e50", 0.35));
    }
    if (waypoints.length > 1) this.statics.add(nedLine(waypoints.flat(), "#34495e", 0.4));
    if (home && home.every(Number.isFinite)) {
      const h = new THREE.Mesh(new THREE.CylinderGeometry(mark, mark, mark / 4, 24), new THREE.MeshLambertMaterial({ color: "#8e44ad" }));
      nedToThree(home[0], home[1], home[2], h.position);
      this.statics.add(h);
    }
    if (runway && runway.td.every(Number.isFinite) && Number.isFinite(runway.heading)) {
      const strip = new THREE.Mesh(new THREE.PlaneGeometry(runway.width, runway.length),
                                   new THREE.MeshBasicMaterial({ color: "#555", side: THREE.DoubleSide }));
      strip.rotation.x = -Math.PI / 2;  // the plane into the ground (y up)
      const along = runway.length / 2;
      nedToThree(runway.td[0] + along * Math.cos(runway.heading), runway.td[1] + along * Math.sin(runway.heading),
                 runway.td[2], strip.position);
      strip.rotateOnWorldAxis(new THREE.Vector3(0, 1, 0), -runway.heading);
      strip.position.y += 0.05;  // above the grid
      this.statics.add(strip);
    }
    this.dirty = true;
  }
  /// The wind (NED, m/s) as an arrow above the first vehicle, `gain` of its drawn spans per m/s.
  setWind(w, gain) {
    const v = this.vehicles[0];
    const speed = Math.hypot(...w);
    this.wind.visible = !!v && v.model.visible && w.every(Number.isFinite) && speed > 0;
    if (!this.wind.visible) return;
    const dir = nedToThree(w[0] / speed, w[1] / speed, w[2] / speed);
    this.wind.setDirection(dir);
    const scale = this.follow ? 1 : this.freeScale, len = gain * speed * v.dims.b * scale;
    this.wind.setLength(len, 0.2 * len, 0.08 * len);
    this.wind.position.copy(v.model.position).add(new THREE.Vector3(0, v.dims.b * scale, 0)).addScaledVector(dir, -len / 2);
  }
  resize() {
    const w = this.container.clientWidth || 640, h = this.container.clientHeight || 400;
    this.renderer.setSize(w, h, false);
    this.renderer.domElement.style.width = "100%";
    this.renderer.domElement.style.height = "100%";
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }
  /// The chase camera: behind and above the first vehicle along its heading.
  chase() {
    const v = this.vehicles[0];
    if (!v || !v.model.visible) return;
    const len = v.dims.nose + v.dims.tail, psi = v.euler[2];
    const back = 6 * Math.max(len, v.dims.b);
    const eye = nedToThree(v.ned[0] - back * Math.cos(psi), v.ned[1] - back * Math.sin(psi), v.ned[2] - back / 3);
    this.camera.position.copy(eye);
    this.camera.lookAt(v.model.position);
  }
  render() {
    if (this.follow) this.chase();
    this.renderer.render(this.scene, this.camera);
    this.frames += 1;
    this.dirty = false;
  }
  /// Where a vehicle's model is on the canvas (CSS px from the top left) and in NED, for tests.
  where(k = 0) {
    const v = this.vehicles[k];
    if (!v || !v.model.visible) return null;
    const p = v.model.position.clone().project(this.camera);
    const el = this.renderer.domElement;
    return { name: v.name, ned: v.ned.slice(), screen: [(p.x + 1) / 2 * el.clientWidth, (1 - p.y) / 2 * el.clientHeight] };
  }
}

export { THREE };
