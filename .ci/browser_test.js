// Browser tests of baked solutions in headless Chromium (Debian's package),
// driven by playwright-core (npm, found through NODE_PATH with three.js):
//
// 1. `radiosity view`'s page, from the bake's camera, against `radiosity
//    render` of the same bake;
// 2. the page with one light group's slider moved to S, against a render of
//    a new solve with that group's emission times S;
// 3. stock three.js (GLTFLoader, no lights added, default colour management)
//    showing the bake, against the same render.
//
// Each comparison: mean difference at most 1 level of 255, at most 2% of the
// pixels more than 8 levels apart in some channel, leaving out edges (pixels
// within one of a step of more than 24 levels in the render). The canvas
// must not be blank. The fixture (a room with two lamps and a bulb) is
// written here.
//
// Usage: NODE_PATH=<node_modules with playwright-core and three> \
//   node .ci/browser_test.js RADIOSITY_BINARY WORK_DIR
//        node .ci/browser_test.js RADIOSITY_BINARY WORK_DIR --measure BAKE.glb
//        node .ci/browser_test.js RADIOSITY_BINARY WORK_DIR --shots BAKE.glb MIXES
// (--measure prints load and frame times; --shots writes WORK_DIR/mix_N.png
// for each mix of the JSON object MIXES: {"eye": [x, y, z], "target": [x, y,
// z], "fov": degrees, "mixes": [[[level, [r, g, b] or null] per group], ...]}
// (eye and target optional); neither runs in CI.)
"use strict";

const fs = require("fs");
const zlib = require("zlib");
const path = require("path");
const http = require("http");
const { spawn, execFileSync } = require("child_process");
const { chromium } = require("playwright-core");

const [binary, work, flag, measured, mixes] = process.argv.slice(2);
const WIDTH = 480, HEIGHT = 360;
const LIMITS = { mean: 1.0, far: 0.02, farLevels: 8, edge: 24 };
const THREE = path.join(path.dirname(require.resolve("three")), "..");

function run(args) {
  const started = Date.now();
  execFileSync(binary, args, { stdio: ["ignore", "inherit", "inherit"] });
  return (Date.now() - started) / 1000;
}

// A 4 x 2.6 x 4 m room (single-sided walls facing in) with a box, two
// emissive panels of their own materials and a point light, and a camera.
function writeFixture(file) {
  const positions = [], indices = [], primitives = [];
  const materials = [
    { name: "wall", pbrMetallicRoughness: { baseColorFactor: [0.72, 0.7, 0.66, 1], metallicFactor: 0 } },
    { name: "floor", pbrMetallicRoughness: { baseColorFactor: [0.8, 0.7, 0.55, 1], metallicFactor: 0,
      baseColorTexture: { index: 0 } } },
    { name: "box", pbrMetallicRoughness: { baseColorFactor: [0.25, 0.45, 0.7, 1], metallicFactor: 0 } },
    { name: "warm lamp", pbrMetallicRoughness: { baseColorFactor: [0.8, 0.8, 0.8, 1], metallicFactor: 0 },
      emissiveFactor: [1, 0.75, 0.5], extensions: { KHR_materials_emissive_strength: { emissiveStrength: 6 } } },
    { name: "cool lamp", pbrMetallicRoughness: { baseColorFactor: [0.8, 0.8, 0.8, 1], metallicFactor: 0 },
      emissiveFactor: [0.5, 0.7, 1], extensions: { KHR_materials_emissive_strength: { emissiveStrength: 4 } } },
  ];
  const quads = { wall: [], floor: [], box: [], "warm lamp": [], "cool lamp": [] };
  const q = (m, a, b, c, d) => quads[m].push([a, b, c, d]);
  const [X, Y, Z] = [4, 2.6, 4];
  q("floor", [0, 0, 0], [0, 0, Z], [X, 0, Z], [X, 0, 0]);
  q("wall", [0, Y, 0], [X, Y, 0], [X, Y, Z], [0, Y, Z]);
  q("wall", [0, 0, 0], [X, 0, 0], [X, Y, 0], [0, Y, 0]);
  q("wall", [0, 0, Z], [0, Y, Z], [X, Y, Z], [X, 0, Z]);
  q("wall", [0, 0, 0], [0, Y, 0], [0, Y, Z], [0, 0, Z]);
  q("wall", [X, 0, 0], [X, 0, Z], [X, Y, Z], [X, Y, 0]);
  q("warm lamp", [1.2, 2.55, 1.2], [2.0, 2.55, 1.2], [2.0, 2.55, 2.0], [1.2, 2.55, 2.0]);
  q("cool lamp", [3.95, 0.8, 1.0], [3.95, 0.8, 2.4], [3.95, 1.6, 2.4], [3.95, 1.6, 1.0]);
  const [lo, hi] = [[2.2, 0, 0.6], [3.0, 0.9, 1.4]];
  const p = (i, j, k) => [[lo[0], hi[0]][i], [lo[1], hi[1]][j], [lo[2], hi[2]][k]];
  q("box", p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0));
  q("box", p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0));
  q("box", p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1));
  q("box", p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0));
  q("box", p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1));
  const views = [], accessors = [];
  const bin = [];
  let offset = 0;
  const push = (bytes, target) => {
    views.push({ buffer: 0, byteOffset: offset, byteLength: bytes.length, target });
    bin.push(bytes);
    const pad = (4 - (bytes.length % 4)) % 4;
    if (pad) bin.push(Buffer.alloc(pad));
    offset += bytes.length + pad;
    return views.length - 1;
  };
  materials.forEach((m, mi) => {
    const list = quads[m.name];
    const pos = [], idx = [], uv = [];
    for (const quad of list) {
      const first = pos.length / 3;
      for (const v of quad) { pos.push(...v); uv.push(v[0] / 2, v[2] / 2); }
      idx.push(first, first + 1, first + 2, first, first + 2, first + 3);
    }
    const pb = Buffer.from(new Float32Array(pos).buffer);
    const ib = Buffer.from(new Uint16Array(idx).buffer);
    const min = [0, 1, 2].map((k) => Math.min(...pos.filter((_, i) => i % 3 === k)));
    const max = [0, 1, 2].map((k) => Math.max(...pos.filter((_, i) => i % 3 === k)));
    accessors.push({ bufferView: push(pb, 34962), componentType: 5126, count: pos.length / 3, type: "VEC3", min, max });
    accessors.push({ bufferView: push(ib, 34963), componentType: 5123, count: idx.length, type: "SCALAR" });
    const attributes = { POSITION: accessors.length - 2 };
    if (m.pbrMetallicRoughness.baseColorTexture) {
      const ub = Buffer.from(new Float32Array(uv).buffer);
      accessors.push({ bufferView: push(ub, 34962), componentType: 5126, count: uv.length / 2, type: "VEC2" });
      attributes.TEXCOORD_0 = accessors.length - 1;
    }
    primitives.push({ name: m.name, primitive: { attributes, indices: accessors.length - (attributes.TEXCOORD_0 ? 2 : 1), material: mi } });
  });
  // The floor's texture: 8 x 8 checks of two greys, one texel each,
  // repeated every 2 m.
  const image = push(checkerPng(8), undefined);
  const data = Buffer.concat(bin);
  // The camera at (0.4, 1.5, 3.7) looking at (2.6, 1.5, 1.2), both lamps
  // and the box in view: a rotation whose -Z is that direction and whose Y
  // is as near up as it can be.
  const eye = [0.4, 1.5, 3.7];
  const f = norm([2.6 - eye[0], 1.5 - eye[1], 1.2 - eye[2]]);
  const r = norm(cross(f, [0, 1, 0]));
  const u = cross(r, f);
  const json = {
    asset: { version: "2.0", generator: "radiosity browser test fixture" },
    extensionsUsed: ["KHR_materials_emissive_strength", "KHR_lights_punctual"],
    extensions: { KHR_lights_punctual: { lights: [{ name: "bulb", type: "point", color: [1, 0.9, 0.75], intensity: 3 }] } },
    scene: 0,
    scenes: [{ nodes: [...primitives.map((_, i) => i), primitives.length, primitives.length + 1] }],
    nodes: [
      ...primitives.map((p, i) => ({ name: p.name, mesh: i })),
      { name: "bulb", translation: [0.9, 1.7, 3.0], extensions: { KHR_lights_punctual: { light: 0 } } },
      { name: "view", camera: 0, translation: eye, rotation: quaternion(r, u, f.map((x) => -x)) },
    ],
    meshes: primitives.map((p) => ({ name: p.name, primitives: [p.primitive] })),
    materials,
    textures: [{ source: 0, sampler: 0 }],
    samplers: [{ magFilter: 9728, minFilter: 9728 }],
    images: [{ bufferView: image, mimeType: "image/png" }],
    cameras: [{ type: "perspective", perspective: { yfov: 1.0, znear: 0.05 } }],
    accessors,
    bufferViews: views,
    buffers: [{ byteLength: data.length, uri: "data:application/octet-stream;base64," + data.toString("base64") }],
  };
  fs.writeFileSync(file, JSON.stringify(json));
}

// An n x n 8-bit RGB PNG of checks, light (0.9) and darker (0.45) linear
// grey, sRGB encoded.
function checkerPng(n) {
  const srgb = (x) => Math.round(255 * (x <= 0.0031308 ? 12.92 * x : 1.055 * Math.pow(x, 1 / 2.4) - 0.055));
  const rows = [];
  for (let y = 0; y < n; y++) {
    const row = [0];
    for (let x = 0; x < n; x++) { const v = srgb((x + y) % 2 ? 0.45 : 0.9); row.push(v, v, v); }
    rows.push(Buffer.from(row));
  }
  const chunk = (type, body) => {
    const head = Buffer.alloc(4); head.writeUInt32BE(body.length);
    const typed = Buffer.concat([Buffer.from(type, "ascii"), body]);
    const crc = Buffer.alloc(4); crc.writeUInt32BE(crc32(typed));
    return Buffer.concat([head, typed, crc]);
  };
  const header = Buffer.alloc(13);
  header.writeUInt32BE(n, 0); header.writeUInt32BE(n, 4);
  header[8] = 8; header[9] = 2; // 8 bits, RGB
  return Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk("IHDR", header),
    chunk("IDAT", zlib.deflateSync(Buffer.concat(rows))), chunk("IEND", Buffer.alloc(0))]);
}

function crc32(bytes) {
  let c = ~0;
  for (const b of bytes) {
    c ^= b;
    for (let k = 0; k < 8; k++) c = (c >>> 1) ^ (0xedb88320 & -(c & 1));
  }
  return ~c >>> 0;
}

function norm(v) { const l = Math.hypot(...v); return v.map((x) => x / l); }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }

// The quaternion of the rotation whose columns are x, y, z.
function quaternion(x, y, z) {
  const [m00, m01, m02, m10, m11, m12, m20, m21, m22] = [x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]];
  const t = m00 + m11 + m22;
  if (t > 0) {
    const s = 0.5 / Math.sqrt(t + 1);
    return [(m21 - m12) * s, (m02 - m20) * s, (m10 - m01) * s, 0.25 / s];
  }
  if (m00 > m11 && m00 > m22) {
    const s = 2 * Math.sqrt(1 + m00 - m11 - m22);
    return [0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s];
  }
  if (m11 > m22) {
    const s = 2 * Math.sqrt(1 + m11 - m00 - m22);
    return [(m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s];
  }
  const s = 2 * Math.sqrt(1 + m22 - m00 - m11);
  return [(m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s];
}

// Serves `dir` (the test's files) and three.js, with CORS for the viewer's
// page on its own origin.
function staticServer(dir) {
  const types = { ".html": "text/html", ".js": "text/javascript", ".png": "image/png", ".glb": "model/gltf-binary" };
  const server = http.createServer((req, res) => {
    const url = decodeURIComponent(req.url.split("?")[0]);
    const file = url.startsWith("/three/") ? path.join(THREE, url.slice(7)) : path.join(dir, url);
    const root = url.startsWith("/three/") ? THREE : dir;
    if (!path.resolve(file).startsWith(path.resolve(root)) || !fs.existsSync(file) || fs.statSync(file).isDirectory()) {
      res.writeHead(404); res.end(); return;
    }
    res.writeHead(200, { "Content-Type": types[path.extname(file)] || "application/octet-stream", "Access-Control-Allow-Origin": "*" });
    fs.createReadStream(file).pipe(res);
  });
  return new Promise((resolve) => server.listen(0, "127.0.0.1", () => resolve(server)));
}

// Starts `radiosity view` and waits for the address it prints.
function startView(bake) {
  const child = spawn(binary, ["view", bake], { stdio: ["ignore", "pipe", "inherit"] });
  return new Promise((resolve, reject) => {
    let text = "";
    child.stdout.on("data", (d) => {
      text += d;
      const m = /http:\/\/127\.0\.0\.1:\d+\//.exec(text);
      if (m) resolve({ child, url: m[0] });
    });
    child.on("exit", (code) => reject(new Error(`radiosity view exited with ${code}: ${text}`)));
  });
}

// In the page: the canvas's pixels against the PNG at `reference`, and
// whether the canvas shows anything.
async function compareInPage(page, canvasSelector, reference, limits) {
  return page.evaluate(async ({ canvasSelector, reference, limits }) => {
    const canvas = document.querySelector(canvasSelector);
    const w = canvas.width, h = canvas.height;
    const pixels = (source) => {
      const c = document.createElement("canvas");
      c.width = w; c.height = h;
      const g = c.getContext("2d", { willReadFrequently: true });
      g.drawImage(source, 0, 0);
      return g.getImageData(0, 0, w, h).data;
    };
    const got = pixels(canvas);
    const blob = await (await fetch(reference)).blob();
    const image = await createImageBitmap(blob, { colorSpaceConversion: "none", premultiplyAlpha: "none" });
    if (image.width !== w || image.height !== h) return { error: `sizes differ: ${image.width}x${image.height} and ${w}x${h}` };
    const want = pixels(image);
    // Edges of the render: a step of more than `edge` levels to a neighbour,
    // and the pixels next to it.
    const step = new Uint8Array(w * h);
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) {
      const i = 4 * (y * w + x);
      for (const [dx, dy] of [[1, 0], [0, 1]]) {
        if (x + dx >= w || y + dy >= h) continue;
        const j = 4 * ((y + dy) * w + x + dx);
        for (let c = 0; c < 3; c++) if (Math.abs(want[i + c] - want[j + c]) > limits.edge) { step[y * w + x] = 1; step[(y + dy) * w + x + dx] = 1; }
      }
    }
    let sum = 0, n = 0, far = 0, edges = 0, lit = 0, lum = 0, lum2 = 0;
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) {
      const i = 4 * (y * w + x);
      const l = (got[i] + got[i + 1] + got[i + 2]) / 3;
      lum += l; lum2 += l * l;
      if (l > 4) lit++;
      let edge = false;
      for (let dy = -1; dy <= 1 && !edge; dy++) for (let dx = -1; dx <= 1; dx++) {
        const xx = x + dx, yy = y + dy;
        if (xx >= 0 && yy >= 0 && xx < w && yy < h && step[yy * w + xx]) { edge = true; break; }
      }
      if (edge) { edges++; continue; }
      let worst = 0;
      for (let c = 0; c < 3; c++) { const d = Math.abs(got[i + c] - want[i + c]); sum += d; worst = Math.max(worst, d); }
      n++;
      if (worst > limits.farLevels) far++;
    }
    const mean = lum / (w * h);
    return { mean: sum / (3 * n), far: far / n, edges: edges / (w * h), lit: lit / (w * h),
      deviation: Math.sqrt(Math.max(0, lum2 / (w * h) - mean * mean)) };
  }, { canvasSelector, reference, limits });
}

function check(what, m) {
  const line = `${what}: mean difference ${m.mean?.toFixed(3)} levels, ${(100 * m.far).toFixed(2)}% of pixels more than ${LIMITS.farLevels} apart, ${(100 * m.edges).toFixed(1)}% left out as edges; ${(100 * m.lit).toFixed(0)}% of the canvas lit`;
  console.log(line);
  const failures = [];
  if (m.error) failures.push(m.error);
  if (!(m.lit > 0.2 && m.deviation > 3)) failures.push("the canvas is blank");
  if (!(m.mean <= LIMITS.mean)) failures.push(`mean difference above ${LIMITS.mean}`);
  if (!(m.far <= LIMITS.far)) failures.push(`more than ${100 * LIMITS.far}% of pixels far apart`);
  return failures.map((f) => `${what}: ${f}`);
}

const THREE_PAGE = `<!doctype html><html><head><style>html,body{margin:0;background:#000}canvas{display:block}</style>
<script type="importmap">{"imports":{"three":"/three/build/three.module.js","three/addons/":"/three/examples/jsm/"}}</script></head>
<body><script type="module">
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(innerWidth, innerHeight);
document.body.append(renderer.domElement);
window.done = new GLTFLoader().loadAsync(new URLSearchParams(location.search).get("bake")).then((gltf) => {
  const camera = gltf.cameras[0];
  camera.aspect = innerWidth / innerHeight;
  camera.updateProjectionMatrix();
  renderer.render(gltf.scene, camera);
});
</script></body></html>`;

async function main() {
  fs.mkdirSync(work, { recursive: true });
  const browser = await chromium.launch({
    executablePath: "/usr/bin/chromium",
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--no-first-run", "--disable-quic"],
  });
  const failures = [];
  try {
    if (flag === "--measure") {
      await measure(browser, measured);
      return;
    }
    if (flag === "--shots") {
      await shots(browser, measured, JSON.parse(mixes));
      return;
    }
    const scene = path.join(work, "room.gltf");
    writeFixture(scene);
    const solve = ["--light-group", "bulb=bulb", "--patch-size", "0.5", "--quiet"];
    const bake = path.join(work, "room.glb");
    run(["bake", scene, "-o", bake, ...solve]);
    run(["render", bake, "--out", work, "--width", `${WIDTH}`, "--height", `${HEIGHT}`, "--quiet"]);
    const description = JSON.parse(execFileSync(process.execPath, ["-e", `
      const b = require("fs").readFileSync(${JSON.stringify(bake)});
      const n = b.readUInt32LE(12);
      process.stdout.write(JSON.stringify(JSON.parse(b.subarray(20, 20 + n)).asset.extras.radiosity));`]));
    const names = description.groups.map((g) => g.name);
    console.log(`bake: light groups ${names.join(", ")}; exposure ${description.exposure.toFixed(3)}`);
    // A new solve with the warm lamp at a quarter, rendered at the first
    // bake's exposure (the page keeps it while the slider moves).
    const k = names.indexOf("warm lamp"), s = 0.25;
    const scaled = path.join(work, "room_scaled.glb");
    run(["bake", scene, "-o", scaled, ...solve, "--group-scale", `warm lamp=${s}`]);
    run(["render", scaled, "--out", work, "--width", `${WIDTH}`, "--height", `${HEIGHT}`, "--quiet",
      "--exposure", `${description.exposure}`]);
    const server = await staticServer(work);
    const base = `http://127.0.0.1:${server.address().port}`;
    const view = await startView(bake);
    try {
      const page = await browser.newPage({ viewport: { width: WIDTH, height: HEIGHT }, deviceScaleFactor: 1 });
      page.on("pageerror", (e) => failures.push(`viewer page: ${e.message}`));
      await page.goto(view.url);
      await page.evaluate(() => window.radiosityViewer.ready);
      await page.evaluate(() => window.radiosityViewer.useCamera(0));
      await page.screenshot({ path: path.join(work, "viewer.png") });
      failures.push(...check("viewer against render", await compareInPage(page, "#view", `${base}/room.png`, LIMITS)));
      await page.evaluate(([k, s]) => window.radiosityViewer.setGroup(k, s), [k, s]);
      await page.screenshot({ path: path.join(work, "viewer_scaled.png") });
      failures.push(...check(`viewer with '${names[k]}' at ${s} against a new solve`, await compareInPage(page, "#view", `${base}/room_scaled.png`, LIMITS)));
      fs.writeFileSync(path.join(work, "three.html"), THREE_PAGE);
      const three = await browser.newPage({ viewport: { width: WIDTH, height: HEIGHT }, deviceScaleFactor: 1 });
      three.on("pageerror", (e) => failures.push(`three.js page: ${e.message}`));
      await three.goto(`${base}/three.html?bake=/room.glb`);
      await three.waitForFunction(() => window.done !== undefined);
      await three.evaluate(() => window.done);
      await three.screenshot({ path: path.join(work, "three.png") });
      failures.push(...check("three.js against render", await compareInPage(three, "canvas", `${base}/room.png`, LIMITS)));
    } finally {
      view.child.kill();
      server.close();
    }
  } finally {
    await browser.close();
  }
  if (failures.length) {
    for (const f of failures) console.error(`FAIL ${f}`);
    process.exit(1);
  }
  console.log("browser tests passed");
}

// Load and frame times of the page for a big bake (not run in CI).
async function measure(browser, bake) {
  const view = await startView(bake);
  try {
    const page = await browser.newPage({ viewport: { width: 1280, height: 720 }, deviceScaleFactor: 1 });
    const started = Date.now();
    await page.goto(view.url);
    await page.evaluate(() => window.radiosityViewer.ready);
    const wall = (Date.now() - started) / 1000;
    const state = await page.evaluate(() => window.radiosityViewer.state());
    const frame = await page.evaluate(() => window.radiosityViewer.measure(20));
    await page.evaluate(() => window.radiosityViewer.setGroup(0, 0.5));
    const relit = await page.evaluate(() => window.radiosityViewer.measure(20));
    console.log(JSON.stringify({ bake, triangles: state.triangles, vertices: state.vertices,
      groups: state.groups.length, loadSeconds: wall, loadMsInPage: state.loadMs, frameMs: frame, frameMsAfterSlider: relit }));
  } finally {
    view.child.kill();
  }
}

// Pictures of a bake relit: the canvas (panel hidden) for each mix.
async function shots(browser, bake, { eye, target, fov, mixes: list }) {
  const view = await startView(bake);
  try {
    const page = await browser.newPage({ viewport: { width: 640, height: 480 }, deviceScaleFactor: 1 });
    await page.goto(view.url);
    await page.evaluate(() => window.radiosityViewer.ready);
    console.log(JSON.stringify(await page.evaluate(() => window.radiosityViewer.state())));
    await page.evaluate(() => document.getElementById("panel").classList.add("hidden"));
    console.log(JSON.stringify(await page.evaluate(() => window.radiosityViewer.bounds())));
    if (eye) await page.evaluate(([e, t, f]) => window.radiosityViewer.lookAt(e, t, f), [eye, target, fov || 45]);
    for (const [n, mix] of list.entries()) {
      for (const [k, [level, colour]] of mix.entries()) {
        await page.evaluate(([k, level, colour]) => window.radiosityViewer.setGroup(k, level, colour), [k, level, colour]);
      }
      await page.locator("#view").screenshot({ path: path.join(work, `mix_${n + 1}.png`) });
    }
  } finally {
    view.child.kill();
  }
}

main().catch((e) => { console.error(e); process.exit(1); });
