// The page of `radiosity view` and `radiosity bake --html`: loads the bake,
// draws it (render.js), walks or orbits through it, and mixes its light
// groups with a slider and a colour each. `window.radiosityViewer` lets
// tests drive it.
"use strict";

import { readBake } from "./gltf.js";
import { Renderer } from "./render.js";

const $ = (id) => document.getElementById(id);
const canvas = $("view");

// Vector helpers on [x, y, z].
const add = (a, b) => a.map((x, i) => x + b[i]);
const sub = (a, b) => a.map((x, i) => x - b[i]);
const scale = (a, s) => a.map((x) => x * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalise = (a) => { const l = Math.hypot(...a) || 1; return scale(a, 1 / l); };
const UP = [0, 1, 0];

// The view-projection matrix (column-major) of eye, forward, up.
function viewProjection(view, aspect, near, far) {
  const f = normalise(view.forward);
  const r = normalise(cross(f, view.up));
  const u = cross(r, f);
  const e = view.eye;
  const t = 1 / Math.tan(view.yfov / 2);
  const p = [t / aspect, t, (far + near) / (near - far), (2 * far * near) / (near - far)];
  // Projection times view, written out.
  const v = [
    r[0], u[0], -f[0], r[1], u[1], -f[1], r[2], u[2], -f[2],
    -dot(r, e), -dot(u, e), dot(f, e),
  ];
  return new Float32Array([
    p[0] * v[0], p[1] * v[1], p[2] * v[2], -v[2],
    p[0] * v[3], p[1] * v[4], p[2] * v[5], -v[5],
    p[0] * v[6], p[1] * v[7], p[2] * v[8], -v[8],
    p[0] * v[9], p[1] * v[10], p[2] * v[11] + p[3], -v[11],
  ]);
}

// sRGB colour input (#rrggbb) to linear.
function linear(hex) {
  return [1, 3, 5].map((i) => {
    const c = parseInt(hex.slice(i, i + 2), 16) / 255;
    return c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4);
  });
}

class Viewer {
  constructor(bake, renderer) {
    this.bake = bake;
    this.renderer = renderer;
    this.exposure = bake.description.exposure;
    this.groups = bake.groups.map((g) => ({ name: g.name, scale: g.scale, level: 1, colour: [1, 1, 1], on: true }));
    this.bounds = this.measureBounds();
    this.cameras = bake.cameras.length ? bake.cameras : [this.framing()];
    this.mode = "walk";
    this.useCamera(0);
    this.keys = new Set();
    this.pending = false;
  }

  measureBounds() {
    const p = this.bake.position;
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < p.length; i += 3) {
      for (let k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], p[i + k]); hi[k] = Math.max(hi[k], p[i + k]); }
    }
    const centre = scale(add(lo, hi), 0.5);
    return { lo, hi, centre, size: Math.hypot(...sub(hi, lo)) || 1 };
  }

  framing() {
    const { centre, size } = this.bounds;
    const eye = add(centre, scale(normalise([0.35, 0.25, 1]), size * 1.3));
    return { name: "framing", eye, forward: normalise(sub(centre, eye)), up: UP, yfov: Math.PI / 4 };
  }

  useCamera(i) {
    const c = this.cameras[i];
    this.camera = i;
    this.view = { eye: [...c.eye], forward: [...c.forward], up: [...c.up], yfov: c.yfov };
    this.clip = c.znear ? { near: c.znear, far: c.zfar || this.bounds.size * 4 } : null;
    this.target = add(c.eye, scale(c.forward, Math.max(dot(sub(this.bounds.centre, c.eye), c.forward), this.bounds.size * 0.05)));
    this.redraw();
  }

  // Near and far planes for a free view: the far plane past the farthest
  // corner, the near one half way to the nearest vertex (a sample of them),
  // at least 1e-4 of the far one.
  freeClip() {
    const { lo, hi } = this.bounds;
    const e = this.view.eye;
    let far = 0;
    for (const x of [lo[0], hi[0]]) for (const y of [lo[1], hi[1]]) for (const z of [lo[2], hi[2]]) {
      far = Math.max(far, Math.hypot(x - e[0], y - e[1], z - e[2]));
    }
    far = far * 1.01 + 1e-6;
    const p = this.bake.position;
    const step = 3 * Math.max(1, Math.floor(p.length / 3 / 50000));
    let nearest = Infinity;
    for (let i = 0; i < p.length; i += step) {
      nearest = Math.min(nearest, Math.hypot(p[i] - e[0], p[i + 1] - e[1], p[i + 2] - e[2]));
    }
    return { near: Math.min(Math.max(0.5 * nearest, far * 1e-4), far * 0.05), far };
  }

  mix() {
    const out = new Float32Array(3 * this.groups.length);
    this.groups.forEach((g, k) => {
      const s = g.on ? g.level * g.scale : 0;
      for (let b = 0; b < 3; b++) out[3 * k + b] = s * g.colour[b];
    });
    return out;
  }

  draw() {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    const clip = this.clip || this.freeClip();
    const m = viewProjection(this.view, w / h, clip.near, clip.far);
    this.renderer.draw(m, this.mix(), Math.pow(2, this.exposure));
  }

  redraw() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame((t) => this.frame(t));
  }

  frame(t) {
    this.pending = false;
    const dt = this.last ? Math.min((t - this.last) / 1000, 0.1) : 0;
    this.last = this.keys.size ? t : 0;
    if (this.keys.size && dt > 0) this.walk(dt);
    this.draw();
    if (this.keys.size) this.redraw();
  }

  // The view leaves a file camera: world up, free clip planes.
  free() {
    if (this.clip) { this.clip = null; this.view.up = UP; }
    const f = this.view.forward;
    if (Math.abs(f[1]) > 0.999) this.view.forward = normalise([f[0] + 1e-3, f[1], f[2]]);
  }

  walk(dt) {
    this.free();
    const speed = this.bounds.size * 0.2 * (this.keys.has("Shift") ? 4 : 1) * dt;
    const f = normalise([this.view.forward[0], 0, this.view.forward[2]]);
    const r = normalise(cross(f, UP));
    let move = [0, 0, 0];
    const k = this.keys;
    if (k.has("w") || k.has("ArrowUp")) move = add(move, f);
    if (k.has("s") || k.has("ArrowDown")) move = sub(move, f);
    if (k.has("d") || k.has("ArrowRight")) move = add(move, r);
    if (k.has("a") || k.has("ArrowLeft")) move = sub(move, r);
    if (k.has("e")) move = add(move, UP);
    if (k.has("q")) move = sub(move, UP);
    const step = scale(move, speed);
    this.view.eye = add(this.view.eye, step);
    this.target = add(this.target, step);
  }

  // Turns the view by `yaw` and `pitch` radians: about the eye when
  // walking, about the target when orbiting.
  turn(yaw, pitch) {
    this.free();
    const f = this.view.forward;
    let heading = Math.atan2(f[0], -f[2]) + yaw;
    let elevation = Math.asin(Math.max(-1, Math.min(1, f[1]))) + pitch;
    elevation = Math.max(-1.55, Math.min(1.55, elevation));
    const forward = [Math.sin(heading) * Math.cos(elevation), Math.sin(elevation), -Math.cos(heading) * Math.cos(elevation)];
    if (this.mode === "orbit") {
      const d = Math.hypot(...sub(this.target, this.view.eye));
      this.view.eye = sub(this.target, scale(forward, d));
    } else {
      this.target = add(this.view.eye, scale(forward, Math.hypot(...sub(this.target, this.view.eye))));
    }
    this.view.forward = forward;
    this.redraw();
  }

  pan(dx, dy) {
    this.free();
    const d = Math.hypot(...sub(this.target, this.view.eye));
    const r = normalise(cross(this.view.forward, UP));
    const u = cross(r, this.view.forward);
    const s = d * Math.tan(this.view.yfov / 2) * 2 / canvas.clientHeight;
    const move = add(scale(r, -dx * s), scale(u, dy * s));
    this.view.eye = add(this.view.eye, move);
    this.target = add(this.target, move);
    this.redraw();
  }

  zoom(amount) {
    this.free();
    if (this.mode === "orbit") {
      const d = Math.hypot(...sub(this.target, this.view.eye));
      const next = Math.max(d * Math.exp(amount), this.bounds.size * 1e-3);
      this.view.eye = sub(this.target, scale(this.view.forward, next));
    } else {
      this.view.eye = add(this.view.eye, scale(this.view.forward, -amount * this.bounds.size * 0.2));
    }
    this.redraw();
  }

  // Mean milliseconds a frame takes over `n` frames, each waited for (a
  // pixel read back: finish() alone returns before a GPU process is done).
  measure(n) {
    const gl = this.renderer.gl;
    const pixel = new Uint8Array(4);
    const frame = () => { this.draw(); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel); };
    frame();
    const start = performance.now();
    for (let i = 0; i < n; i++) frame();
    return (performance.now() - start) / n;
  }
}

function buildPanel(viewer) {
  const select = $("camera");
  viewer.cameras.forEach((c, i) => select.add(new Option(c.name, String(i))));
  select.onchange = () => viewer.useCamera(Number(select.value));
  const setMode = (mode) => {
    viewer.mode = mode;
    $("walk").disabled = mode === "walk";
    $("orbit").disabled = mode === "orbit";
  };
  $("walk").onclick = () => setMode("walk");
  $("orbit").onclick = () => setMode("orbit");
  setMode("walk");
  const exposure = $("exposure");
  exposure.min = String(Math.floor(viewer.exposure - 8));
  exposure.max = String(Math.ceil(viewer.exposure + 8));
  exposure.value = String(viewer.exposure);
  const showExposure = () => { $("exposure-value").value = Number(viewer.exposure).toFixed(1); };
  exposure.oninput = () => { viewer.exposure = Number(exposure.value); showExposure(); viewer.redraw(); };
  showExposure();
  const list = $("groups");
  viewer.controls = viewer.groups.map((g, k) => {
    const row = document.createElement("div");
    row.className = "row";
    const on = Object.assign(document.createElement("input"), { type: "checkbox", checked: true, title: "on" });
    const label = Object.assign(document.createElement("label"), { textContent: g.name, title: g.name });
    const level = Object.assign(document.createElement("input"), { type: "range", min: "0", max: "4", step: "0.01", value: "1" });
    const shown = document.createElement("output");
    const colour = Object.assign(document.createElement("input"), { type: "color", value: "#ffffff", title: "colour" });
    const show = () => { shown.value = g.level.toFixed(2); };
    on.onchange = () => { g.on = on.checked; viewer.redraw(); };
    level.oninput = () => { g.level = Number(level.value); show(); viewer.redraw(); };
    colour.oninput = () => { g.colour = linear(colour.value); viewer.redraw(); };
    show();
    row.append(on, label, level, shown, colour);
    list.append(row);
    return { on, level, colour, show };
  });
  $("status").textContent = `${viewer.bake.triangles} triangles, ${viewer.bake.vertices} vertices, ${viewer.groups.length} light groups`;
}

function bindInput(viewer) {
  let drag = null;
  canvas.addEventListener("pointerdown", (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey };
    canvas.setPointerCapture(e.pointerId);
    canvas.focus();
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    if (drag.pan && viewer.mode === "orbit") viewer.pan(dx, dy);
    else {
      const k = viewer.view.yfov / canvas.clientHeight;
      const sign = viewer.mode === "orbit" ? -1 : 1;
      viewer.turn(sign * dx * k, -sign * dy * k);
    }
  });
  canvas.addEventListener("pointerup", () => { drag = null; });
  canvas.addEventListener("contextmenu", (e) => e.preventDefault());
  canvas.addEventListener("wheel", (e) => { e.preventDefault(); viewer.zoom(e.deltaY * 0.001); }, { passive: false });
  const key = (e) => (e.key.length === 1 ? e.key.toLowerCase() : e.key);
  window.addEventListener("keydown", (e) => {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
    if (key(e) === "h") { $("panel").classList.toggle("hidden"); return; }
    if (["w", "a", "s", "d", "q", "e", "Shift", "ArrowUp", "ArrowDown", "ArrowLeft", "ArrowRight"].includes(key(e))) {
      viewer.keys.add(key(e));
      viewer.redraw();
      e.preventDefault();
    }
  });
  window.addEventListener("keyup", (e) => viewer.keys.delete(key(e)));
  window.addEventListener("blur", () => viewer.keys.clear());
  window.addEventListener("resize", () => viewer.redraw());
}

async function main() {
  const name = document.querySelector('meta[name="radiosity-scene"]').content;
  const response = await fetch(name);
  if (!response.ok) throw new Error(`${name}: ${response.status} ${response.statusText}`);
  const bake = readBake(await response.arrayBuffer());
  const renderer = new Renderer(canvas, bake);
  await renderer.loadTextures();
  const viewer = new Viewer(bake, renderer);
  buildPanel(viewer);
  bindInput(viewer);
  viewer.measure(0);
  viewer.loadMs = performance.now();
  return viewer;
}

const ready = main();
ready.catch((e) => { $("error").textContent = `Cannot show the bake: ${e.message}`; });

// For tests and scripts: set a group's slider (and colour), the exposure, the
// view; measure frames.
window.radiosityViewer = {
  ready: ready.then(() => undefined),
  async state() {
    const v = await ready;
    return { groups: v.groups.map((g) => g.name), exposure: v.exposure, loadMs: v.loadMs,
      triangles: v.bake.triangles, vertices: v.bake.vertices, cameras: v.cameras.map((c) => c.name) };
  },
  async setGroup(k, level, colour) {
    const v = await ready;
    const g = v.groups[k];
    g.level = level;
    if (colour) g.colour = colour;
    v.controls[k].level.value = String(level);
    v.controls[k].show();
    v.draw();
    v.renderer.gl.finish();
  },
  async setExposure(stops) {
    const v = await ready;
    v.exposure = stops;
    v.draw();
    v.renderer.gl.finish();
  },
  async useCamera(i) {
    const v = await ready;
    v.useCamera(i);
    v.draw();
    v.renderer.gl.finish();
  },
  async lookAt(eye, target, fovDegrees) {
    const v = await ready;
    v.view = { eye, forward: normalise(sub(target, eye)), up: UP, yfov: (fovDegrees * Math.PI) / 180 };
    v.target = target;
    v.clip = null;
    v.draw();
    v.renderer.gl.finish();
  },
  async bounds() {
    const v = await ready;
    return v.bounds;
  },
  async measure(frames) {
    const v = await ready;
    return v.measure(frames);
  },
};
