// Draws a bake with WebGL2 as `radiosity render` draws it: per pixel, the
// light mixed from the groups (each group's values times its slider, colour
// and scale, summed in the vertex shader), times the texture where there is
// one, over pi, exposed, tone mapped (the same ACES fit) and sRGB encoded.
// Relighting changes uniforms only: the vertex data is uploaded once.
"use strict";

import { textureImage } from "./gltf.js";

// Most light groups the shaders take.
export const MAX_GROUPS = 64;
// Width of the data texture that holds the groups' values.
const DATA_WIDTH = 2048;

const VERTEX = `#version 300 es
precision highp float;
precision highp int;
precision highp sampler2D;
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec2 aUv;
uniform mat4 uViewProjection;
uniform sampler2D uGroups;
uniform int uGroupCount;
uniform vec3 uMix[${MAX_GROUPS}];
out vec3 vLight;
out vec2 vUv;
void main() {
  vec3 light = vec3(0.0);
  int first = gl_VertexID * uGroupCount;
  for (int k = 0; k < uGroupCount; k++) {
    int i = first + k;
    light += uMix[k] * texelFetch(uGroups, ivec2(i % ${DATA_WIDTH}, i / ${DATA_WIDTH}), 0).rgb;
  }
  vLight = light;
  vUv = aUv;
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}`;

const FRAGMENT = `#version 300 es
precision highp float;
in vec3 vLight;
in vec2 vUv;
uniform bool uTextured;
uniform sampler2D uTexture;
uniform vec3 uFactor;
uniform float uGain;
out vec4 colour;
// The ACES fit of radiosity's tone map (src/render/tonemap.rs), row by row.
vec3 aces(vec3 x) {
  vec3 v = vec3(dot(vec3(0.59719, 0.35458, 0.04823), x),
                dot(vec3(0.07600, 0.90834, 0.01566), x),
                dot(vec3(0.02840, 0.13383, 0.83777), x));
  vec3 a = v * (v + 0.0245786) - 0.000090537;
  vec3 b = v * (0.983729 * v + 0.4329510) + 0.238081;
  v = a / b;
  vec3 o = vec3(dot(vec3(1.60475, -0.53108, -0.07367), v),
                dot(vec3(-0.10208, 1.10813, -0.00605), v),
                dot(vec3(-0.00327, -0.07276, 1.07602), v));
  return clamp(o, 0.0, 1.0);
}
vec3 srgb(vec3 v) {
  vec3 lo = 12.92 * v;
  vec3 hi = 1.055 * pow(v, vec3(1.0 / 2.4)) - 0.055;
  return mix(hi, lo, vec3(lessThanEqual(v, vec3(0.0031308))));
}
void main() {
  vec3 reflected = vLight;
  if (uTextured) reflected *= texture(uTexture, vUv).rgb * uFactor;
  vec3 radiance = max(reflected, vec3(0.0)) * 0.3183098861837907;
  colour = vec4(srgb(aces(radiance * uGain)), 1.0);
}`;

function compile(gl, type, source) {
  const s = gl.createShader(type);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
  return s;
}

export class Renderer {
  constructor(canvas, bake) {
    const gl = canvas.getContext("webgl2", { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error("this browser has no WebGL2");
    if (bake.groups.length > MAX_GROUPS) {
      throw new Error(`the bake has ${bake.groups.length} light groups; the viewer draws at most ${MAX_GROUPS}`);
    }
    this.gl = gl;
    this.bake = bake;
    const program = gl.createProgram();
    gl.attachShader(program, compile(gl, gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(program, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT));
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
    this.program = program;
    const u = (n) => gl.getUniformLocation(program, n);
    this.uniforms = {
      viewProjection: u("uViewProjection"), groups: u("uGroups"), groupCount: u("uGroupCount"),
      mix: u("uMix"), textured: u("uTextured"), texture: u("uTexture"), factor: u("uFactor"), gain: u("uGain"),
    };
    this.vao = gl.createVertexArray();
    gl.bindVertexArray(this.vao);
    const buffer = (target, data) => {
      const b = gl.createBuffer();
      gl.bindBuffer(target, b);
      gl.bufferData(target, data, gl.STATIC_DRAW);
      return b;
    };
    buffer(gl.ARRAY_BUFFER, bake.position);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    buffer(gl.ARRAY_BUFFER, bake.uv);
    gl.enableVertexAttribArray(1);
    gl.vertexAttribPointer(1, 2, gl.FLOAT, false, 0, 0);
    buffer(gl.ELEMENT_ARRAY_BUFFER, bake.index);
    // The groups' values, three floats a texel, padded to whole rows.
    const texels = bake.light.length / 3;
    const rows = Math.max(1, Math.ceil(texels / DATA_WIDTH));
    if (rows > gl.getParameter(gl.MAX_TEXTURE_SIZE)) throw new Error("too many vertices times light groups for one data texture");
    const data = new Float32Array(DATA_WIDTH * rows * 3);
    data.set(bake.light);
    this.data = gl.createTexture();
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.data);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB32F, DATA_WIDTH, rows, 0, gl.RGB, gl.FLOAT, data);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    this.textures = new Map();
  }

  // Uploads the materials' textures (sRGB: sampling gives linear values).
  async loadTextures() {
    const gl = this.gl;
    for (const r of this.bake.ranges) {
      const m = this.bake.materials[r.material];
      if (!m || !m.texture || this.textures.has(r.material)) continue;
      const image = await textureImage(this.bake, r.material);
      const t = gl.createTexture();
      gl.activeTexture(gl.TEXTURE1);
      gl.bindTexture(gl.TEXTURE_2D, t);
      gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.SRGB8_ALPHA8, gl.RGBA, gl.UNSIGNED_BYTE, image);
      const s = m.texture.sampler || {};
      const nearest = s.magFilter === 9728;
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, nearest ? gl.NEAREST : gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, nearest ? gl.NEAREST : gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, s.wrapS || gl.REPEAT);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, s.wrapT || gl.REPEAT);
      this.textures.set(r.material, t);
    }
  }

  // Draws one frame: `viewProjection` a column-major 4x4, `mix` three
  // floats per group (slider times colour times the group's scale), `gain`
  // 2^exposure.
  draw(viewProjection, mix, gain) {
    const gl = this.gl;
    const u = this.uniforms;
    gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
    gl.clearColor(0, 0, 0, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LEQUAL);
    gl.enable(gl.CULL_FACE);
    gl.cullFace(gl.BACK);
    gl.frontFace(gl.CCW);
    gl.useProgram(this.program);
    gl.bindVertexArray(this.vao);
    gl.uniformMatrix4fv(u.viewProjection, false, viewProjection);
    gl.uniform1i(u.groupCount, this.bake.groups.length);
    gl.uniform3fv(u.mix, mix);
    gl.uniform1f(u.gain, gain);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.data);
    gl.uniform1i(u.groups, 0);
    gl.uniform1i(u.texture, 1);
    for (const r of this.bake.ranges) {
      const m = this.bake.materials[r.material];
      const texture = this.textures.get(r.material);
      gl.uniform1i(u.textured, texture ? 1 : 0);
      gl.uniform3fv(u.factor, m ? m.factor : [1, 1, 1]);
      if (texture) {
        gl.activeTexture(gl.TEXTURE1);
        gl.bindTexture(gl.TEXTURE_2D, texture);
      }
      gl.drawElements(gl.TRIANGLES, r.count, gl.UNSIGNED_INT, 4 * r.start);
    }
  }
}
