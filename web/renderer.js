// renderer.js: plain WebGL2 around MaterialX's generated ESSL. The material's program renders
// the night scene (scene.js) into a linear RGBA32F target (the frame the test reads back and
// compares with the C++ render), and the R_A table: one pixel per (observation, entrance) entry,
// a flat patch lit by a directional light along wi and seen from wo (analysis/photometry.h's
// angles), R_A = pixel * cos(theta_o). A display pass shows the frame with an exposure and the
// sRGB transfer function. Programs live in named slots ("material": MaterialX's shader of the
// document; "baseline": the GGX baseline, baseline.js), each keeping its uniforms; the frame and
// the table are drawn with the selected one.
import { LIGHT_DIRECTIONAL, LIGHT_POINT } from './mx.js';
import { buildScene, signMesh, sphereMesh, projection } from './scene.js';

const DEG = Math.PI / 180;
const IDENTITY = new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);

function compile(gl, type, source, label) {
  const s = gl.createShader(type);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS))
    throw new Error(`${label} shader does not compile: ${gl.getShaderInfoLog(s)}`);
  return s;
}

function link(gl, vertex, fragment, label) {
  const p = gl.createProgram();
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, vertex, `${label} vertex`));
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, fragment, `${label} fragment`));
  gl.bindAttribLocation(p, 0, 'i_position');
  gl.bindAttribLocation(p, 1, 'i_normal');
  gl.bindAttribLocation(p, 2, 'i_tangent');
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS))
    throw new Error(`${label} program does not link: ${gl.getProgramInfoLog(p)}`);
  return p;
}

// A float colour target with depth.
function target(gl, width, height) {
  const tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, tex);
  gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, width, height);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  const depth = gl.createRenderbuffer();
  gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
  gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, width, height);
  const fbo = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
  gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
  if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE)
    throw new Error('WebGL2: a float (RGBA32F) render target is not supported here');
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  return { tex, fbo, width, height };
}

function upload(gl, m) {
  const vao = gl.createVertexArray();
  gl.bindVertexArray(vao);
  const vb = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, vb);
  gl.bufferData(gl.ARRAY_BUFFER, m.vertices, gl.STATIC_DRAW);
  for (let a = 0; a < 3; ++a) {
    gl.enableVertexAttribArray(a);
    gl.vertexAttribPointer(a, 3, gl.FLOAT, false, 36, 12 * a);
  }
  const ib = gl.createBuffer();
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
  gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, m.indices, gl.STATIC_DRAW);
  gl.bindVertexArray(null);
  return { vao, vb, count: m.indices.length };
}

const DISPLAY_VERTEX = `#version 300 es
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}`;
// Exposure, then the sRGB transfer function (IEC 61966-2-1) of the clamped linear value.
const DISPLAY_FRAGMENT = `#version 300 es
precision highp float;
uniform highp sampler2D u_frame;
uniform float u_gain;
out vec4 color;
void main() {
  ivec2 size = textureSize(u_frame, 0);
  vec3 c = clamp(texelFetch(u_frame, ivec2(gl_FragCoord.xy), 0).rgb * u_gain, 0.0, 1.0);
  vec3 s = mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
  color = vec4(s, 1.0);
}`;

export class Renderer {
  // canvas: the page's WebGL2 canvas; its width and height are the frame's.
  constructor(canvas) {
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has no WebGL2');
    if (!gl.getExtension('EXT_color_buffer_float'))
      throw new Error('WebGL2 without EXT_color_buffer_float: cannot render linear float frames');
    this.gl = gl;
    this.width = canvas.width;
    this.height = canvas.height;
    this.frameTarget = target(gl, this.width, this.height);
    this.display = link(gl, DISPLAY_VERTEX, DISPLAY_FRAGMENT, 'display');
    this.slots = new Map(); // slot name -> { program, locations }
    this.current = '';
    this.meshes = null;
    this.sceneKey = '';
  }

  // Compiles a shader ({vertex, fragment}) into `slot` (replacing its program; on a compile
  // error the slot keeps it) and selects the slot; the compile-and-link time in milliseconds.
  setShader(essl, slot = 'material') {
    const gl = this.gl;
    const t0 = performance.now();
    const program = link(gl, essl.vertex, essl.fragment, slot);
    if (this.slots.has(slot)) gl.deleteProgram(this.slots.get(slot).program);
    this.slots.set(slot, { program, locations: new Map() });
    this.current = slot;
    return performance.now() - t0;
  }

  hasShader(slot) {
    return this.slots.has(slot);
  }

  // Selects the program the next frames, tables and uniforms use.
  use(slot) {
    if (!this.slots.has(slot)) throw new Error(`no ${slot} shader compiled`);
    this.current = slot;
  }

  get program() {
    return this.slots.get(this.current).program;
  }

  loc(name) {
    const { program, locations } = this.slots.get(this.current);
    if (!locations.has(name)) locations.set(name, this.gl.getUniformLocation(program, name));
    return locations.get(name);
  }

  // Uniforms [{name, type (MaterialX's), value (number or array)}]: the generated shader's
  // defaults and the node's inputs (named `<node>_<input>` by MaterialX).
  setUniforms(list) {
    const gl = this.gl;
    gl.useProgram(this.program);
    for (const { name, type, value } of list) {
      const l = this.loc(name);
      if (l === null) continue;
      if (type === 'float') gl.uniform1f(l, value);
      else if (type === 'integer' || type === 'boolean') gl.uniform1i(l, value);
      else if (type === 'vector2') gl.uniform2fv(l, value);
      else if (type === 'color3' || type === 'vector3') gl.uniform3fv(l, value);
      else if (type === 'color4' || type === 'vector4') gl.uniform4fv(l, value);
    }
  }

  setCommon(viewProjection, viewPosition, light) {
    const gl = this.gl;
    gl.useProgram(this.program);
    gl.uniformMatrix4fv(this.loc('u_worldMatrix'), false, IDENTITY);
    gl.uniformMatrix4fv(this.loc('u_worldInverseTransposeMatrix'), false, IDENTITY);
    gl.uniformMatrix4fv(this.loc('u_viewProjectionMatrix'), false, viewProjection);
    gl.uniform3fv(this.loc('u_viewPosition'), viewPosition);
    gl.uniform1i(this.loc('u_numActiveLightSources'), 1);
    const set = (member, f, v) => {
      const l = this.loc(`u_lightData[0].${member}`);
      if (l !== null) f.call(gl, l, v);
    };
    set('type', gl.uniform1i, light.type);
    set('position', gl.uniform3fv, light.position || [0, 0, 0]);
    set('direction', gl.uniform3fv, light.direction || [0, 0, -1]);
    set('color', gl.uniform3fv, [1, 1, 1]);
    set('intensity', gl.uniform1f, light.intensity);
    set('decay_rate', gl.uniform1f, 2);
  }

  // Renders the night scene into the float target and shows it; the scene's angles.
  renderFrame(observationDeg, entranceDeg, exposureEv) {
    const gl = this.gl;
    const scene = buildScene(this.width, this.height, observationDeg, entranceDeg);
    const key = `${observationDeg},${entranceDeg}`;
    if (key !== this.sceneKey) {
      if (this.meshes) for (const m of this.meshes) gl.deleteBuffer(m.vb);
      this.meshes = [upload(gl, signMesh(scene.sign)), upload(gl, sphereMesh(scene.sphere))];
      this.sceneKey = key;
    }
    this.setCommon(projection(scene), scene.eye, {
      type: LIGHT_POINT,
      position: scene.light.position,
      intensity: scene.light.intensity,
    });
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameTarget.fbo);
    gl.viewport(0, 0, this.width, this.height);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    for (const m of this.meshes) {
      gl.bindVertexArray(m.vao);
      gl.drawElements(gl.TRIANGLES, m.count, gl.UNSIGNED_INT, 0);
    }
    gl.bindVertexArray(null);
    this.show(exposureEv);
    return scene;
  }

  show(exposureEv) {
    const gl = this.gl;
    gl.disable(gl.DEPTH_TEST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, this.width, this.height);
    gl.useProgram(this.display);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.frameTarget.tex);
    gl.uniform1i(gl.getUniformLocation(this.display, 'u_frame'), 0);
    gl.uniform1f(gl.getUniformLocation(this.display, 'u_gain'), Math.pow(2, exposureEv));
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindTexture(gl.TEXTURE_2D, null);
  }

  // The linear frame, RGBA float, row 0 at the top (as the C++ render's).
  readFrame() {
    const gl = this.gl;
    const { width: w, height: h } = this;
    const px = new Float32Array(w * h * 4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameTarget.fbo);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    const out = new Float32Array(w * h * 4);
    for (let y = 0; y < h; ++y) out.set(px.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
    return out;
  }

  // Waits for the GPU: the time of a frame is measured up to here.
  finish() {
    const gl = this.gl;
    const p = new Float32Array(4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameTarget.fbo);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.FLOAT, p);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  // R_A (RGB, cd lx^-1 m^-2) at every (observation, entrance) pair, rotation 0: by the shader on
  // a flat patch (normal +z, tangent +x) with wi = (sin b, 0, cos b) and
  // wo = (sin(b - a), 0, cos(b - a)) (analysis/photometry.h, coplanar geometry).
  raTable(observation, entrance) {
    const gl = this.gl;
    const w = entrance.length;
    const h = observation.length;
    if (!this.raTarget || this.raTarget.width !== w || this.raTarget.height !== h) this.raTarget = target(gl, w, h);
    if (!this.patch) {
      const r = 1e-3;
      const v = [];
      for (const [x, y] of [[-r, -r], [r, -r], [r, r], [-r, r]]) v.push(x, y, 0, 0, 0, 1, 1, 0, 0);
      this.patch = upload(gl, { vertices: new Float32Array(v), indices: new Uint32Array([0, 1, 2, 0, 2, 3]) });
    }
    // The patch fills whichever one-pixel viewport it is drawn into.
    const ortho = new Float32Array([1e3, 0, 0, 0, 0, 1e3, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.raTarget.fbo);
    // The frame's pipeline state (depth test on): a software driver (Mesa's llvmpipe) compiles
    // a shader variant per state, and the node's shader takes seconds to compile.
    gl.enable(gl.DEPTH_TEST);
    gl.viewport(0, 0, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.bindVertexArray(this.patch.vao);
    const cosO = [];
    for (let row = 0; row < h; ++row) {
      cosO.push([]);
      for (let col = 0; col < w; ++col) {
        const b = entrance[col] * DEG;
        const bo = (entrance[col] - observation[row]) * DEG;
        const wi = [Math.sin(b), 0, Math.cos(b)];
        const wo = [Math.sin(bo), 0, Math.cos(bo)];
        cosO[row].push(wo[2]);
        // The viewer far along wo (V = normalize(eye - P), P within 1e-3 of the origin);
        // a directional light's direction is its travel direction, -wi.
        this.setCommon(ortho, wo.map((c) => c * 1e6), {
          type: LIGHT_DIRECTIONAL,
          direction: wi.map((c) => -c),
          intensity: 1,
        });
        gl.viewport(col, row, 1, 1);
        gl.drawElements(gl.TRIANGLES, this.patch.count, gl.UNSIGNED_INT, 0);
      }
    }
    gl.bindVertexArray(null);
    const px = new Float32Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    const rgb = [];
    for (let row = 0; row < h; ++row) {
      rgb.push([]);
      for (let col = 0; col < w; ++col) {
        const i = 4 * (row * w + col);
        const c = cosO[row][col];
        rgb[row].push([px[i] * c, px[i + 1] * c, px[i + 2] * c]);
      }
    }
    return rgb;
  }
}
