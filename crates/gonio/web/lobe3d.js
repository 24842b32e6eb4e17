// The 3D lobe in WebGL: the surface r(wo)·wo over the hemisphere of viewing directions, one per
// shown model, r = ρ·cos θo or ρ as on the in-plane plot, turned by dragging.
'use strict';

window.Lobe3d = (() => {
  const canvas = document.getElementById('lobe3d');
  // No multisampling: where WebGL runs in software (no GPU) it would quadruple the fill cost.
  const gl = canvas.getContext('webgl', { antialias: false, premultipliedAlpha: false });
  let yaw = -0.9, pitch = 0.45, last = { models: [], state: null };
  if (!gl) {
    const g = canvas.getContext('2d');
    g.fillText('WebGL is not available in this browser', 20, 40);
    return { draw() {} };
  }
  const vs = `attribute vec3 p; attribute vec3 n; uniform mat4 m; varying vec3 vn;
    void main() { vn = mat3(m) * n; gl_Position = m * vec4(p, 1.0); }`;
  const fs = `precision mediump float; varying vec3 vn; uniform vec4 c; uniform float lit;
    void main() { float d = abs(normalize(vn + vec3(1e-6)).z);
      gl_FragColor = vec4(c.rgb * mix(1.0, 0.35 + 0.65 * d, lit), c.a); }`;
  const sh = (type, src) => { const s = gl.createShader(type); gl.shaderSource(s, src); gl.compileShader(s); return s; };
  const prog = gl.createProgram();
  gl.attachShader(prog, sh(gl.VERTEX_SHADER, vs));
  gl.attachShader(prog, sh(gl.FRAGMENT_SHADER, fs));
  gl.linkProgram(prog);
  gl.useProgram(prog);
  const loc = { p: gl.getAttribLocation(prog, 'p'), n: gl.getAttribLocation(prog, 'n'), m: gl.getUniformLocation(prog, 'm'), c: gl.getUniformLocation(prog, 'c'), lit: gl.getUniformLocation(prog, 'lit') };
  const pbuf = gl.createBuffer(), nbuf = gl.createBuffer(), ibuf = gl.createBuffer();

  // World z-up to the screen: turn by yaw about z, tilt by pitch, then x right and z up.
  function matrix(s) {
    const cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
    const a = canvas.height / canvas.width;
    // Rows: screen x, screen y, depth.
    const X = [cy, -sy, 0], Y = [sp * sy, sp * cy, cp], Z = [cp * sy, cp * cy, -sp];
    return new Float32Array([
      X[0] * s * a, Y[0] * s, -Z[0] * s * 0.5, 0,
      X[1] * s * a, Y[1] * s, -Z[1] * s * 0.5, 0,
      X[2] * s * a, Y[2] * s, -Z[2] * s * 0.5, 0,
      0, -0.6, 0, 1,
    ]);
  }

  function hexRgb(h) { return [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16) / 255); }

  function drawArrays(mode, pos, colour, lit, normals, indices) {
    gl.bindBuffer(gl.ARRAY_BUFFER, pbuf);
    gl.bufferData(gl.ARRAY_BUFFER, pos, gl.DYNAMIC_DRAW);
    gl.enableVertexAttribArray(loc.p);
    gl.vertexAttribPointer(loc.p, 3, gl.FLOAT, false, 0, 0);
    gl.bindBuffer(gl.ARRAY_BUFFER, nbuf);
    gl.bufferData(gl.ARRAY_BUFFER, normals || new Float32Array(pos.length), gl.DYNAMIC_DRAW);
    gl.enableVertexAttribArray(loc.n);
    gl.vertexAttribPointer(loc.n, 3, gl.FLOAT, false, 0, 0);
    gl.uniform4fv(loc.c, colour);
    gl.uniform1f(loc.lit, lit);
    if (indices) {
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ibuf);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, indices, gl.DYNAMIC_DRAW);
      gl.drawElements(mode, indices.length, gl.UNSIGNED_SHORT, 0);
    } else {
      gl.drawArrays(mode, 0, pos.length / 3);
    }
  }

  function surface(m, state, vmax) {
    const { rows, cols, rho } = m.lobe;
    const pos = new Float32Array((rows + 1) * cols * 3);
    for (let i = 0; i <= rows; i++) {
      const t = (Math.min(89.5, (i * 90) / rows) * Math.PI) / 180;
      for (let j = 0; j < cols; j++) {
        const p = (j * 2 * Math.PI) / cols, k = i * cols + j;
        let v = rho[k] || 0;
        if (state.quantity === 'intensity') v *= Math.cos(t);
        let r = v / vmax;
        if (state.log) r = v > 0 ? Math.max(0, 1 + Math.log10(v / vmax) / 4) : 0;
        pos.set([r * Math.sin(t) * Math.cos(p), r * Math.sin(t) * Math.sin(p), r * Math.cos(t)], k * 3);
      }
    }
    const idx = [];
    for (let i = 0; i < rows; i++) for (let j = 0; j < cols; j++) {
      const a = i * cols + j, b = i * cols + ((j + 1) % cols), c = a + cols, d = b + cols;
      idx.push(a, c, b, b, c, d);
    }
    const nrm = new Float32Array(pos.length);
    for (let k = 0; k < idx.length; k += 3) {
      const [a, b, c] = [idx[k] * 3, idx[k + 1] * 3, idx[k + 2] * 3];
      const u = [pos[b] - pos[a], pos[b + 1] - pos[a + 1], pos[b + 2] - pos[a + 2]];
      const w = [pos[c] - pos[a], pos[c + 1] - pos[a + 1], pos[c + 2] - pos[a + 2]];
      const n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
      for (const v of [a, b, c]) { nrm[v] += n[0]; nrm[v + 1] += n[1]; nrm[v + 2] += n[2]; }
    }
    return { pos, nrm, idx: new Uint16Array(idx) };
  }

  function draw(models, state) {
    last = { models, state };
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    gl.uniformMatrix4fv(loc.m, false, matrix(1.1));
    let vmax = 0;
    for (const m of models) if (m.lobe) m.lobe.rho.forEach((v, k) => {
      const t = (Math.min(89.5, (Math.floor(k / m.lobe.cols) * 90) / m.lobe.rows) * Math.PI) / 180;
      const x = (v || 0) * (state.quantity === 'intensity' ? Math.cos(t) : 1);
      if (x > vmax && isFinite(x)) vmax = x;
    });
    vmax = vmax > 0 ? vmax : 1;
    // The surface: a circle of radius 1, and the x axis.
    const circle = [];
    for (let k = 0; k <= 64; k++) { const p = (k / 64) * 2 * Math.PI; circle.push(Math.cos(p), Math.sin(p), 0); }
    drawArrays(gl.LINE_STRIP, new Float32Array(circle), [0.6, 0.6, 0.6, 1], 0);
    const t = (state.ti * Math.PI) / 180, p = (state.pi * Math.PI) / 180;
    const wi = [-Math.sin(t) * Math.cos(p), -Math.sin(t) * Math.sin(p), Math.cos(t)];
    drawArrays(gl.LINES, new Float32Array([0, 0, 0, wi[0] * 1.2, wi[1] * 1.2, wi[2] * 1.2]), [0.1, 0.1, 0.1, 1], 0);
    drawArrays(gl.LINES, new Float32Array([0, 0, 0, -wi[0] * 1.2, -wi[1] * 1.2, wi[2] * 1.2, -1, 0, 0, 1, 0, 0]), [0.55, 0.55, 0.55, 1], 0);
    // Translucent and without depth writes, so a lobe inside another still shows.
    gl.depthMask(false);
    for (const m of models) {
      if (!m.lobe) continue;
      const s = surface(m, state, vmax);
      drawArrays(gl.TRIANGLES, s.pos, [...hexRgb(m.colour), 0.55], 1, s.nrm, s.idx);
    }
    gl.depthMask(true);
  }

  let down = null;
  canvas.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener('pointerup', () => { down = null; });
  canvas.addEventListener('pointermove', (e) => {
    if (!down) return;
    yaw += (e.clientX - down[0]) * 0.01;
    pitch = Math.max(-0.2, Math.min(1.5, pitch + (e.clientY - down[1]) * 0.01));
    down = [e.clientX, e.clientY];
    if (last.state) draw(last.models, last.state);
  });
  return { draw };
})();
