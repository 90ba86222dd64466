// Reads a bake written by `radiosity bake` (glTF 2.0, .glb or .gltf with its
// buffer embedded) into flat arrays for the viewer: world positions, texture
// coordinates, the light groups' values per vertex, and draw ranges per
// material. Written for this project's own bakes; it reads any node tree and
// index type, but only the attributes the bake writes.
"use strict";

const GLB_MAGIC = 0x46546c67; // "glTF"
const CHUNK_JSON = 0x4e4f534a;
const CHUNK_BIN = 0x004e4942;
const COMPONENTS = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4, MAT4: 16 };
const ARRAYS = {
  5120: Int8Array, 5121: Uint8Array, 5122: Int16Array,
  5123: Uint16Array, 5125: Uint32Array, 5126: Float32Array,
};

// Splits a .glb into its JSON and binary chunk, or reads a .gltf's JSON
// and its data-URI buffers.
function parseContainer(bytes) {
  const view = new DataView(bytes);
  if (bytes.byteLength >= 12 && view.getUint32(0, true) === GLB_MAGIC) {
    let offset = 12, json = null, bin = null;
    while (offset + 8 <= bytes.byteLength) {
      const length = view.getUint32(offset, true);
      const type = view.getUint32(offset + 4, true);
      const body = bytes.slice(offset + 8, offset + 8 + length);
      if (type === CHUNK_JSON) json = JSON.parse(new TextDecoder().decode(body));
      else if (type === CHUNK_BIN) bin = body;
      offset += 8 + length;
    }
    if (!json) throw new Error("the .glb file has no JSON chunk");
    return { json, buffers: [bin] };
  }
  const json = JSON.parse(new TextDecoder().decode(bytes));
  const buffers = (json.buffers || []).map((b, i) => {
    const m = /^data:[^;,]*;base64,(.*)$/.exec(b.uri || "");
    if (!m) throw new Error(`buffer ${i} is not embedded as a base64 data URI`);
    const text = atob(m[1]);
    const out = new Uint8Array(text.length);
    for (let k = 0; k < text.length; k++) out[k] = text.charCodeAt(k);
    return out.buffer;
  });
  return { json, buffers };
}

// The values of accessor `index` as a typed array of `count * components`.
function readAccessor(json, buffers, index) {
  const a = json.accessors[index];
  const components = COMPONENTS[a.type];
  const Type = ARRAYS[a.componentType];
  if (!components || !Type) throw new Error(`accessor ${index} has an unknown type`);
  const n = a.count * components;
  if (a.bufferView === undefined) return new Type(n);
  const v = json.bufferViews[a.bufferView];
  const buffer = buffers[v.buffer || 0];
  const start = (v.byteOffset || 0) + (a.byteOffset || 0);
  const size = Type.BYTES_PER_ELEMENT;
  const stride = v.byteStride || components * size;
  if (stride === components * size && start % size === 0) {
    return new Type(buffer, start, n);
  }
  const data = new DataView(buffer);
  const out = new Type(n);
  const getter = {
    5120: "getInt8", 5121: "getUint8", 5122: "getInt16",
    5123: "getUint16", 5125: "getUint32", 5126: "getFloat32",
  }[a.componentType];
  for (let i = 0; i < a.count; i++) {
    for (let c = 0; c < components; c++) {
      out[i * components + c] = data[getter](start + i * stride + c * size, true);
    }
  }
  return out;
}

// 4x4 column-major matrices.
function multiply(a, b) {
  const out = new Float64Array(16);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
  }
  return out;
}

function nodeMatrix(node) {
  if (node.matrix) return Float64Array.from(node.matrix);
  const [tx, ty, tz] = node.translation || [0, 0, 0];
  const [x, y, z, w] = node.rotation || [0, 0, 0, 1];
  const [sx, sy, sz] = node.scale || [1, 1, 1];
  return Float64Array.from([
    (1 - 2 * (y * y + z * z)) * sx, 2 * (x * y + z * w) * sx, 2 * (x * z - y * w) * sx, 0,
    2 * (x * y - z * w) * sy, (1 - 2 * (x * x + z * z)) * sy, 2 * (y * z + x * w) * sy, 0,
    2 * (x * z + y * w) * sz, 2 * (y * z - x * w) * sz, (1 - 2 * (x * x + y * y)) * sz, 0,
    tx, ty, tz, 1,
  ]);
}

const IDENTITY = Float64Array.from([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);

// Every node of the default scene with its world matrix.
function placedNodes(json) {
  const out = [];
  const scene = json.scenes ? json.scenes[json.scene || 0] : null;
  const roots = scene ? scene.nodes : (json.nodes || []).map((_, i) => i);
  const walk = (i, parent, depth) => {
    if (depth > 64) throw new Error("the node tree is deeper than 64");
    const world = multiply(parent, nodeMatrix(json.nodes[i]));
    out.push({ index: i, world });
    for (const c of json.nodes[i].children || []) walk(c, world, depth + 1);
  };
  for (const r of roots) walk(r, IDENTITY, 0);
  return out;
}

// A camera node as eye, forward, up, vertical field of view and clip planes.
function cameraOf(json, node, world, index) {
  const c = json.cameras[node.camera];
  if (!c || c.type !== "perspective") return null;
  const p = c.perspective;
  const col = (k) => [world[k * 4], world[k * 4 + 1], world[k * 4 + 2]];
  const norm = (v) => { const l = Math.hypot(...v) || 1; return v.map((x) => x / l); };
  return {
    name: c.name || node.name || `camera ${index}`,
    eye: col(3),
    forward: norm(col(2).map((x) => -x)),
    up: norm(col(1)),
    yfov: p.yfov,
    znear: p.znear,
    zfar: p.zfar,
  };
}

// The bake as the viewer draws it.
export function readBake(bytes) {
  const { json, buffers } = parseContainer(bytes);
  const description = ((json.asset || {}).extras || {}).radiosity;
  if (!description || description.version !== 2) {
    throw new Error("this file is not a bake with light groups (run `radiosity bake` again)");
  }
  const groups = description.groups;
  const G = groups.length;
  const materials = (json.materials || []).map((m) => {
    const pbr = m.pbrMetallicRoughness || {};
    const texture = pbr.baseColorTexture ? json.textures[pbr.baseColorTexture.index] : null;
    return {
      name: m.name || "",
      factor: (pbr.baseColorFactor || [1, 1, 1, 1]).slice(0, 3),
      texture: texture
        ? { image: texture.source, sampler: json.samplers ? json.samplers[texture.sampler] : null }
        : null,
    };
  });
  const positions = [], uvs = [], values = [], draws = [], cameras = [];
  let vertices = 0;
  for (const { index, world } of placedNodes(json)) {
    const node = json.nodes[index];
    if (node.camera !== undefined) {
      const c = cameraOf(json, node, world, cameras.length);
      if (c) cameras.push(c);
    }
    if (node.mesh === undefined) continue;
    for (const prim of json.meshes[node.mesh].primitives) {
      if ((prim.mode === undefined ? 4 : prim.mode) !== 4) continue;
      const at = prim.attributes;
      const p = readAccessor(json, buffers, at.POSITION);
      const n = p.length / 3;
      const world32 = new Float32Array(p.length);
      for (let i = 0; i < n; i++) {
        const [x, y, z] = [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
        for (let r = 0; r < 3; r++) {
          world32[3 * i + r] = world[r] * x + world[4 + r] * y + world[8 + r] * z + world[12 + r];
        }
      }
      positions.push(world32);
      uvs.push(at.TEXCOORD_0 !== undefined ? readAccessor(json, buffers, at.TEXCOORD_0) : new Float32Array(2 * n));
      const own = groups.map((g) => {
        if (at[g.attribute] === undefined) throw new Error(`a primitive lacks ${g.attribute}`);
        return readAccessor(json, buffers, at[g.attribute]);
      });
      values.push(own);
      const indices = prim.indices !== undefined
        ? readAccessor(json, buffers, prim.indices)
        : Uint32Array.from({ length: n }, (_, i) => i);
      // A mirroring transform turns the winding around.
      const det = world[0] * (world[5] * world[10] - world[9] * world[6])
        - world[4] * (world[1] * world[10] - world[9] * world[2])
        + world[8] * (world[1] * world[6] - world[5] * world[2]);
      draws.push({ material: prim.material === undefined ? -1 : prim.material, indices, first: vertices, mirrored: det < 0 });
      vertices += n;
    }
  }
  // Flat arrays over every vertex.
  const position = new Float32Array(3 * vertices);
  const uv = new Float32Array(2 * vertices);
  // Per vertex, G values of 3 floats: vertex i's group k at (i * G + k) * 3.
  const light = new Float32Array(3 * G * vertices);
  let at = 0;
  positions.forEach((p, d) => {
    position.set(p, 3 * at);
    uv.set(uvs[d], 2 * at);
    const n = p.length / 3;
    for (let k = 0; k < G; k++) {
      const v = values[d][k];
      for (let i = 0; i < n; i++) {
        const o = ((at + i) * G + k) * 3;
        light[o] = v[3 * i]; light[o + 1] = v[3 * i + 1]; light[o + 2] = v[3 * i + 2];
      }
    }
    at += n;
  });
  // Indices rebased onto the flat arrays, grouped by material.
  const byMaterial = new Map();
  let triangles = 0;
  for (const d of draws) {
    const list = byMaterial.get(d.material) || [];
    list.push(d);
    byMaterial.set(d.material, list);
    triangles += d.indices.length / 3;
  }
  const index = new Uint32Array(3 * triangles);
  const ranges = [];
  let next = 0;
  for (const [material, list] of byMaterial) {
    const start = next;
    for (const d of list) {
      for (let t = 0; t < d.indices.length; t += 3) {
        const [a, b, c] = [d.indices[t], d.indices[t + 1], d.indices[t + 2]];
        index[next++] = d.first + a;
        index[next++] = d.first + (d.mirrored ? c : b);
        index[next++] = d.first + (d.mirrored ? b : c);
      }
    }
    ranges.push({ material, start, count: next - start });
  }
  return {
    json, buffers, description, groups, materials, cameras,
    position, uv, light, index, ranges, vertices, triangles,
  };
}

// The image of material `m`'s texture as an ImageBitmap.
export async function textureImage(bake, m) {
  const img = bake.json.images[bake.materials[m].texture.image];
  let blob;
  if (img.bufferView !== undefined) {
    const v = bake.json.bufferViews[img.bufferView];
    const bytes = new Uint8Array(bake.buffers[v.buffer || 0], v.byteOffset || 0, v.byteLength);
    blob = new Blob([bytes], { type: img.mimeType || "image/png" });
  } else {
    blob = await (await fetch(img.uri)).blob();
  }
  return createImageBitmap(blob, { colorSpaceConversion: "none", premultiplyAlpha: "none" });
}
