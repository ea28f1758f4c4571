/* brdfit report viewer: per material, lit spheres of the measurement and of each fitted
 * model (WebGL 2), slices at any incidence, half/difference images, all evaluated from
 * the tables brdfit writes beside the page (mN-viewer.js, report_viewer.c). It works from
 * disk: nothing is fetched, the tables are inflated by the browser's DecompressionStream.
 * docs/report.md describes the page, the tables and window.brdfitViewer.
 *
 * brdfit's own code, no third-party script; its licence is brdfit's (debian/copyright). */
(function () {
  'use strict';
  const HALF_PI = Math.PI / 2;
  const SPHERE = 160;       /* sphere canvases, pixels */
  const SLICE_W = 440, SLICE_H = 300;
  const HD = 180;           /* half/difference images, pixels */
  const HD_OX = 34, HD_OY = 6;                   /* the image's place in its canvas ... */
  const HD_CW = HD + HD_OX + 8, HD_CH = HD + 62; /* ... which has room for axes and a colour bar */
  const HD_DECADES = 4;     /* the value images' colour range below the 99th percentile */
  const HD_SPAN = 2;        /* log2 ratios saturate at a factor of 4 */
  const SLICE_DECADES = 6;  /* the slice's log axis spans at most this below its top */
  const POINT_TOL = 2.5;    /* samples this close (degrees) to the slice's incidence ... */
  const PLANE_TOL = 2;      /* ... and to the plane of incidence are drawn on it */
  const COLORS = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#8c564b', '#e377c2', '#17becf',
                   '#bcbd22', '#7f7f7f'];

  const materials = [];
  const decoding = [];
  let gl = null, glCanvas = null, glProgram = null, glLoc = null, glError = null;

  /* ---- Tables: base64 -> inflate -> 16-bit codes -> values -------------------------- */

  function bytesOf(uri) {
    const b64 = uri.slice(uri.indexOf(',') + 1);
    const s = atob(b64);
    const out = new Uint8Array(s.length);
    for (let q = 0; q < s.length; q++) out[q] = s.charCodeAt(q);
    return out;
  }

  async function inflate(bytes) {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  }

  /* The codes, undone: byte planes joined, differences along runs summed. */
  async function codesOf(uri, run) {
    const planes = await inflate(bytesOf(uri));
    const n = planes.length / 2;
    const codes = new Uint16Array(n);
    for (let q = 0; q < n; q++) codes[q] = (planes[q] << 8) | planes[n + q];
    for (let q = 1; q < n; q++) if (q % run) codes[q] = (codes[q] + codes[q - 1]) & 0xffff;
    return codes;
  }

  /* Channel-major values: NaN no value, 0 zero, else exp(lo + (code - 2) * step). */
  async function valuesOf(enc, count, run) {
    const codes = await codesOf(enc.data, run);
    const v = new Float32Array(codes.length);
    for (let q = 0; q < codes.length; q++) {
      const c = Math.floor(q / count), k = codes[q];
      v[q] = k === 0 ? NaN : k === 1 ? 0 : Math.exp(enc.lo[c] + (k - 2) * enc.step[c]);
    }
    return v;
  }

  /* ---- Geometry: directions -> the table's (theta_h, theta_d, folded phi_d) ---------- */

  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function dirOf(thetaDeg, phiDeg) {
    const t = thetaDeg * Math.PI / 180, p = phiDeg * Math.PI / 180;
    return [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
  }
  function clamp(x, a, b) { return x < a ? a : x > b ? b : x; }

  /* Half/difference angles of light L and view V about normal n (unit vectors). phi_d
   * is folded into [0, 90] degrees: isotropic, reciprocal BRDFs repeat over phi_d ->
   * -phi_d and phi_d -> phi_d + 180, so |cos phi_d| is all that matters. The same
   * arithmetic as the shader below. */
  function halfDiff(n, L, V) {
    const h = [L[0] + V[0], L[1] + V[1], L[2] + V[2]];
    const hl = Math.hypot(h[0], h[1], h[2]);
    if (hl < 1e-12) return null;
    h[0] /= hl; h[1] /= hl; h[2] /= hl;
    const cth = clamp(dot(n, h), -1, 1), cd = clamp(dot(L, h), -1, 1);
    const np = [n[0] - cth * h[0], n[1] - cth * h[1], n[2] - cth * h[2]];
    const lp = [L[0] - cd * h[0], L[1] - cd * h[1], L[2] - cd * h[2]];
    const a = Math.hypot(np[0], np[1], np[2]), b = Math.hypot(lp[0], lp[1], lp[2]);
    const pd = a < 1e-9 || b < 1e-9 ? 0 : Math.acos(clamp(Math.abs(dot(np, lp)) / (a * b), 0, 1));
    return [Math.acos(cth), Math.acos(cd), pd];
  }

  /* Trilinear interpolation between the nodes (theta_h on its square-root scale); nodes
   * with no value are left out and the weights of the others renormalised. RGB, or null
   * where no node around has a value. */
  function lookup(T, g, th, td, pd) {
    const u = Math.sqrt(clamp(th / HALF_PI, 0, 1)) * (g.nh - 1);
    const v = clamp(td / HALF_PI, 0, 1) * (g.nd - 1), w = clamp(pd / HALF_PI, 0, 1) * (g.np - 1);
    const i0 = Math.min(Math.floor(u), g.nh - 2), j0 = Math.min(Math.floor(v), g.nd - 2);
    const k0 = Math.min(Math.floor(w), g.np - 2);
    const fu = u - i0, fv = v - j0, fw = w - k0, N = g.nh * g.nd * g.np;
    let r = 0, gg = 0, b = 0, ws = 0;
    for (let c = 0; c < 8; c++) {
      const di = c & 1, dj = (c >> 1) & 1, dk = c >> 2;
      const wt = (di ? fu : 1 - fu) * (dj ? fv : 1 - fv) * (dk ? fw : 1 - fw);
      if (wt <= 0) continue;
      const q = i0 + di + g.nh * (j0 + dj + g.nd * (k0 + dk));
      if (Number.isNaN(T[q])) continue;
      r += wt * T[q]; gg += wt * T[N + q]; b += wt * T[2 * N + q]; ws += wt;
    }
    return ws > 1e-6 ? [r / ws, gg / ws, b / ws] : null;
  }

  /* f at light L and view V about normal n: RGB; [0, 0, 0] below the horizon. */
  function evalAt(m, src, n, L, V) {
    if (dot(n, L) <= 0 || dot(n, V) <= 0) return [0, 0, 0];
    const a = halfDiff(n, L, V);
    return a ? lookup(src.values, m.grid, a[0], a[1], a[2]) : null;
  }
  const UP = [0, 0, 1];

  function mean3(c) { return c ? (c[0] + c[1] + c[2]) / 3 : NaN; }

  /* ---- WebGL: one context for the page, each sphere drawn then copied to its canvas --- */

  const VERT = `#version 300 es
    in vec2 pos; out vec2 uv;
    void main() { uv = pos; gl_Position = vec4(pos, 0.0, 1.0); }`;
  const FRAG = `#version 300 es
    precision highp float; precision highp int;
    in vec2 uv; out vec4 color;
    uniform highp sampler2D table; uniform ivec3 grid; uniform vec3 light; uniform float exposure;
    const float HALF_PI = 1.5707963267948966;
    vec4 node(int i, int j, int k) { return texelFetch(table, ivec2(i, j + grid.y * k), 0); }
    float srgb(float x) { return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055; }
    void main() {
      vec2 s = vec2(uv.x, uv.y);
      float r2 = dot(s, s);
      if (r2 >= 1.0) { color = vec4(0.0, 0.0, 0.0, 1.0); return; }
      vec3 n = vec3(s, sqrt(1.0 - r2)), V = vec3(0.0, 0.0, 1.0), L = light;
      float nl = dot(n, L);
      if (nl <= 0.0 || n.z <= 0.0) { color = vec4(0.0, 0.0, 0.0, 1.0); return; }
      vec3 h = L + V;
      if (length(h) < 1e-12) { color = vec4(0.0, 0.0, 0.0, 1.0); return; }
      h = normalize(h);
      float cth = clamp(dot(n, h), -1.0, 1.0), cd = clamp(dot(L, h), -1.0, 1.0);
      vec3 np = n - cth * h, lp = L - cd * h;
      float a = length(np), b = length(lp);
      float pd = (a < 1e-9 || b < 1e-9) ? 0.0 : acos(clamp(abs(dot(np, lp)) / (a * b), 0.0, 1.0));
      float u = sqrt(clamp(acos(cth) / HALF_PI, 0.0, 1.0)) * float(grid.x - 1);
      float v = clamp(acos(cd) / HALF_PI, 0.0, 1.0) * float(grid.y - 1);
      float w = clamp(pd / HALF_PI, 0.0, 1.0) * float(grid.z - 1);
      int i0 = min(int(floor(u)), grid.x - 2), j0 = min(int(floor(v)), grid.y - 2), k0 = min(int(floor(w)), grid.z - 2);
      float fu = u - float(i0), fv = v - float(j0), fw = w - float(k0);
      vec3 acc = vec3(0.0); float ws = 0.0;
      for (int c = 0; c < 8; c++) {
        int di = c & 1, dj = (c >> 1) & 1, dk = c >> 2;
        float wt = (di == 1 ? fu : 1.0 - fu) * (dj == 1 ? fv : 1.0 - fv) * (dk == 1 ? fw : 1.0 - fw);
        if (wt <= 0.0) continue;
        vec4 t = node(i0 + di, j0 + dj, k0 + dk);
        if (t.a < 0.5) continue;
        acc += wt * t.rgb; ws += wt;
      }
      vec3 f = ws > 1e-6 ? acc / ws : vec3(0.0);
      vec3 e = clamp(f * nl * exposure, 0.0, 1.0);
      color = vec4(srgb(e.r), srgb(e.g), srgb(e.b), 1.0);
    }`;

  function initGL() {
    if (gl || glError) return gl;
    glCanvas = document.createElement('canvas');
    glCanvas.width = glCanvas.height = SPHERE;
    gl = glCanvas.getContext('webgl2', {preserveDrawingBuffer: true, antialias: false});
    if (!gl) { glError = 'this browser has no WebGL 2'; return null; }
    const shader = (type, text) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, text);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    glProgram = gl.createProgram();
    gl.attachShader(glProgram, shader(gl.VERTEX_SHADER, VERT));
    gl.attachShader(glProgram, shader(gl.FRAGMENT_SHADER, FRAG));
    gl.linkProgram(glProgram);
    if (!gl.getProgramParameter(glProgram, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(glProgram));
    gl.useProgram(glProgram);
    const buf = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
    const at = gl.getAttribLocation(glProgram, 'pos');
    gl.enableVertexAttribArray(at);
    gl.vertexAttribPointer(at, 2, gl.FLOAT, false, 0, 0);
    glLoc = {};
    for (const name of ['table', 'grid', 'light', 'exposure']) glLoc[name] = gl.getUniformLocation(glProgram, name);
    gl.viewport(0, 0, SPHERE, SPHERE);
    return gl;
  }

  /* A table as an RGBA32F texture, nh wide and nd * np high; alpha 1 where it has a value. */
  function texture(m, src) {
    if (src.texture) return src.texture;
    const g = m.grid, N = g.nh * g.nd * g.np, px = new Float32Array(4 * N), T = src.values;
    for (let q = 0; q < N; q++) {
      const ok = !Number.isNaN(T[q]);
      px[4 * q] = ok ? T[q] : 0; px[4 * q + 1] = ok ? T[N + q] : 0; px[4 * q + 2] = ok ? T[2 * N + q] : 0;
      px[4 * q + 3] = ok ? 1 : 0;
    }
    src.texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, src.texture);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, g.nh, g.nd * g.np, 0, gl.RGBA, gl.FLOAT, px);
    return src.texture;
  }

  function drawSphere(m, src) {
    if (!initGL()) return;
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, texture(m, src));
    gl.uniform1i(glLoc.table, 0);
    gl.uniform3i(glLoc.grid, m.grid.nh, m.grid.nd, m.grid.np);
    gl.uniform3fv(glLoc.light, m.light);
    gl.uniform1f(glLoc.exposure, m.exposure * Math.pow(2, m.stops));
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const ctx = src.sphere.getContext('2d');
    ctx.drawImage(glCanvas, 0, 0);
  }

  function drawSpheres(m) {
    for (const src of m.sources) if (src.values && src.sphere) drawSphere(m, src);
    const t = lightAngles(m);
    m.ui.lightText.textContent = `light at ${t.theta.toFixed(1)}\u00b0 from the view, azimuth ${t.phi.toFixed(1)}\u00b0`;
  }

  function lightAngles(m) {
    const L = m.light;
    let phi = Math.atan2(L[1], L[0]) * 180 / Math.PI;
    if (phi < 0) phi += 360;
    return {theta: Math.acos(clamp(L[2], -1, 1)) * 180 / Math.PI, phi: phi};
  }

  /* One exposure for all: the 99th percentile of the brightest channel of the lit pixels
   * of the measured sphere (of the best model's without one) at the starting light is
   * white, as the static spheres. */
  function autoExposure(m) {
    const src = m.sources.find((s) => s.values && s.kind === 'measured') ||
                m.sources.filter((s) => s.values).sort((a, b) => a.rank - b.rank)[0];
    if (!src) return 1;
    const px = [], n = 64;
    for (let y = 0; y < n; y++)
      for (let x = 0; x < n; x++) {
        const sx = 2 * (x + 0.5) / n - 1, sy = 1 - 2 * (y + 0.5) / n, r2 = sx * sx + sy * sy;
        if (r2 >= 1) continue;
        const nn = [sx, sy, Math.sqrt(1 - r2)], nl = dot(nn, m.light);
        if (nl <= 0) continue;
        const f = evalAt(m, src, nn, m.light, UP);
        const v = f ? Math.max(f[0], f[1], f[2]) * nl : 0;
        if (v > 0) px.push(v);
      }
    if (!px.length) return 1;
    px.sort((a, b) => a - b);
    return 1 / px[Math.min(px.length - 1, Math.floor(0.99 * (px.length - 1)))];
  }

  /* ---- Slices ---------------------------------------------------------------------- */

  /* In the plane of incidence: light at theta_i (azimuth 0), view at theta_o, the mirror
   * side (azimuth 180) positive. */
  function slicePair(ti, to) {
    return [dirOf(ti, 0), to >= 0 ? dirOf(to, 180) : dirOf(-to, 0)];
  }

  /* Measured samples near this incidence and in the plane, as [signed theta_o, value]. */
  function slicePoints(m, ti) {
    const p = m.points, out = [];
    if (!p) return out;
    for (let q = 0; q < p.n; q++) {
      const a = p.angles, n = p.n;
      if (Math.abs(a[q] / 100 - ti) > POINT_TOL) continue;
      let dphi = Math.abs(((a[3 * n + q] - a[n + q]) / 100) % 360);
      if (dphi > 180) dphi = 360 - dphi;
      const to = a[2 * n + q] / 100;
      const v = (p.values[q] + p.values[n + q] + p.values[2 * n + q]) / 3;
      if (dphi >= 180 - PLANE_TOL) out.push([to, v]);
      else if (dphi <= PLANE_TOL) out.push([-to, v]);
    }
    return out;
  }

  function sliceCurve(m, src, ti) {
    const pts = [];
    for (let q = -360; q <= 360; q++) {
      const to = q / 4, [L, V] = slicePair(ti, to);
      pts.push([to, mean3(evalAt(m, src, UP, L, V))]);
    }
    return pts;
  }

  function drawSlice(m) {
    const ti = m.incidence, c = m.ui.slice, ctx = c.getContext('2d');
    const curves = m.sources.filter((s) => s.on && s.values).map((s) => ({s: s, pts: sliceCurve(m, s, ti)}));
    const points = m.sources.some((s) => s.on && s.kind === 'measured') ? slicePoints(m, ti) : [];
    let hi = -Infinity, lo = Infinity;
    for (const cv of curves)
      for (const [, v] of cv.pts) if (v > 0) { hi = Math.max(hi, Math.log10(v)); lo = Math.min(lo, Math.log10(v)); }
    for (const [, v] of points) if (v > 0) { hi = Math.max(hi, Math.log10(v)); lo = Math.min(lo, Math.log10(v)); }
    if (!(hi >= lo)) { hi = 0; lo = -1; }
    lo = Math.max(lo, hi - SLICE_DECADES);
    const pad = Math.max(0.1, 0.05 * (hi - lo));
    hi += pad; lo -= pad;
    const L = 56, R = 10, T = 10, B = 34, W = SLICE_W - L - R, H = SLICE_H - T - B;
    const X = (to) => L + (to + 90) / 180 * W, Y = (v) => T + (hi - Math.log10(v)) / (hi - lo) * H;
    m.sliceAxes = {X: X, L: L, W: W, lo: lo, hi: hi};
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, SLICE_W, SLICE_H);
    ctx.strokeStyle = '#ccc';
    ctx.fillStyle = '#333';
    ctx.font = '11px sans-serif';
    ctx.lineWidth = 1;
    /* Decades; 2 and 5 times them too when the axis spans few decades. */
    const mantissas = hi - lo < 2.5 ? [1, 2, 5] : [1];
    for (let d = Math.floor(lo); d <= Math.ceil(hi); d++)
      for (const k of mantissas) {
        const t = Math.log10(k) + d;
        if (t < lo || t > hi) continue;
        ctx.beginPath(); ctx.moveTo(L, Y(Math.pow(10, t))); ctx.lineTo(L + W, Y(Math.pow(10, t))); ctx.stroke();
        ctx.fillText(`${k}e${d}`, 4, Y(Math.pow(10, t)) + 4);
      }
    for (let to = -90; to <= 90; to += 30) {
      ctx.beginPath(); ctx.moveTo(X(to), T); ctx.lineTo(X(to), T + H); ctx.stroke();
      ctx.fillText(`${to}\u00b0`, X(to) - 10, T + H + 14);
    }
    ctx.fillText('\u03b8o (mirror side right); f in 1/sr, mean of the channels', L + 40, SLICE_H - 4);
    ctx.setLineDash([3, 3]); ctx.strokeStyle = '#888';
    ctx.beginPath(); ctx.moveTo(X(ti), T); ctx.lineTo(X(ti), T + H); ctx.stroke();
    ctx.setLineDash([]);
    ctx.save();
    ctx.beginPath(); ctx.rect(L, T, W, H); ctx.clip();
    for (const cv of curves) {
      ctx.strokeStyle = cv.s.color;
      ctx.lineWidth = cv.s.kind === 'measured' ? 2.5 : 1.5;
      ctx.beginPath();
      let pen = false;
      for (const [to, v] of cv.pts) {
        if (!(v > 0)) { pen = false; continue; }
        if (pen) ctx.lineTo(X(to), Y(v)); else ctx.moveTo(X(to), Y(v));
        pen = true;
      }
      ctx.stroke();
    }
    ctx.fillStyle = '#000';
    for (const [to, v] of points) if (v > 0) ctx.fillRect(X(to) - 2, Y(v) - 2, 4, 4);
    if (m.pointer !== null) {
      ctx.strokeStyle = '#000';
      ctx.beginPath(); ctx.moveTo(X(m.pointer), T); ctx.lineTo(X(m.pointer), T + H); ctx.stroke();
    }
    ctx.restore();
    m.ui.sliceText.textContent = `incidence ${ti}\u00b0` +
      (m.points ? `; ${points.length} measured samples within ${POINT_TOL}\u00b0 of it and ${PLANE_TOL}\u00b0 of the plane` : '');
    readout(m);
  }

  /* The value and error of each source at the pointer's theta_o. */
  function readout(m) {
    const box = m.ui.readout;
    if (m.pointer === null) { box.textContent = 'Point at the slice to read values.'; return; }
    const to = m.pointer, [L, V] = slicePair(m.incidence, to);
    const meas = m.sources.find((s) => s.kind === 'measured' && s.values);
    let ref = meas ? mean3(evalAt(m, meas, UP, L, V)) : NaN;
    let refText = meas ? 'measured table' : '';
    if (!meas && m.points) {
      let best = null;
      for (const p of slicePoints(m, m.incidence)) if (Math.abs(p[0] - to) <= 1 && (!best || Math.abs(p[0] - to) < Math.abs(best[0] - to))) best = p;
      if (best) { ref = best[1]; refText = `measured sample at ${best[0].toFixed(1)}\u00b0`; }
    }
    const rows = [`\u03b8i ${m.incidence}\u00b0, \u03b8o ${to.toFixed(2)}\u00b0` + (refText ? `: ${refText} ${fmt(ref)}` : '')];
    for (const s of m.sources) {
      if (!s.on || !s.values || s.kind === 'measured') continue;
      const v = mean3(evalAt(m, s, UP, L, V));
      rows.push(`${s.name}: ${fmt(v)}` + (ref > 0 && v >= 0 ? ` (${((v / ref - 1) * 100).toFixed(1)}% vs measured)` : ''));
    }
    box.textContent = rows.join('\n');
  }

  function fmt(v) { return Number.isFinite(v) ? v.toPrecision(4) : '\u2013'; }

  /* ---- Half/difference images ------------------------------------------------------ */

  const VIRIDIS = [[68, 1, 84], [72, 40, 120], [62, 74, 137], [49, 104, 142], [38, 130, 142], [31, 158, 137],
                   [53, 183, 121], [110, 206, 88], [181, 222, 43], [253, 231, 37]];
  const RDBU = [[5, 48, 97], [33, 102, 172], [67, 147, 195], [146, 197, 222], [209, 229, 240], [247, 247, 247],
                [253, 219, 199], [244, 165, 130], [214, 96, 77], [178, 24, 43], [103, 0, 31]];
  function ramp(tab, t) {
    const x = clamp(t, 0, 1) * (tab.length - 1), i = Math.min(Math.floor(x), tab.length - 2), f = x - i;
    return [0, 1, 2].map((c) => Math.round(tab[i][c] + f * (tab[i + 1][c] - tab[i][c])));
  }
  const NONE = [150, 150, 150];

  /* Column x: theta_h on the square-root scale; row y from the bottom: theta_d. */
  function hdAngles(x, y) {
    const u = (x + 0.5) / HD;
    return [u * u * HALF_PI, (HD - 1 - y + 0.5) / HD * HALF_PI];
  }
  function hdPixel(th, td) {
    return [Math.floor(Math.sqrt(th / HALF_PI) * HD), HD - 1 - Math.floor(td / HALF_PI * HD)];
  }

  function hdImage(m, fn) {
    const img = new ImageData(HD, HD);
    for (let y = 0; y < HD; y++)
      for (let x = 0; x < HD; x++) {
        const [th, td] = hdAngles(x, y), c = fn(th, td), o = 4 * (y * HD + x);
        img.data[o] = c[0]; img.data[o + 1] = c[1]; img.data[o + 2] = c[2]; img.data[o + 3] = 255;
      }
    return img;
  }

  /* log10 range: the 99th percentile of the values, HD_DECADES below it. */
  function logRange(vals) {
    const v = vals.filter((x) => x > 0).sort((a, b) => a - b);
    if (!v.length) return [-HD_DECADES, 0];
    const hi = Math.log10(v[Math.min(v.length - 1, Math.floor(0.99 * (v.length - 1)))]);
    return [hi - HD_DECADES, hi];
  }

  function pointHD(m, q) {
    const p = m.points, a = p.angles, n = p.n;
    const L = dirOf(a[q] / 100, a[n + q] / 100), V = dirOf(a[2 * n + q] / 100, a[3 * n + q] / 100);
    return halfDiff(UP, L, V);
  }

  /* Axes (theta_h ticks on the square-root scale, theta_d up) and a colour bar from
   * `tab` labelled a and b at its ends, around the image. */
  function hdFrame(ctx, tab, a, b, title) {
    ctx.fillStyle = '#333';
    ctx.strokeStyle = '#333';
    ctx.font = '10px sans-serif';
    ctx.strokeRect(HD_OX - 0.5, HD_OY - 0.5, HD + 1, HD + 1);
    for (const t of [0, 2, 10, 25, 45, 90]) {
      const x = HD_OX + Math.sqrt(t / 90) * HD;
      ctx.fillRect(x, HD_OY + HD, 1, 4);
      ctx.fillText(`${t}`, x - 4, HD_OY + HD + 14);
    }
    ctx.fillText('\u03b8h (\u00b0)', HD_OX + HD / 2 - 12, HD_OY + HD + 25);
    for (const t of [0, 30, 60, 90]) {
      const y = HD_OY + HD - t / 90 * HD;
      ctx.fillRect(HD_OX - 4, y, 4, 1);
      ctx.fillText(`${t}`, HD_OX - 18, y + 4);
    }
    ctx.save();
    ctx.translate(9, HD_OY + HD / 2 + 10);
    ctx.rotate(-Math.PI / 2);
    ctx.fillText('\u03b8d (\u00b0)', 0, 0);
    ctx.restore();
    const y = HD_OY + HD + 32;
    for (let x = 0; x < HD; x++) {
      ctx.fillStyle = `rgb(${ramp(tab, x / (HD - 1)).join(',')})`;
      ctx.fillRect(HD_OX + x, y, 1, 8);
    }
    ctx.fillStyle = '#333';
    ctx.fillText(a, HD_OX, y + 19);
    ctx.fillText(b, HD_OX + HD - ctx.measureText(b).width, y + 19);
    ctx.fillText(title, HD_OX + HD / 2 - ctx.measureText(title).width / 2, y + 19);
  }

  function hdClear(ctx) {
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, HD_CW, HD_CH);
  }

  function drawHalfDiff(m) {
    const meas = m.sources.find((s) => s.kind === 'measured' && s.values);
    const model = m.sources.find((s) => s.kind === 'model' && String(s.index) === m.ui.hdSelect.value);
    const at = (s, th, td) => mean3(lookup(s.values, m.grid, th, td, HALF_PI));
    const left = m.ui.hdLeft.getContext('2d'), right = m.ui.hdRight.getContext('2d');
    if (meas || !m.points) {
      /* Without a measurement (brdfit report) the best-ranked model is the reference. */
      const base = meas || m.sources.filter((s) => s.kind === 'model').sort((a, b) => a.rank - b.rank)[0];
      if (!base) { m.ui.hdText.textContent = 'No model was fitted.'; return; }
      const baseName = meas ? 'measured' : base.name;
      const vals = [];
      for (let x = 0; x < HD; x += 2) for (let y = 0; y < HD; y += 2) vals.push(at(base, ...hdAngles(x, y)));
      const [lo, hi] = logRange(vals);
      const valueColor = (v) => Number.isNaN(v) ? NONE : v <= 0 ? VIRIDIS[0] : ramp(VIRIDIS, (Math.log10(v) - lo) / (hi - lo));
      hdClear(left);
      hdClear(right);
      left.putImageData(hdImage(m, (th, td) => valueColor(at(base, th, td))), HD_OX, HD_OY);
      hdFrame(left, VIRIDIS, `1e${lo.toFixed(1)}`, `1e${hi.toFixed(1)}`, 'f (1/sr)');
      if (model) {
        right.putImageData(hdImage(m, (th, td) => {
          const a = at(model, th, td), b = at(base, th, td);
          if (!(b > 0) || Number.isNaN(a)) return NONE;
          return ramp(RDBU, 0.5 + 0.5 * clamp(Math.log2(Math.max(a, 1e-30) / b) / HD_SPAN, -1, 1));
        }), HD_OX, HD_OY);
        hdFrame(right, RDBU, `-${HD_SPAN}`, `+${HD_SPAN}`, `log2(${model.name} / ${baseName})`);
      }
      m.ui.hdText.textContent = (meas ? 'Left: the measurement' : `Left: ${base.name}, the best-ranked model (no measurement)`) +
        `, \u03c6d 90\u00b0, log colour 10^${lo.toFixed(2)} to 10^${hi.toFixed(2)} 1/sr. Right: ` +
        `log2(${model ? model.name : '-'} / ${baseName}), white equal, red brighter, blue darker, saturating at a factor of ${Math.pow(2, HD_SPAN)}.`;
      return;
    }
    /* Scattered samples: each a point at its (theta_h, theta_d), every phi_d. */
    const p = m.points, n = p.n, vals = [];
    for (let q = 0; q < n; q++) vals.push((p.values[q] + p.values[n + q] + p.values[2 * n + q]) / 3);
    const [lo, hi] = logRange(vals);
    for (const ctx of [left, right]) { hdClear(ctx); ctx.fillStyle = '#eee'; ctx.fillRect(HD_OX, HD_OY, HD, HD); }
    for (let q = 0; q < n; q++) {
      const a = pointHD(m, q);
      if (!a) continue;
      const [x, y] = hdPixel(a[0], a[1]), v = vals[q];
      left.fillStyle = `rgb(${(v > 0 ? ramp(VIRIDIS, (Math.log10(v) - lo) / (hi - lo)) : VIRIDIS[0]).join(',')})`;
      left.fillRect(HD_OX + x - 1, HD_OY + y - 1, 3, 3);
      if (model && v > 0) {
        const mv = mean3(lookup(model.values, m.grid, a[0], a[1], a[2]));
        right.fillStyle = `rgb(${ramp(RDBU, 0.5 + 0.5 * clamp(Math.log2(Math.max(mv, 1e-30) / v) / HD_SPAN, -1, 1)).join(',')})`;
        right.fillRect(HD_OX + x - 1, HD_OY + y - 1, 3, 3);
      }
    }
    hdFrame(left, VIRIDIS, `1e${lo.toFixed(1)}`, `1e${hi.toFixed(1)}`, 'f (1/sr)');
    if (model) hdFrame(right, RDBU, `-${HD_SPAN}`, `+${HD_SPAN}`, `log2(${model.name} / measured)`);
    m.ui.hdText.textContent = `Left: the ${n} measured samples shown (of ${p.of}) at their \u03b8h, \u03b8d (every \u03c6d), ` +
      `log colour 10^${lo.toFixed(2)} to 10^${hi.toFixed(2)} 1/sr. Right: log2(${model ? model.name : '-'} / measured) at each ` +
      `sample, red brighter, blue darker, saturating at a factor of ${Math.pow(2, HD_SPAN)}.`;
  }

  /* ---- The page ---------------------------------------------------------------------- */

  function el(tag, attrs, ...kids) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    for (const k of kids) e.append(k);
    return e;
  }

  function build(m) {
    const root = document.getElementById('viewer-' + m.id);
    root.textContent = '';
    const ui = m.ui = {};
    ui.lightText = el('span', {class: 'light'});
    ui.stops = el('input', {type: 'range', min: '-6', max: '6', step: '0.5', value: '0', 'aria-label': 'exposure'});
    const head = el('p', {}, 'Drag on a sphere to move the light (one exposure for all; view from above). ',
                    ui.lightText, '. Exposure ', ui.stops);
    const toggles = el('p', {class: 'toggles'}, 'Show: ');
    const row = el('div', {class: 'row'});
    for (const s of m.sources) {
      const box = el('input', {type: 'checkbox'});
      box.checked = true;
      box.addEventListener('change', () => { s.on = box.checked; s.figure.style.display = s.on ? '' : 'none'; drawSlice(m); });
      s.toggle = box;
      const label = el('label', {style: `color:${s.color}`}, box, ' ' + s.name + ' ');
      toggles.append(label);
      const fig = el('figure', s.kind === 'model' ? {id: `${m.id}-view-${s.index}`} : {});
      if (s.values) {
        s.sphere = el('canvas', {width: String(SPHERE), height: String(SPHERE), class: 'sphere', 'data-source': s.name});
        fig.append(s.sphere);
      } else {
        fig.append(el('div', {class: 'nosphere'}, s.why));
      }
      fig.append(el('figcaption', {}, s.name + (s.kind === 'model' ? ` (rank ${s.rank}, k ${s.k})` : '')));
      s.figure = fig;
      row.append(fig);
    }
    ui.slider = el('input', {type: 'range', min: '0', max: '85', step: '1', value: String(m.incidence), 'aria-label': 'incidence'});
    ui.slice = el('canvas', {width: String(SLICE_W), height: String(SLICE_H), class: 'slice'});
    ui.sliceText = el('span', {});
    ui.readout = el('pre', {class: 'readout'});
    ui.hdSelect = el('select', {'aria-label': 'model'});
    for (const s of m.sources) if (s.kind === 'model') ui.hdSelect.append(el('option', {value: String(s.index)}, s.name));
    ui.hdLeft = el('canvas', {width: String(HD_CW), height: String(HD_CH), class: 'hd'});
    ui.hdRight = el('canvas', {width: String(HD_CW), height: String(HD_CH), class: 'hd'});
    ui.hdText = el('p', {class: 'hdtext'});
    root.append(head, toggles, row,
                el('p', {}, 'Slice at incidence ', ui.slider, ' ', ui.sliceText),
                el('div', {class: 'row'}, ui.slice, ui.readout),
                el('p', {}, 'Half/difference images (\u03b8h across on a square-root scale, \u03b8d up) of model ', ui.hdSelect),
                el('div', {class: 'row'}, ui.hdLeft, ui.hdRight), ui.hdText);

    const drag = (ev) => {
      const r = ev.target.getBoundingClientRect();
      let sx = 2 * (ev.clientX - r.left) / r.width - 1, sy = 1 - 2 * (ev.clientY - r.top) / r.height;
      const l = Math.hypot(sx, sy);
      if (l > 0.999) { sx *= 0.999 / l; sy *= 0.999 / l; }
      m.light = [sx, sy, Math.sqrt(Math.max(0, 1 - sx * sx - sy * sy))];
      drawSpheres(m);
    };
    for (const s of m.sources) {
      if (!s.sphere) continue;
      s.sphere.addEventListener('pointerdown', (ev) => { m.dragging = true; s.sphere.setPointerCapture(ev.pointerId); drag(ev); });
      s.sphere.addEventListener('pointermove', (ev) => { if (m.dragging) drag(ev); });
      s.sphere.addEventListener('pointerup', () => { m.dragging = false; });
    }
    ui.stops.addEventListener('input', () => { m.stops = Number(ui.stops.value); drawSpheres(m); });
    ui.slider.addEventListener('input', () => { m.incidence = Number(ui.slider.value); drawSlice(m); });
    ui.slice.addEventListener('pointermove', (ev) => {
      const r = ui.slice.getBoundingClientRect(), a = m.sliceAxes;
      const to = ((ev.clientX - r.left) * SLICE_W / r.width - a.L) / a.W * 180 - 90;
      m.pointer = to >= -90 && to <= 90 ? Math.round(to * 4) / 4 : null;
      drawSlice(m);
    });
    ui.slice.addEventListener('pointerleave', () => { m.pointer = null; drawSlice(m); });
    ui.hdSelect.addEventListener('change', () => drawHalfDiff(m));
  }

  /* The table's link #mN-view-J: that model in the half/difference images, shown. */
  function follow() {
    const hit = /^#(m\d+)-view-(\d+)$/.exec(location.hash);
    const m = hit && materials.find((x) => x.id === hit[1]);
    const s = m && m.ui && m.sources.find((x) => x.kind === 'model' && String(x.index) === hit[2]);
    if (!s) return;
    if (!s.on) { s.on = true; s.toggle.checked = true; s.figure.style.display = ''; drawSlice(m); }
    m.ui.hdSelect.value = String(s.index);
    drawHalfDiff(m);
  }

  async function load(data) {
    const m = {id: data.id, title: data.title, grid: data.grid, sources: [], points: null, light: dirOf(45, 0),
               stops: 0, incidence: 30, pointer: null, dragging: false};
    const count = data.grid.nh * data.grid.nd * data.grid.np;
    materials.push(m);
    const meas = data.measured || {};
    const ms = {kind: 'measured', name: 'measured', color: '#000', on: true, rank: 0, why: meas.why || ''};
    if (meas.table) ms.values = await valuesOf(meas.table, count, data.grid.nh);
    if (meas.points) {
      const n = meas.points.n;
      m.points = {n: n, of: meas.points.of, angles: await codesOf(meas.points.angles.data, n),
                  values: await valuesOf(meas.points.values, n, n)};
      ms.why = `scattered samples (${meas.points.of}): shown as points in the slices and half/difference images`;
    }
    m.sources.push(ms);
    let c = 0;
    for (const e of data.models)
      m.sources.push({kind: 'model', name: e.name, index: e.index, rank: e.rank, k: e.k, on: true,
                      color: COLORS[c++ % COLORS.length], values: await valuesOf(e.table, count, data.grid.nh)});
    m.exposure = autoExposure(m);
    build(m);
    drawSpheres(m);
    drawSlice(m);
    drawHalfDiff(m);
    if (glError) document.getElementById('viewer-' + m.id).prepend(el('p', {}, `Spheres not drawn: ${glError}.`));
  }

  function find(material) {
    return materials.find((m) => m.id === material || m.title === material || m.id === 'm' + material);
  }
  function sourceOf(m, model) {
    return m && m.sources.find((s) => s.name === model || (s.kind === 'model' && s.index === model));
  }

  window.brdfitViewer = {
    add(data) {
      decoding.push(load(data).catch((e) => { console.error('brdfit viewer:', e); throw e; }));
    },
    /* Resolves once every material on the page is decoded and drawn. */
    ready: new Promise((resolve, reject) => {
      const go = () => Promise.all(decoding).then(() => resolve(materials.map((m) => m.id)), reject);
      if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', go); else go();
    }),
    materials() { return materials.map((m) => ({id: m.id, title: m.title})); },
    models(material) { const m = find(material); return m ? m.sources.map((s) => s.name) : null; },
    /* f (RGB, 1/sr) as the viewer draws it, directions in degrees in the surface's frame;
     * null where the table has no value (nothing measured there). */
    value(material, model, ti, pi, to, po) {
      const m = find(material), s = sourceOf(m, model);
      if (!s || !s.values) return null;
      return evalAt(m, s, UP, dirOf(ti, pi), dirOf(to, po));
    },
    /* The light, degrees: theta from the view direction, phi about it from the image's x. */
    light(material) { const m = find(material); return m ? lightAngles(m) : null; },
    setLight(material, theta, phi) {
      const m = find(material);
      if (m) { m.light = dirOf(theta, phi); drawSpheres(m); }
    },
    incidence(material) { const m = find(material); return m ? m.incidence : null; },
  };
  window.addEventListener('hashchange', follow);
  window.brdfitViewer.ready.then(follow, () => {});
})();
