'use strict';
// kezuri view: the page's viewer (WebGL2, no library). The data format is described in the
// Rust module that writes the page (crates/picture/src/view.rs). Sections:
//   1 page helpers and formatting   2 unpacking   3 geometry   4 WebGL
//   5 camera   6 drawing   7 panels (readout, legend, text, marks)   8 input   9 start
(async () => {
  // ---------------------------------------------------------------- 1 page helpers
  const $ = (id) => document.getElementById(id);
  const root = document.documentElement;
  const canvas = $('kz-canvas');
  const view = $('kz-view');
  let resolveReady, rejectReady;
  const ready = new Promise((res, rej) => { resolveReady = res; rejectReady = rej; });
  ready.catch(() => {});
  const api = { ready, moves: 0, canvas, setMove: () => NaN, redraw: () => NaN, project: () => [NaN, NaN], state: () => null };
  window.kezuriView = api;

  function message(text, isError) {
    const el = $('kz-message');
    el.textContent = text || '';
    el.hidden = !text;
    el.classList.toggle('error', !!isError);
  }
  function fail(err) {
    const text = typeof err === 'string' ? err : 'The view could not be shown: ' + ((err && err.message) || err);
    root.dataset.error = text;
    message(text, true);
    rejectReady(new Error(text));
  }

  const INT = new Intl.NumberFormat('en-US');
  const fmtInt = (n) => (Number.isFinite(n) ? INT.format(n) : '—');
  function fmtNum(v, digits) {
    if (!Number.isFinite(v)) return '—';
    const s = v.toFixed(digits);
    return /^-0\.?0*$/.test(s) ? s.slice(1) : s;
  }
  function fmtTime(s) {
    if (!Number.isFinite(s) || s < 0) return '—';
    const t = Math.round(s * 10);
    const h = Math.floor(t / 36000), m = Math.floor(t / 600) % 60, ds = t % 600;
    return h + ':' + String(m).padStart(2, '0') + ':' + (ds / 10).toFixed(1).padStart(4, '0');
  }
  const hex = (c) => [1, 3, 5].map((i) => parseInt(c.slice(i, i + 2), 16) / 255);
  const css = (rgb) => 'rgb(' + rgb.map((v) => Math.round(v * 255)).join(',') + ')';

  const KINDS = ['rapid', 'feed', 'arc', 'plunge', 'probe', 'dwell', 'position not known'];
  const UNPLACED = 6;                // to a place the program does not give: not drawn, nor the tool
  const KIND_COLOURS = ['#ff5b4f', '#4ea6ff', '#3fd07f', '#ffc53d', '#c77dff', '#ffffff'].map(hex);
  const TOOL_COLOURS = ['#4ea6ff', '#ffa23d', '#45d483', '#ff5f8f', '#b38cff', '#3fd6d0',
    '#e8dc55', '#ff7d4f', '#8fb0ff', '#b9e36a', '#f38fdc', '#c8c8c8'].map(hex);
  const NO_TOOL = [0.55, 0.55, 0.55];
  const BG = hex('#1f2226');
  const toolColour = (t) => (t === 0xffff ? NO_TOOL : TOOL_COLOURS[t % TOOL_COLOURS.length]);
  // diverging map for the deviation, −1 … +1: below the target red (as sim's picture), above blue
  const CMAP = ['#b2182b', '#ef8a62', '#ececec', '#67a9cf', '#2166ac'].map(hex);
  const GOUGE = hex('#ff3fd8');
  // beyond the full-colour scale, as the deviation PNG: more left amber, a deeper gouge dark purple
  const OVER_LEFT = hex('#f5a000');
  const OVER_GOUGE = hex('#5a0032');
  const NOT_COMPARED = [0.45, 0.45, 0.47];

  // ---------------------------------------------------------------- 2 unpacking
  function base64Bytes(el) {
    const s = el.textContent.trim();
    if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(s);
    const bin = atob(s);
    const n = bin.length, out = new Uint8Array(n);
    for (let i = 0; i < n; i++) out[i] = bin.charCodeAt(i);
    return out;
  }
  async function gunzip(bytes) {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('gzip'));
    try {
      return await new Response(stream).arrayBuffer();
    } catch (e) {
      throw new Error('the packed data could not be unpacked (a damaged or cut-off file?)');
    }
  }
  function parseBlob(buf, meta) {
    const N = meta.moves, V = meta.vertices;
    let off = 0;
    const take = (C, n) => {
      const bytes = n * C.BYTES_PER_ELEMENT;
      if (off + bytes > buf.byteLength) throw new Error('the packed data is shorter than the page says (a cut-off file?)');
      const a = new C(buf, off, n);
      off += (bytes + 3) & ~3;
      return a;
    };
    const d = {
      kind: take(Uint8Array, N), tool: take(Uint16Array, N), frame: take(Uint16Array, N),
      line: take(Int32Array, N), feed: take(Float32Array, N), secs: take(Float32Array, N),
      vcount: take(Uint32Array, N), dx: take(Int32Array, V), dy: take(Int32Array, V), dz: take(Int32Array, V),
      brk: take(Uint8Array, V),
    };
    const s = meta.sim;
    if (s) {
      d.height = take(Int32Array, s.nx * s.ny);
      d.blocks = take(Uint32Array, 3 * s.blocks);
      if (s.deviation) d.dev = take(Int32Array, s.nx * s.ny);
    }
    return d;
  }

  // ---------------------------------------------------------------- 3 geometry
  let meta, D, N = 0, V = 0;
  let C = [0, 0, 0];                 // the centre: GPU positions are mm relative to it
  let vstart, elapsed, lineOf, pos, attr;
  let box = null;                    // [[min],[max]] in mm relative to C, of path and part
  let part = null;                   // {pos, dev, index, count}
  let unitMm = 1, unitName = 'mm', digits = 3;

  const grow = (b, x, y, z) => {
    if (x < b[0][0]) b[0][0] = x; if (y < b[0][1]) b[0][1] = y; if (z < b[0][2]) b[0][2] = z;
    if (x > b[1][0]) b[1][0] = x; if (y > b[1][1]) b[1][1] = y; if (z > b[1][2]) b[1][2] = z;
  };
  function buildPath() {
    const { vcount, kind, tool, brk, dx, dy, dz, secs } = D;
    vstart = new Uint32Array(N + 1);
    for (let i = 0; i < N; i++) vstart[i + 1] = vstart[i] + vcount[i];
    if (vstart[N] !== V) throw new Error('the moves add up to ' + vstart[N] + ' vertices, the page has ' + V);
    lineOf = D.line;                 // line deltas → line numbers, in place
    for (let i = 0, l = 0; i < N; i++) { l += lineOf[i]; lineOf[i] = l; }
    elapsed = new Float64Array(N + 1);
    for (let i = 0; i < N; i++) { const s = secs[i]; elapsed[i + 1] = elapsed[i] + (s > 0 && s < Infinity ? s : 0); }
    // positions: deltas → running sums in quanta (in place, kept for exact readouts) → f32 mm about C
    const q = meta.quantum_mm, o = meta.origin_mm;
    const ox = o[0] - C[0], oy = o[1] - C[1], oz = o[2] - C[2];
    pos = new Float32Array(3 * V);
    let x = 0, y = 0, z = 0, x0 = Infinity, y0 = Infinity, z0 = Infinity, x1 = -Infinity, y1 = -Infinity, z1 = -Infinity;
    for (let k = 0, j = 0; k < V; k++, j += 3) {
      x += dx[k]; y += dy[k]; z += dz[k];
      dx[k] = x; dy[k] = y; dz[k] = z;
      if (x < x0) x0 = x; if (x > x1) x1 = x; if (y < y0) y0 = y; if (y > y1) y1 = y; if (z < z0) z0 = z; if (z > z1) z1 = z;
      pos[j] = ox + q * x; pos[j + 1] = oy + q * y; pos[j + 2] = oz + q * z;
    }
    if (V) box = [[ox + q * x0, oy + q * y0, oz + q * z0], [ox + q * x1, oy + q * y1, oz + q * z1]];
    // per-vertex kind, tool, break: the segment ending at vertex k is drawn in the colour of k's move
    attr = new Uint8Array(4 * V);
    for (let i = 0; i < N; i++) {
      const k0 = vstart[i], k1 = vstart[i + 1];
      const kd = kind[i], t = tool[i], lo = t & 255, hi = t >> 8;
      for (let k = k0, j = 4 * k0; k < k1; k++, j += 4) { attr[j] = kd; attr[j + 1] = lo; attr[j + 2] = hi; attr[j + 3] = brk[k]; }
    }
  }
  // vertex k in machine mm (exact, from the running sums)
  function vertexMm(k) {
    const q = meta.quantum_mm, o = meta.origin_mm;
    return [o[0] + q * D.dx[k], o[1] + q * D.dy[k], o[2] + q * D.dz[k]];
  }
  function buildPart() {
    const s = meta.sim, nx = s.nx | 0, ny = s.ny | 0;
    if (nx < 2 || ny < 2) return;
    const n = nx * ny, h = D.height, q = meta.quantum_mm;
    const p = new Float32Array(3 * n), dev = new Float32Array(2 * n);
    const bx = s.x0_mm - C[0], by = s.y0_mm - C[1], bz = s.z0_mm - C[2], cell = s.cell_mm;
    let acc = 0, zmin = Infinity, zmax = -Infinity;
    for (let j = 0, k = 0; j < ny; j++) {
      for (let i = 0; i < nx; i++, k++) {
        acc += h[k];
        const z = bz + q * acc;
        if (z < zmin) zmin = z; if (z > zmax) zmax = z;
        p[3 * k] = bx + i * cell; p[3 * k + 1] = by + j * cell; p[3 * k + 2] = z;
      }
    }
    if (D.dev) {
      const qu = s.deviation.quantum_um;
      for (let k = 0; k < n; k++) { const v = D.dev[k]; if (v !== -2147483648) { dev[2 * k] = v * qu; dev[2 * k + 1] = 1; } }
    }
    // flat blocks: one quad each; every other grid quad: two triangles
    const qx = nx - 1, qy = ny - 1, covered = new Uint8Array(qx * qy), B = D.blocks, blocks = [];
    for (let b = 0; b + 2 < B.length; b += 3) {
      const i = B[b], j = B[b + 1], sz = B[b + 2];
      if (sz < 1 || i + sz > qx || j + sz > qy) continue;
      blocks.push(i, j, sz);
      for (let jj = j; jj < j + sz; jj++) covered.fill(1, jj * qx + i, jj * qx + i + sz);
    }
    let free = 0;
    for (let k = 0; k < covered.length; k++) free += 1 - covered[k];
    const index = new Uint32Array(6 * (free + blocks.length / 3));
    let w = 0;
    const quad = (a, b, c, d) => { index[w++] = a; index[w++] = b; index[w++] = c; index[w++] = a; index[w++] = c; index[w++] = d; };
    for (let j = 0; j < qy; j++) {
      for (let i = 0; i < qx; i++) {
        if (covered[j * qx + i]) continue;
        const a = j * nx + i;
        quad(a, a + 1, a + nx + 1, a + nx);
      }
    }
    for (let b = 0; b < blocks.length; b += 3) {
      const i = blocks[b], j = blocks[b + 1], sz = blocks[b + 2], a = j * nx + i;
      quad(a, a + sz, a + sz * nx + sz, a + sz * nx);
    }
    part = { pos: p, dev, index, count: w };
    const pb = [[bx, by, zmin], [bx + qx * cell, by + qy * cell, zmax]];
    if (!box) box = pb; else { grow(box, ...pb[0]); grow(box, ...pb[1]); }
  }
  // a tool's outline turned about its axis (z up from the tip); triangles, no normals (flat shading)
  function revolve(profile) {
    const pts = profile.filter((p) => Array.isArray(p) && Number.isFinite(p[0]) && Number.isFinite(p[1])).map((p) => [p[0], Math.max(0, p[1])]);
    if (pts.length < 2) return null;
    const SEG = 40, out = [];
    const ring = (r, z, a) => [r * Math.cos(a), r * Math.sin(a), z];
    for (let s = 0; s < SEG; s++) {
      const a0 = (s / SEG) * 2 * Math.PI, a1 = ((s + 1) / SEG) * 2 * Math.PI;
      const first = pts[0], last = pts[pts.length - 1];
      if (first[1] > 0) out.push(0, 0, first[0], ...ring(first[1], first[0], a1), ...ring(first[1], first[0], a0));
      for (let m = 0; m + 1 < pts.length; m++) {
        const [z0, r0] = pts[m], [z1, r1] = pts[m + 1];
        const p00 = ring(r0, z0, a0), p01 = ring(r0, z0, a1), p10 = ring(r1, z1, a0), p11 = ring(r1, z1, a1);
        if (r0 > 0) out.push(...p00, ...p01, ...p11);
        if (r1 > 0) out.push(...p00, ...p11, ...p10);
      }
      if (last[1] > 0) out.push(0, 0, last[0], ...ring(last[1], last[0], a0), ...ring(last[1], last[0], a1));
    }
    return new Float32Array(out);
  }
  const MARKER = new Float32Array([[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]].flatMap((a, i, all) => {
    const b = all[(i + 1) % 4];
    return [0, 0, 0, ...a, ...b, 0, 0, 2, ...b, ...a].map((v, j) => (j % 3 === 2 ? v : v * 0.8));
  }));

  // ---------------------------------------------------------------- 4 WebGL
  let gl, progPath, progMesh, progLine, vaoPath, vaoPart, vaoLine, lineBuf;
  const toolMeshes = new Map();      // tool index → {vao, count} (null: marker)
  let W = 0, H = 0, cssW = 1, cssH = 1, dpr = 1;
  let fbStatic = null, fbResolve = null, samples = 0;

  const PATH_VS = `#version 300 es
layout(location=0) in vec3 aPos;
layout(location=1) in uvec4 aAttr;
uniform mat4 uMvp;
uniform int uColourBy;
uniform bool uHideRapids;
uniform vec3 uKind[6];
uniform vec3 uTool[12];
flat out vec4 vCol;
void main() {
  gl_Position = uMvp * vec4(aPos, 1.0);
  gl_Position.z -= 0.0004;
  uint k = aAttr.x, t = aAttr.y | (aAttr.z << 8u);
  vec3 c = uColourBy == 0 ? uKind[min(k, 5u)] : (t == 65535u ? vec3(0.55) : uTool[t % 12u]);
  vCol = vec4(c, (aAttr.w != 0u || (uHideRapids && k == 0u)) ? 0.0 : 1.0);
}`;
  const PATH_FS = `#version 300 es
precision mediump float;
flat in vec4 vCol;
out vec4 o;
void main() { if (vCol.a < 0.5) discard; o = vec4(vCol.rgb, 1.0); }`;
  const MESH_VS = `#version 300 es
layout(location=0) in vec3 aPos;
layout(location=1) in vec2 aDev;
uniform mat4 uMvp;
uniform mat4 uRot;
uniform vec3 uOffset;
uniform float uScale;
out vec3 vView;
out vec2 vDev;
void main() {
  vec3 p = aPos * uScale + uOffset;
  gl_Position = uMvp * vec4(p, 1.0);
  vView = (uRot * vec4(p, 1.0)).xyz;
  vDev = aDev;
}`;
  const MESH_FS = `#version 300 es
precision highp float;
in vec3 vView;
in vec2 vDev;
uniform int uMode;
uniform vec3 uColour;
uniform float uScaleUm, uGougeUm;
uniform vec3 uMap[5];
uniform vec3 uGouge, uNone, uOverLeft, uOverGouge;
out vec4 o;
vec3 cmap(float t) {
  float u = (clamp(t, -1.0, 1.0) + 1.0) * 2.0;
  if (u < 1.0) return mix(uMap[0], uMap[1], u);
  if (u < 2.0) return mix(uMap[1], uMap[2], u - 1.0);
  if (u < 3.0) return mix(uMap[2], uMap[3], u - 2.0);
  return mix(uMap[3], uMap[4], u - 3.0);
}
void main() {
  vec3 n = normalize(cross(dFdx(vView), dFdy(vView)));
  if (n.z < 0.0) n = -n;
  vec3 l = normalize(vec3(-0.35, 0.5, 0.8));
  float d = max(dot(n, l), 0.0);
  float s = pow(max(dot(n, normalize(l + vec3(0.0, 0.0, 1.0))), 0.0), 40.0);
  vec3 base = uColour;
  if (uMode == 1) {
    if (vDev.y < 0.5) base = uNone;
    else if (vDev.x > uScaleUm) base = uOverLeft;
    else if (vDev.x < -uScaleUm && uScaleUm > uGougeUm) base = uOverGouge;
    else if (vDev.x < -uGougeUm) base = uGouge;
    else base = cmap(vDev.x / uScaleUm);
  }
  o = vec4(base * (0.32 + 0.68 * d) + 0.18 * s, 1.0);
}`;
  const LINE_VS = `#version 300 es
layout(location=0) in vec3 aPos;
layout(location=2) in vec3 aCol;
uniform mat4 uMvp;
out vec3 vCol;
void main() { gl_Position = uMvp * vec4(aPos, 1.0); vCol = aCol; }`;
  const LINE_FS = `#version 300 es
precision mediump float;
in vec3 vCol;
out vec4 o;
void main() { o = vec4(vCol, 1.0); }`;

  // compile and link without waiting: the checks come after the data is unpacked (see finishGl)
  function program(vs, fs) {
    const p = gl.createProgram();
    p.shaders = [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]].map(([type, src]) => {
      const sh = gl.createShader(type);
      gl.shaderSource(sh, src);
      gl.compileShader(sh);
      gl.attachShader(p, sh);
      return sh;
    });
    gl.linkProgram(p);
    return p;
  }
  function checkProgram(p) {
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) {
      const log = p.shaders.map((sh) => gl.getShaderInfoLog(sh)).join(' ') + ' ' + gl.getProgramInfoLog(p);
      throw new Error('WebGL shader: ' + log.trim());
    }
    p.u = {};
    const n = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
    for (let i = 0; i < n; i++) {
      const name = gl.getActiveUniform(p, i).name.replace(/\[0\]$/, '');
      p.u[name] = gl.getUniformLocation(p, name);
    }
  }
  function buffer(target, data) {
    const b = gl.createBuffer();
    gl.bindBuffer(target, b);
    gl.bufferData(target, data, gl.STATIC_DRAW);
    return b;
  }
  function vao(attribs, index) {
    const v = gl.createVertexArray();
    gl.bindVertexArray(v);
    v.bufs = attribs.map(([loc, size, type, data, integer]) => {
      const b = buffer(gl.ARRAY_BUFFER, data);
      gl.enableVertexAttribArray(loc);
      if (integer) gl.vertexAttribIPointer(loc, size, type, 0, 0);
      else gl.vertexAttribPointer(loc, size, type, false, 0, 0);
      return b;
    });
    if (index) v.index = buffer(gl.ELEMENT_ARRAY_BUFFER, index);
    gl.bindVertexArray(null);
    return v;
  }
  // before the data arrives: the context, the shaders, and one small draw of each kind, so that the
  // driver compiles its pipelines while the page unpacks (software GL takes long over that)
  function startGl() {
    resize();                        // a canvas resized after getContext costs a slow reallocation
    gl = canvas.getContext('webgl2', { antialias: false, alpha: false, depth: true, stencil: false, preserveDrawingBuffer: false, powerPreference: 'high-performance' });
    if (!gl) throw new Error('WebGL2 is not available in this browser: the 3D view needs it.');
    canvas.addEventListener('webglcontextlost', (e) => { e.preventDefault(); fail('The graphics context was lost (WebGL): reload the page.'); });
    // multisampling where the GL is a GPU; software GL (SwiftShader, llvmpipe) pays for it in full
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    const renderer = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
    samples = /swiftshader|llvmpipe|softpipe|software|basic render/i.test(renderer) ? 0 : Math.min(4, gl.getParameter(gl.MAX_SAMPLES) | 0);
    api.renderer = renderer;
    progPath = program(PATH_VS, PATH_FS);
    progMesh = program(MESH_VS, MESH_FS);
    progLine = program(LINE_VS, LINE_FS);
    const tri = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]);
    vaoPath = vao([[0, 3, gl.FLOAT, tri], [1, 4, gl.UNSIGNED_BYTE, new Uint8Array(12), true]]);
    vaoPart = vao([[0, 3, gl.FLOAT, tri], [1, 2, gl.FLOAT, new Float32Array(6)]], new Uint32Array([0, 1, 2]));
    vaoLine = gl.createVertexArray();
    gl.bindVertexArray(vaoLine);
    lineBuf = buffer(gl.ARRAY_BUFFER, new Float32Array(36));
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 24, 0);
    gl.enableVertexAttribArray(2);
    gl.vertexAttribPointer(2, 3, gl.FLOAT, false, 24, 12);
    gl.bindVertexArray(null);
    const t = target(4, 4, 0, true);
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.fb);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) throw new Error('WebGL: an offscreen target is incomplete');
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.fb);
    gl.viewport(0, 0, 4, 4);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LEQUAL);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.useProgram(progPath);
    gl.bindVertexArray(vaoPath);
    gl.drawArrays(gl.LINE_STRIP, 0, 3);
    gl.useProgram(progMesh);
    gl.bindVertexArray(vaoPart);
    gl.drawElements(gl.TRIANGLES, 3, gl.UNSIGNED_INT, 0);
    markerMesh = meshVao(MARKER);
    gl.bindVertexArray(markerMesh.vao);
    gl.vertexAttrib2f(1, 0, 0);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindVertexArray(vaoLine);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindFramebuffer(gl.READ_FRAMEBUFFER, t.fb);
    gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, null);
    gl.blitFramebuffer(0, 0, 4, 4, 0, 0, 4, 4, gl.COLOR_BUFFER_BIT, gl.NEAREST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.clear(gl.DEPTH_BUFFER_BIT);
    gl.bindVertexArray(markerMesh.vao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.disable(gl.DEPTH_TEST);
    gl.useProgram(progLine);
    gl.drawArrays(gl.LINES, 0, 2);
    gl.bindVertexArray(null);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.flush();
    dropTarget(t);
  }
  // after: check the shaders, set the constant uniforms, upload the geometry (once)
  function finishGl() {
    for (const p of [progPath, progMesh, progLine]) checkProgram(p);
    gl.useProgram(progPath);
    gl.uniform3fv(progPath.u.uKind, KIND_COLOURS.flat());
    gl.uniform3fv(progPath.u.uTool, TOOL_COLOURS.flat());
    gl.useProgram(progMesh);
    gl.uniform3fv(progMesh.u.uMap, CMAP.flat());
    gl.uniform3fv(progMesh.u.uGouge, GOUGE);
    gl.uniform3fv(progMesh.u.uNone, NOT_COMPARED);
    gl.uniform3fv(progMesh.u.uOverLeft, OVER_LEFT);
    gl.uniform3fv(progMesh.u.uOverGouge, OVER_GOUGE);
    const upload = (target, b, data) => { gl.bindBuffer(target, b); gl.bufferData(target, data, gl.STATIC_DRAW); };
    upload(gl.ARRAY_BUFFER, vaoPath.bufs[0], pos);
    upload(gl.ARRAY_BUFFER, vaoPath.bufs[1], attr);
    if (part) {
      upload(gl.ARRAY_BUFFER, vaoPart.bufs[0], part.pos);
      upload(gl.ARRAY_BUFFER, vaoPart.bufs[1], part.dev);
      gl.bindVertexArray(vaoPart);
      upload(gl.ELEMENT_ARRAY_BUFFER, vaoPart.index, part.index);
      gl.bindVertexArray(null);
      part.pos = part.dev = part.index = null;
    }
  }
  const meshVao = (tri) => ({ vao: vao([[0, 3, gl.FLOAT, tri]]), count: tri.length / 3 });
  function toolMesh(t) {
    if (!toolMeshes.has(t)) {
      const tl = meta.tools[t];
      const tri = tl && Array.isArray(tl.profile) ? revolve(tl.profile) : null;
      toolMeshes.set(t, tri && tri.length ? meshVao(tri) : null);
    }
    return toolMeshes.get(t);
  }
  let markerMesh = null;
  // colour and depth targets, one for the static layer (part + path so far), one for the frame
  // samples > 0: multisampled (smooth lines), resolved through a plain colour target
  function target(w, h, samples, depth) {
    const fb = gl.createFramebuffer(), c = gl.createRenderbuffer(), d = depth ? gl.createRenderbuffer() : null;
    const store = (fmt) => (samples ? gl.renderbufferStorageMultisample(gl.RENDERBUFFER, samples, fmt, w, h) : gl.renderbufferStorage(gl.RENDERBUFFER, fmt, w, h));
    gl.bindRenderbuffer(gl.RENDERBUFFER, c);
    store(gl.RGBA8);
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.RENDERBUFFER, c);
    if (d) {
      gl.bindRenderbuffer(gl.RENDERBUFFER, d);
      store(gl.DEPTH_COMPONENT24);
      gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, d);
    }
    return { fb, c, d };
  }
  function dropTarget(t) {
    if (!t) return;
    gl.deleteFramebuffer(t.fb); gl.deleteRenderbuffer(t.c);
    if (t.d) gl.deleteRenderbuffer(t.d);
  }
  function resize() {
    const r = view.getBoundingClientRect();
    const w = Math.max(1, Math.round(r.width)), h = Math.max(1, Math.round(r.height));
    const ratio = Math.min(window.devicePixelRatio || 1, 2);
    const pw = Math.max(1, Math.round(w * ratio)), ph = Math.max(1, Math.round(h * ratio));
    if (pw === W && ph === H && w === cssW && h === cssH) return false;
    cssW = w; cssH = h; dpr = ratio; W = pw; H = ph;
    if (canvas.width !== W) canvas.width = W;
    if (canvas.height !== H) canvas.height = H;
    if (!gl) return true;
    dropTarget(fbStatic);
    dropTarget(fbResolve);
    fbStatic = target(W, H, samples, true);
    fbResolve = samples ? target(W, H, 0, false) : null;
    cameraChanged();
    return true;
  }

  // ---------------------------------------------------------------- 5 camera (orthographic, Z up)
  const cam = { yaw: Math.PI / 4, pitch: Math.atan(Math.SQRT1_2), tgt: [0, 0, 0], scale: 1 };  // scale: mm per CSS pixel
  const VIEWS = { top: [0, Math.PI / 2], front: [0, 0], side: [Math.PI / 2, 0], iso: [Math.PI / 4, Math.atan(Math.SQRT1_2)] };
  let mvp = new Float32Array(16), rot = new Float32Array(16), rows = null, toolLen = 0;
  function basis() {
    const cy = Math.cos(cam.yaw), sy = Math.sin(cam.yaw), cp = Math.cos(cam.pitch), sp = Math.sin(cam.pitch);
    const e = [sy * cp, -cy * cp, sp], r = [cy, sy, 0];
    const u = [e[1] * r[2] - e[2] * r[1], e[2] * r[0] - e[0] * r[2], e[0] * r[1] - e[1] * r[0]];
    return [r, u, e];
  }
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  function updateMatrix() {
    const [r, u, e] = basis();
    const hw = (cam.scale * cssW) / 2, hh = (cam.scale * cssH) / 2;
    const t = cam.tgt;
    const b = box || [[0, 0, 0], [0, 0, 0]];
    const c = [(b[0][0] + b[1][0]) / 2, (b[0][1] + b[1][1]) / 2, (b[0][2] + b[1][2]) / 2];
    const rad = Math.hypot(b[1][0] - b[0][0], b[1][1] - b[0][1], b[1][2] - b[0][2]) / 2;
    const R = Math.hypot(t[0] - c[0], t[1] - c[1], t[2] - c[2]) + rad * 1.05 + toolLen + 1;
    const a = r.map((v) => v / hw), bb = u.map((v) => v / hh), cc = e.map((v) => -v / R);
    rows = [a, bb, cc];
    mvp = new Float32Array([a[0], bb[0], cc[0], 0, a[1], bb[1], cc[1], 0, a[2], bb[2], cc[2], 0, -dot(a, t), -dot(bb, t), -dot(cc, t), 1]);
    rot = new Float32Array([r[0], u[0], e[0], 0, r[1], u[1], e[1], 0, r[2], u[2], e[2], 0, 0, 0, 0, 1]);
  }
  // relative-to-C mm → CSS pixels of the canvas
  function toScreen(x, y, z) {
    const [a, b] = rows, t = cam.tgt;
    const px = a[0] * (x - t[0]) + a[1] * (y - t[1]) + a[2] * (z - t[2]);
    const py = b[0] * (x - t[0]) + b[1] * (y - t[1]) + b[2] * (z - t[2]);
    return [((px + 1) / 2) * cssW, ((1 - py) / 2) * cssH];
  }
  function fit() {
    if (!box) { cam.tgt = [0, 0, 0]; cam.scale = 1; return; }
    const [r, u] = basis();
    let r0 = Infinity, r1 = -Infinity, u0 = Infinity, u1 = -Infinity;
    for (let m = 0; m < 8; m++) {
      const p = [box[m & 1][0], box[(m >> 1) & 1][1], box[(m >> 2) & 1][2]];
      const pr = dot(p, r), pu = dot(p, u);
      r0 = Math.min(r0, pr); r1 = Math.max(r1, pr); u0 = Math.min(u0, pu); u1 = Math.max(u1, pu);
    }
    const c = [(box[0][0] + box[1][0]) / 2, (box[0][1] + box[1][1]) / 2, (box[0][2] + box[1][2]) / 2];
    const dr = (r0 + r1) / 2 - dot(c, r), du = (u0 + u1) / 2 - dot(c, u);
    cam.tgt = [c[0] + r[0] * dr + u[0] * du, c[1] + r[1] * dr + u[1] * du, c[2] + r[2] * dr + u[2] * du];
    // at least 1 mm across; a path that does not move: room for the tool
    const diag = Math.hypot(box[1][0] - box[0][0], box[1][1] - box[0][1], box[1][2] - box[0][2]);
    const least = diag > 1e-3 ? 1 : Math.max(20, 2.5 * toolLen);
    cam.scale = Math.max(Math.max(r1 - r0, least) / Math.max(cssW - 60, 40), Math.max(u1 - u0, least) / Math.max(cssH - 90, 40));
  }
  function setView(name) {
    if (VIEWS[name]) [cam.yaw, cam.pitch] = VIEWS[name];
    fit();
    cameraChanged();
  }

  // ---------------------------------------------------------------- 6 drawing
  let cur = 0;                       // moves shown: moves 0 … cur−1 are drawn, cur−1 is the current one
  let drawn = -1;                    // moves in the static layer; −1: to redraw
  let showPath = true, showRapids = true, showPart = true, colourBy = 0;
  let overlaysDirty = true, frameQueued = false;

  function cameraChanged() { updateMatrix(); drawn = -1; overlaysDirty = true; schedule(); }
  function invalidate() { drawn = -1; schedule(); }
  function schedule() {
    if (frameQueued || !gl) return;
    frameQueued = true;
    requestAnimationFrame(() => { frameQueued = false; render(); });
  }
  function drawPathRange(m0, m1) {
    const first = Math.max(0, vstart[m0] - 1), count = vstart[m1] - first;
    if (count < 2) return;
    gl.useProgram(progPath);
    gl.uniformMatrix4fv(progPath.u.uMvp, false, mvp);
    gl.uniform1i(progPath.u.uColourBy, colourBy);
    gl.uniform1i(progPath.u.uHideRapids, showRapids ? 0 : 1);
    if (m0 === 0 && count >= LOD_MIN) { drawPathLod(count); return; }
    gl.bindVertexArray(vaoPath);
    gl.drawArrays(gl.LINE_STRIP, first, count);
  }
  function drawMesh(vao, count, indexed, offset, scale, colour, mode) {
    gl.useProgram(progMesh);
    gl.uniformMatrix4fv(progMesh.u.uMvp, false, mvp);
    gl.uniformMatrix4fv(progMesh.u.uRot, false, rot);
    gl.uniform3fv(progMesh.u.uOffset, offset);
    gl.uniform1f(progMesh.u.uScale, scale);
    gl.uniform3fv(progMesh.u.uColour, colour);
    gl.uniform1i(progMesh.u.uMode, mode);
    const dv = meta.sim && meta.sim.deviation;
    gl.uniform1f(progMesh.u.uScaleUm, dv && dv.scale_um > 0 ? dv.scale_um : 1);
    gl.uniform1f(progMesh.u.uGougeUm, dv && dv.gouge_um > 0 ? dv.gouge_um : Infinity);
    gl.bindVertexArray(vao);
    if (!indexed) gl.vertexAttrib2f(1, 0, 0);
    if (indexed) gl.drawElements(gl.TRIANGLES, count, gl.UNSIGNED_INT, 0);
    else gl.drawArrays(gl.TRIANGLES, 0, count);
  }
  // A full redraw of a long path draws it at the screen's resolution: a vertex that stays within
  // LOD_PX pixels of the last one kept, in a move of the same kind and tool, is left out (an
  // indexed strip). Software GL pays per segment; a picture only needs the pixels.
  const LOD_MIN = 150000, LOD_PX = 0.7;
  let lodIndex = null, lodBuf = null;
  function drawPathLod(vEnd) {
    if (!lodIndex) { lodIndex = new Uint32Array(V); lodBuf = gl.createBuffer(); }
    const [a, b] = rows, t = cam.tgt;
    const ax = (a[0] * W) / 2, ay = (a[1] * W) / 2, az = (a[2] * W) / 2, a0 = W / 2 - (ax * t[0] + ay * t[1] + az * t[2]);
    const bx = (b[0] * H) / 2, by = (b[1] * H) / 2, bz = (b[2] * H) / 2, b0 = H / 2 - (bx * t[0] + by * t[1] + bz * t[2]);
    let n = 0, lx = 0, ly = 0, lkey = -1, skipped = -1;
    for (let k = 0, j = 0, q = 0; k < vEnd; k++, j += 3, q += 4) {
      const x = pos[j], y = pos[j + 1], z = pos[j + 2];
      const sx = ax * x + ay * y + az * z + a0, sy = bx * x + by * y + bz * z + b0;
      const key = attr[q] | (attr[q + 1] << 8) | (attr[q + 2] << 16);
      if (attr[q + 3] || key !== lkey || sx - lx > LOD_PX || lx - sx > LOD_PX || sy - ly > LOD_PX || ly - sy > LOD_PX) {
        lodIndex[n++] = k; lx = sx; ly = sy; lkey = key; skipped = -1;
      } else skipped = k;
    }
    if (skipped >= 0) lodIndex[n++] = skipped;    // the path ends where the tool is
    gl.bindVertexArray(vaoPath);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, lodBuf);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, lodIndex.subarray(0, n), gl.STREAM_DRAW);
    gl.drawElements(gl.LINE_STRIP, n, gl.UNSIGNED_INT, 0);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, null);
    api.lodVertices = n;
  }
  // the static layer: full redraw, or only the moves added since the last frame
  function drawStatic() {
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbStatic.fb);
    gl.viewport(0, 0, W, H);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LEQUAL);
    if (drawn < 0 || cur < drawn) {
      gl.clearColor(BG[0], BG[1], BG[2], 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      if (part && showPart) drawMesh(vaoPart, part.count, true, [0, 0, 0], 1, hex('#a3abb5'), meta.sim.deviation ? 1 : 0);
      drawn = 0;
    }
    // the path in time order (later moves over earlier ones), hidden only by the part
    if (showPath && cur > drawn) {
      if (!(part && showPart)) gl.disable(gl.DEPTH_TEST);
      gl.depthMask(false);
      drawPathRange(drawn, cur);
      gl.depthMask(true);
      gl.enable(gl.DEPTH_TEST);
    }
    drawn = cur;
  }
  function currentVertex() { return V === 0 ? -1 : Math.max(0, vstart[cur] - 1); }
  function currentMove() { return cur > 0 ? cur - 1 : (N > 0 ? 0 : -1); }
  // the tool is where the program put it, or nowhere: not at a reference point or G53 position
  // the page does not know, nor where the machine happened to start
  function toolPlaced() {
    const m = currentMove();
    return currentVertex() >= 0 && !(m >= 0 && D.kind[m] === UNPLACED);
  }
  function drawTool() {
    const k = currentVertex(), m = currentMove();
    if (!toolPlaced()) return;
    const p = [pos[3 * k], pos[3 * k + 1], pos[3 * k + 2]];
    const t = m >= 0 ? D.tool[m] : 0xffff;
    const mesh = t < meta.tools.length ? toolMesh(t) : null;
    const tint = toolColour(t).map((v) => 0.62 + 0.22 * v);
    if (mesh) drawMesh(mesh.vao, mesh.count, false, p, 1, tint, 0);
    else {
      if (!markerMesh) markerMesh = meshVao(MARKER);
      drawMesh(markerMesh.vao, markerMesh.count, false, p, 7 * cam.scale, tint, 0);
    }
  }
  // the axes (X red, Y green, Z blue) at each work zero, drawn over everything
  function drawTriads() {
    const frames = uniqueFrames();
    if (!frames.length) return;
    const L = 48 * cam.scale, data = [];
    const cols = [[1, 0.3, 0.3], [0.35, 0.9, 0.35], [0.35, 0.55, 1]];
    for (const f of frames) {
      for (let a = 0; a < 3; a++) {
        const e = [f[0], f[1], f[2]];
        e[a] += L;
        data.push(...f, ...cols[a], ...e, ...cols[a]);
      }
    }
    gl.disable(gl.DEPTH_TEST);
    gl.useProgram(progLine);
    gl.uniformMatrix4fv(progLine.u.uMvp, false, mvp);
    gl.bindVertexArray(vaoLine);
    gl.bindBuffer(gl.ARRAY_BUFFER, lineBuf);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(data), gl.DYNAMIC_DRAW);
    gl.drawArrays(gl.LINES, 0, data.length / 6);
    gl.enable(gl.DEPTH_TEST);
  }
  let framesRel = null;
  function uniqueFrames() {
    if (!framesRel) {
      const seen = new Set();
      framesRel = [];
      for (const f of meta.frames || []) {
        if (!Array.isArray(f) || !f.every(Number.isFinite)) continue;
        const key = f.join(',');
        if (seen.has(key) || framesRel.length >= 64) continue;
        seen.add(key);
        framesRel.push([f[0] - C[0], f[1] - C[1], f[2] - C[2]]);
      }
    }
    return framesRel;
  }
  function render() {
    if (!gl || gl.isContextLost()) return;
    drawStatic();
    // the frame: the static layer, then the tool (over it, with a depth buffer of its own) and the axes
    const blit = (from, to) => {
      gl.bindFramebuffer(gl.READ_FRAMEBUFFER, from);
      gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, to);
      gl.blitFramebuffer(0, 0, W, H, 0, 0, W, H, gl.COLOR_BUFFER_BIT, gl.NEAREST);
    };
    if (fbResolve) { blit(fbStatic.fb, fbResolve.fb); blit(fbResolve.fb, null); } else blit(fbStatic.fb, null);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.clear(gl.DEPTH_BUFFER_BIT);
    drawTool();
    drawTriads();
    if (overlaysDirty) { overlaysDirty = false; placePins(); scaleBar(); }
  }

  // ---------------------------------------------------------------- 7 panels
  const txt = (id, s) => { const el = $(id); if (el.textContent !== s) el.textContent = s; };
  function scaleBar() {
    const target = (120 * cam.scale) / unitMm;    // program units in ~120 px
    if (!(target > 0) || !Number.isFinite(target)) { $('kz-scale').hidden = true; return; }
    const k = Math.floor(Math.log10(target));
    let len = 10 ** k;
    for (const m of [1, 2, 5, 10]) if (m * 10 ** k <= target) len = m * 10 ** k;
    const px = (len * unitMm) / cam.scale;
    $('kz-scale').hidden = false;
    $('kz-scale-bar').style.width = px.toFixed(1) + 'px';
    const s = len >= 1 ? String(len) : len.toFixed(-k);
    txt('kz-scale-label', s + ' ' + unitName);
  }
  function readout() {
    const m = currentMove(), k = currentVertex();
    txt('kz-r-move', fmtInt(cur) + ' / ' + fmtInt(N));
    const line = m >= 0 ? lineOf[m] : NaN;
    txt('kz-r-line', line > 0 ? fmtInt(line) : line === 0 ? 'generated' : '—');
    let p = [NaN, NaN, NaN];
    if (toolPlaced()) {
      const mm = vertexMm(k), f = (meta.frames || [])[m >= 0 ? D.frame[m] : 0] || [0, 0, 0];
      p = mm.map((v, a) => (v - (Number.isFinite(f[a]) ? f[a] : 0)) / unitMm);
    }
    ['x', 'y', 'z'].forEach((a, i) => txt('kz-r-' + a, fmtNum(p[i], digits) + ' ' + unitName));
    const kind = m >= 0 ? D.kind[m] : -1;
    const feed = m >= 0 ? D.feed[m] / unitMm : NaN;
    txt('kz-r-feed', kind === 0 ? 'rapid' : kind === 5 ? 'dwell' : kind === UNPLACED ? '—' : Number.isFinite(feed) && m >= 0 ? fmtNum(feed, unitMm > 1 ? 2 : 0) + ' ' + unitName + '/min' : '—');
    txt('kz-r-kind', KINDS[kind] || '—');
    const t = m >= 0 ? D.tool[m] : 0xffff;
    txt('kz-r-tool', t === 0xffff ? (m >= 0 ? 'none' : '—') : (meta.tools[t] && meta.tools[t].label) || 'T?');
    const total = Number.isFinite(meta.cycle_time_s) ? meta.cycle_time_s : elapsed[N];
    txt('kz-r-time', fmtTime(elapsed[cur]) + ' / ' + fmtTime(total));
    const slider = $('kz-slider');
    if (+slider.value !== cur) slider.value = cur;
  }
  function legend() {
    const el = $('kz-legend');
    el.textContent = '';
    const add = (rgb, label) => {
      const row = document.createElement('div'), sw = document.createElement('span');
      sw.className = 'kz-sw';
      sw.style.background = css(rgb);
      row.append(sw, label);
      el.append(row);
    };
    if (colourBy === 0) {
      const seen = new Uint8Array(6);
      for (let i = 0; i < N; i++) seen[Math.min(D.kind[i], 5)] = 1;
      for (let k = 0; k < 5; k++) if (seen[k]) add(KIND_COLOURS[k], KINDS[k]);
    } else {
      for (const t of usedTools) add(toolColour(t), t === 0xffff ? 'no tool' : (meta.tools[t] && meta.tools[t].label) || 'tool ' + t);
    }
    let unplaced = 0;
    for (let i = 0; i < N; i++) if (D.kind[i] === UNPLACED) unplaced++;
    if (unplaced) {
      const row = document.createElement('div');
      row.id = 'kz-unplaced';
      row.textContent = 'not drawn: ' + fmtInt(unplaced) + (unplaced === 1 ? ' move' : ' moves') +
        ' to a place the program does not give (G28, G30, G53, or an axis not yet named), nor the tool there';
      el.append(row);
    }
    el.hidden = !el.childElementCount;
  }
  let usedTools = [];
  function findTools() {
    const seen = new Uint8Array(65536);
    for (let i = 0; i < N; i++) if (D.kind[i] !== UNPLACED) seen[D.tool[i]] = 1;   // the tools drawn
    usedTools = [];
    for (let t = 0; t < 65536; t++) if (seen[t]) usedTools.push(t);
  }
  function colourBar() {
    const dv = meta.sim && meta.sim.deviation;
    if (!dv) return;
    const el = $('kz-colorbar');
    const title = document.createElement('div');
    title.textContent = 'deviation (µm), scale ' + dv.scale_basis;
    const grad = document.createElement('div');
    grad.className = 'kz-cb-grad';
    grad.style.background = 'linear-gradient(to right,' + CMAP.map(css).join(',') + ')';
    const ticks = document.createElement('div');
    ticks.className = 'kz-cb-ticks';
    const s = dv.scale_um;
    const sd = Math.abs(s) < 10 ? 1 : 0;
    for (const v of [-s, -s / 2, 0, s / 2, s]) {
      const sp = document.createElement('span');
      sp.textContent = (v > 0 ? '+' : v < 0 ? '−' : '') + fmtNum(Math.abs(v), sd);
      ticks.append(sp);
    }
    const extra = document.createElement('div');
    extra.className = 'kz-cb-extra';
    const sw = (rgb, label) => {
      const wrap = document.createElement('span'), sq = document.createElement('span');
      sq.className = 'kz-sq';
      sq.style.background = css(rgb);
      wrap.append(sq, ' ' + label);
      extra.append(wrap);
    };
    sw(GOUGE, 'gouge < −' + fmtNum(dv.gouge_um, 1) + ' µm');
    const mm = (um) => fmtNum(um / 1000, 3) + ' mm';
    if (dv.left_max_um > s) sw(OVER_LEFT, 'left over +' + fmtNum(s, sd) + ' µm: up to ' + mm(dv.left_max_um));
    if (dv.gouge_max_um > s && s > dv.gouge_um) sw(OVER_GOUGE, 'gouge deeper than ' + fmtNum(s, sd) + ' µm: down to ' + mm(dv.gouge_max_um));
    sw(NOT_COMPARED, 'not compared');
    el.append(title, grad, ticks, extra);
    el.hidden = false;
  }
  // marks: a list in the side panel and pins over the view
  const pins = [];
  function marks() {
    const list = meta.marks || [];
    if (!list.length) return;
    $('kz-marks-box').hidden = false;
    const ul = $('kz-marks');
    list.slice(0, 2000).forEach((mk) => {
      const li = document.createElement('li'), b = document.createElement('button'), sq = document.createElement('span');
      b.type = 'button';
      li.className = mk.kind === 'rapid' ? 'rapid' : 'gouge';
      sq.className = 'kz-sq';
      b.append(sq, String(mk.label || mk.kind || 'mark'));
      b.addEventListener('click', () => goToMark(mk));
      li.append(b);
      ul.append(li);
      if (pins.length < 500 && Array.isArray(mk.at_mm) && mk.at_mm.every(Number.isFinite)) {
        const pin = document.createElement('div');
        pin.className = 'kz-pin ' + (mk.kind === 'rapid' ? 'rapid' : 'gouge');
        pin.title = String(mk.label || '');
        pin.addEventListener('click', () => goToMark(mk));
        $('kz-pins').append(pin);
        pins.push([pin, mk.at_mm.map((v, a) => v - C[a])]);
      }
    });
  }
  function goToMark(mk) {
    if (Array.isArray(mk.at_mm) && mk.at_mm.every(Number.isFinite)) {   // off the screen: centre it
      const p = mk.at_mm.map((v, a) => v - C[a]), [x, y] = toScreen(p[0], p[1], p[2]);
      if (!(x > 0 && y > 0 && x < cssW && y < cssH)) {
        const [r, u] = basis(), dx = x - cssW / 2, dy = y - cssH / 2;
        cam.tgt = cam.tgt.map((v, a) => v + (r[a] * dx - u[a] * dy) * cam.scale);
        cameraChanged();
      }
    }
    if (Number.isInteger(mk.move) && mk.move >= 0 && mk.move < N) setMove(mk.move + 1);
    else if (Number.isInteger(mk.line) && mk.line > 0) { curLine = mk.line; showLine(mk.line, true); }
  }
  function placePins() {
    for (const [pin, p] of pins) {
      const [x, y] = toScreen(p[0], p[1], p[2]);
      pin.hidden = !(x > -20 && y > -20 && x < cssW + 20 && y < cssH + 20);
      pin.style.translate = x.toFixed(1) + 'px ' + y.toFixed(1) + 'px';
    }
  }

  // program text: virtual scrolling, only the visible lines are in the DOM
  const LH = 18, MAXPX = 8e6;
  const tv = $('kz-program'), tvRows = $('kz-program-rows');
  let lines = null, curLine = 0, firstMoveOfLine = null;
  const rowPool = [];
  const scaled = () => lines.length * LH > MAXPX;
  function firstVisible() {
    if (!scaled()) return Math.floor(tv.scrollTop / LH);
    const maxSt = MAXPX - tv.clientHeight, vis = Math.floor(tv.clientHeight / LH);
    return maxSt > 0 ? Math.round((tv.scrollTop / maxSt) * Math.max(0, lines.length - vis)) : 0;
  }
  function renderText() {
    if (!lines) return;
    const n = Math.ceil(tv.clientHeight / LH) + 1, first = firstVisible();
    tvRows.style.transform = 'translateY(' + (scaled() ? tv.scrollTop : first * LH) + 'px)';
    while (rowPool.length < n) {
      const row = document.createElement('div'), ln = document.createElement('span'), src = document.createElement('span');
      row.className = 'kz-line'; ln.className = 'kz-ln'; src.className = 'kz-src';
      row.append(ln, src);
      tvRows.append(row);
      rowPool.push({ row, ln, src, idx: -1 });
    }
    rowPool.forEach((r, i) => {
      const idx = first + i;
      if (i >= n || idx >= lines.length) { r.row.hidden = true; r.idx = -1; return; }
      r.row.hidden = false;
      if (r.idx !== idx) {
        r.idx = idx;
        r.ln.textContent = String(idx + 1);
        const s = lines[idx];
        r.src.textContent = s.endsWith('\r') ? s.slice(0, -1) : s;
      }
      r.row.classList.toggle('cur', idx + 1 === curLine);
    });
  }
  function showLine(l, force) {
    if (!lines) return;
    const vis = Math.max(1, Math.floor(tv.clientHeight / LH)), first = firstVisible(), idx = l - 1;
    if (l >= 1 && l <= lines.length && (force || idx < first || idx >= first + vis)) {
      const top = Math.max(0, idx - Math.floor(vis / 3));
      tv.scrollTop = scaled() ? (top / Math.max(1, lines.length - vis)) * (MAXPX - tv.clientHeight) : top * LH;
    }
    renderText();
  }
  async function loadText() {
    const data = document.querySelector('script#kz-text');
    if (!meta.text || !data) { noText('The program text is not in this page.'); return; }
    const text = new TextDecoder().decode(await gunzip(base64Bytes(data)));
    lines = text.split('\n');
    if (lines.length > 1 && lines[lines.length - 1] === '') lines.pop();
    $('kz-program-spacer').style.height = Math.min(lines.length * LH, MAXPX) + 'px';
    txt('kz-program-head', 'Program · ' + fmtInt(lines.length) + ' lines');
    tvRows.style.setProperty('--ln', Math.max(4.5, String(lines.length).length + 2) + 'ch');
    let maxLine = 0;
    for (let i = 0; i < N; i++) if (lineOf[i] > maxLine) maxLine = lineOf[i];
    firstMoveOfLine = new Int32Array(Math.max(maxLine, lines.length) + 2).fill(-1);
    for (let i = N - 1; i >= 0; i--) if (lineOf[i] > 0) firstMoveOfLine[lineOf[i]] = i;
    tv.addEventListener('scroll', renderText, { passive: true });
    new ResizeObserver(() => renderText()).observe(tv);
    tvRows.addEventListener('click', (e) => {
      const r = rowPool.find((x) => x.row.contains(e.target));
      if (r && r.idx >= 0) jumpToLine(r.idx + 1);
    });
    showLine(curLine, true);
  }
  function noText(s) {
    const d = document.createElement('div');
    d.className = 'kz-text-none';
    d.textContent = s;
    tvRows.append(d);
  }
  // a line with no move: the first move of a later line
  function jumpToLine(l) {
    if (!firstMoveOfLine) return;
    for (let k = l; k < firstMoveOfLine.length; k++) {
      if (firstMoveOfLine[k] >= 0) { setMove(firstMoveOfLine[k] + 1); return; }
    }
  }

  // the current move: readouts, slider, text, picture
  function setCur(n) {
    n = Math.max(0, Math.min(N, Math.round(Number(n)) || 0));
    cur = n;
    const m = currentMove();
    const l = m >= 0 ? lineOf[m] : 0;
    readout();
    if (l !== curLine) { curLine = l; showLine(l, false); }
    schedule();
  }
  // draw now and wait for the GPU (finish alone does not wait in Chromium: a one-pixel read does)
  const px1 = new Uint8Array(4);
  function renderAndWait() {
    frameQueued = false;
    render();
    gl.finish();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px1);
  }
  function setMove(n) {
    const t0 = performance.now();
    pause();
    setCur(n);
    renderAndWait();
    return performance.now() - t0;
  }

  // ---------------------------------------------------------------- 8 input
  function pick(cx, cy) {
    const end = vstart[cur];
    if (!showPath || end < 2) return -1;
    const [a, b] = rows, t = cam.tgt;
    const ax = (a[0] * cssW) / 2, ay = (a[1] * cssW) / 2, az = (a[2] * cssW) / 2;
    const bx = (-b[0] * cssH) / 2, by = (-b[1] * cssH) / 2, bz = (-b[2] * cssH) / 2;
    const a0 = cssW / 2 - (ax * t[0] + ay * t[1] + az * t[2]) - cx;
    const b0 = cssH / 2 - (bx * t[0] + by * t[1] + bz * t[2]) - cy;
    const R = 6;
    let best = -1, bestD = R * R, px = 0, py = 0;
    for (let k = 0, j = 0, q = 0; k < end; k++, j += 3, q += 4) {
      const x = pos[j], y = pos[j + 1], z = pos[j + 2];
      const sx = ax * x + ay * y + az * z + a0, sy = bx * x + by * y + bz * z + b0;   // relative to the cursor
      if (k > 0 && attr[q + 3] === 0 && (showRapids || attr[q] !== 0) &&
          !((sx > R && px > R) || (sx < -R && px < -R) || (sy > R && py > R) || (sy < -R && py < -R))) {
        const dx = sx - px, dy = sy - py, l2 = dx * dx + dy * dy;
        const u = l2 > 0 ? Math.max(0, Math.min(1, -(px * dx + py * dy) / l2)) : 0;
        const ex = px + u * dx, ey = py + u * dy, d2 = ex * ex + ey * ey;
        if (d2 <= bestD) { bestD = d2; best = k; }
      }
      px = sx; py = sy;
    }
    if (best < 0) return -1;
    let lo = 0, hi = N;                // the move of vertex best: last i with vstart[i] <= best
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (vstart[mid] <= best) lo = mid; else hi = mid; }
    return lo;
  }
  function wireInput() {
    let drag = null;
    canvas.addEventListener('contextmenu', (e) => e.preventDefault());
    canvas.addEventListener('pointerdown', (e) => {
      canvas.setPointerCapture(e.pointerId);
      drag = { x: e.clientX, y: e.clientY, x0: e.clientX, y0: e.clientY, pan: e.button !== 0 || e.shiftKey, moved: false, button: e.button };
    });
    canvas.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      drag.x = e.clientX; drag.y = e.clientY;
      if (Math.abs(e.clientX - drag.x0) + Math.abs(e.clientY - drag.y0) > 4) drag.moved = true;
      if (!drag.moved) return;
      if (drag.pan) {
        const [r, u] = basis(), s = cam.scale;
        cam.tgt = cam.tgt.map((v, a) => v - r[a] * dx * s + u[a] * dy * s);
      } else {
        cam.yaw -= dx * 0.008;
        cam.pitch = Math.max(-Math.PI / 2, Math.min(Math.PI / 2, cam.pitch + dy * 0.008));
      }
      cameraChanged();
    });
    const up = (e) => {
      if (!drag) return;
      const d = drag;
      drag = null;
      if (!d.moved && d.button === 0 && e.type === 'pointerup') {
        const r = canvas.getBoundingClientRect();
        const m = pick(e.clientX - r.left, e.clientY - r.top);
        if (m >= 0) setMove(m + 1);
      }
    };
    canvas.addEventListener('pointerup', up);
    canvas.addEventListener('pointercancel', up);
    canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      const unit = e.deltaMode === 1 ? 33 : e.deltaMode === 2 ? 400 : 1;
      const f = Math.exp(Math.max(-200, Math.min(200, e.deltaY * unit)) * 0.002);
      const s1 = Math.max(1e-6, Math.min(1e5, cam.scale * f)), g = 1 - s1 / cam.scale;
      const r = canvas.getBoundingClientRect(), [rv, uv] = basis();
      const ox = (e.clientX - r.left - cssW / 2) * cam.scale, oy = (cssH / 2 - (e.clientY - r.top)) * cam.scale;
      cam.tgt = cam.tgt.map((v, a) => v + (rv[a] * ox + uv[a] * oy) * g);
      cam.scale = s1;
      cameraChanged();
    }, { passive: false });
    for (const b of document.querySelectorAll('#kz-views button')) b.addEventListener('click', () => setView(b.dataset.view));
    for (const b of document.querySelectorAll('#kz-steps button[data-step]')) b.addEventListener('click', () => { pause(); setCur(cur + Number(b.dataset.step)); });
    const slider = $('kz-slider');
    slider.addEventListener('input', () => { pause(); setCur(slider.value); });
    $('kz-playbtn').addEventListener('click', () => (playing ? pause() : play()));
    $('kz-colorby').addEventListener('change', (e) => { colourBy = e.target.value === 'tool' ? 1 : 0; legend(); invalidate(); });
    $('kz-show-path').addEventListener('change', (e) => { showPath = e.target.checked; invalidate(); });
    $('kz-show-rapids').addEventListener('change', (e) => { showRapids = e.target.checked; invalidate(); });
    $('kz-show-part').addEventListener('change', (e) => { showPart = e.target.checked; invalidate(); });
    document.addEventListener('keydown', (e) => {
      const tag = e.target && e.target.tagName;
      if (tag === 'INPUT' && e.target.type !== 'range' && e.target.type !== 'checkbox') return;
      if (tag === 'SELECT' || e.ctrlKey || e.metaKey || e.altKey) return;
      const step = e.shiftKey ? 100 : 1;
      if (e.key === 'ArrowRight') { pause(); setCur(cur + step); }
      else if (e.key === 'ArrowLeft') { pause(); setCur(cur - step); }
      else if (e.key === ' ' && tag !== 'BUTTON') { if (playing) pause(); else play(); }
      else if (e.key === 'f' || e.key === 'F') setView('fit');
      else if (e.key === 't' || e.key === 'T') setView('top');
      else if (e.key === 'i' || e.key === 'I') setView('iso');
      else return;
      e.preventDefault();
    });
    new ResizeObserver(() => { if (resize()) render(); }).observe(view);
  }
  // playback at a multiple of the machine's own time
  let playing = false, playClock = 0, lastT = 0;
  function play() {
    if (N === 0) return;
    if (cur >= N) setCur(0);
    playing = true;
    playClock = elapsed[cur];
    lastT = performance.now();
    txt('kz-playbtn', '❚❚');
    requestAnimationFrame(tick);
  }
  function pause() { playing = false; txt('kz-playbtn', '▶'); }
  function tick(t) {
    if (!playing) return;
    const dt = Math.min(0.1, Math.max(0, (t - lastT) / 1000));
    lastT = t;
    const speed = Number($('kz-speed').value) || 1;
    let n;
    if (elapsed[N] > 0) {
      playClock += dt * speed;
      let lo = cur, hi = N;              // last n with elapsed[n] <= playClock
      while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (elapsed[mid] <= playClock) lo = mid; else hi = mid - 1; }
      n = lo;
    } else n = cur + Math.max(1, Math.round(dt * speed * 10));
    setCur(n);
    if (cur >= N) pause(); else requestAnimationFrame(tick);
  }

  // ---------------------------------------------------------------- 9 start
  async function main() {
    const metaEl = $('kz-meta');
    if (!metaEl) throw new Error('this page has no data (kz-meta is missing)');
    meta = JSON.parse(metaEl.textContent);
    if (meta.version !== 1) throw new Error('this page\'s data is format version ' + meta.version + '; this viewer reads version 1');
    const finite = (a, n) => Array.isArray(a) && a.length === n && a.every(Number.isFinite);
    if (!(meta.quantum_mm > 0) || !finite(meta.origin_mm, 3) || !(meta.moves >= 0) || !(meta.vertices >= 0)) {
      throw new Error('this page\'s data is incomplete (moves, vertices, quantum_mm, origin_mm)');
    }
    N = Math.max(0, meta.moves | 0);
    V = Math.max(0, meta.vertices | 0);
    meta.tools = Array.isArray(meta.tools) ? meta.tools : [];
    unitMm = meta.unit_mm > 0 ? meta.unit_mm : 1;
    unitName = meta.units === 'inch' ? 'in' : 'mm';
    digits = unitMm > 1 ? 4 : 3;
    api.moves = N;
    document.title = (meta.title ? meta.title + ' · ' : '') + 'kezuri view';
    txt('kz-title', String(meta.title || 'kezuri view'));
    if (meta.rotary) $('kz-rotary').hidden = false;
    const notes = Array.isArray(meta.notes) ? meta.notes : [];
    for (const n of notes) { const li = document.createElement('li'); li.textContent = String(n); $('kz-notes').append(li); }
    $('kz-notes-box').hidden = !notes.length;

    if (typeof DecompressionStream !== 'function') throw new Error('this browser cannot unpack the page (no DecompressionStream): use a current Chrome, Edge, Firefox or Safari.');
    const dataEl = document.querySelector('script#kz-data');
    if (!dataEl) throw new Error('this page has no data (kz-data is missing)');
    const T = (api.timings = { start: performance.now() });
    const unpacked = gunzip(base64Bytes(dataEl));
    unpacked.catch(() => {});        // awaited below; not unhandled if WebGL fails first
    T.base64 = performance.now();
    startGl();
    T.startGl = performance.now();
    D = parseBlob(await unpacked, meta);
    T.gunzip = performance.now();
    const bb = meta.bbox_mm;
    if (Array.isArray(bb) && bb.length === 2 && bb.flat().every(Number.isFinite)) C = [0, 1, 2].map((a) => (bb[0][a] + bb[1][a]) / 2);
    else if (Array.isArray(meta.origin_mm)) C = meta.origin_mm.slice();
    buildPath();
    if (meta.sim && D.height) buildPart();
    for (const t of meta.tools) if (t && Array.isArray(t.profile)) for (const p of t.profile) if (Array.isArray(p) && p[0] > toolLen) toolLen = p[0];
    findTools();
    colourBy = usedTools.filter((t) => t !== 0xffff).length > 1 ? 1 : 0;
    $('kz-colorby').value = colourBy ? 'tool' : 'kind';

    T.geometry = performance.now();
    finishGl();
    T.upload = performance.now();
    const slider = $('kz-slider');
    slider.max = String(N);
    if (N === 0) for (const b of document.querySelectorAll('#kz-play button, #kz-play input')) b.disabled = true;
    if (part) $('kz-part-toggle').hidden = false;
    legend();
    colourBar();
    marks();
    wireInput();
    W = 0;
    resize();
    fit();
    updateMatrix();
    setCur(N);

    const moving = box && (box[1][0] - box[0][0] > 0 || box[1][1] - box[0][1] > 0 || box[1][2] - box[0][2] > 0);
    if (N === 0) message('This program has no moves: there is no toolpath to show.');
    else if (!V && D.kind.some((k) => k === UNPLACED)) message('Nothing to draw: every move goes to or from a place the program does not give (G28, G30, G53, or an axis not yet named).');
    else if (!V || !moving && !part) message('No motion: the ' + fmtInt(N) + ' moves of this program do not move the tool.');
    else message('');

    api.setMove = setMove;
    api.redraw = () => { const t0 = performance.now(); drawn = -1; renderAndWait(); return performance.now() - t0; };
    api.project = (p) => { const [x, y] = toScreen(p[0] - C[0], p[1] - C[1], p[2] - C[2]); return [x, y]; };
    api.state = () => {
      const k = currentVertex(), m = currentMove();
      const mm = k >= 0 ? vertexMm(k) : null;
      const f = (meta.frames || [])[m >= 0 ? D.frame[m] : 0] || [0, 0, 0];
      const placed = toolPlaced();
      return { move: cur, line: m >= 0 ? lineOf[m] : null, pos: mm && placed ? mm.map((v, a) => (v - f[a]) / unitMm) : null, posMm: placed ? mm : null, toolShown: placed, elapsedS: elapsed[cur] };
    };
    api.palette = { kind: KIND_COLOURS.map((c) => c.map((v) => Math.round(v * 255))), tool: TOOL_COLOURS.map((c) => c.map((v) => Math.round(v * 255))), background: BG.map((v) => Math.round(v * 255)) };
    api.colourBy = () => (colourBy ? 'tool' : 'kind');
    api.pick = (x, y) => pick(x, y);
    api.vertices = V;
    api.kindOf = (m) => (m >= 0 && m < N ? KINDS[D.kind[m]] || null : null);
    api.vertex = (k) => (k >= 0 && k < V ? vertexMm(k) : null);
    api.vertexOfMove = (m) => (m >= 0 && m < N && vstart[m + 1] > 0 ? vertexMm(vstart[m + 1] - 1) : null);

    renderAndWait();
    T.frame = performance.now();
    api.readyMs = performance.now();
    root.dataset.ready = '1';
    resolveReady(api);
    loadText().catch((e) => noText('The program text could not be unpacked: ' + e.message));
  }

  try {
    await main();
  } catch (e) {
    fail(e);
  }
})();
