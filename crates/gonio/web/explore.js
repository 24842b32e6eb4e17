// gonio explore: the page. Every number comes from the server's /api (the brdf crate); this
// file only draws. The model panel is generated from /api/models (the registry's ParamSpecs).
'use strict';

const $ = (id) => document.getElementById(id);
const COLOURS = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#8c564b', '#e377c2'];
// Measured in the page, read by the browser test: input-to-drawn latency of the 2D plots, time
// to the first lit frame, and per view group the last request and drawing times.
const stats = { plotLatencies: [], plotParts: [], litFirstFrame: [], errors: [], timing: {} };
window.gonioStats = stats;

let registry = [];            // /api/models
let files = { measured: [], meshes: [], probes: [] };
const state = {
  models: [],                 // {name, given: {param: text}, visible, solo, colour}
  active: 0,
  ti: 45, pi: 0, phid: 90, channel: 'luminance', quantity: 'intensity', log: false,
  object: 'suzanne', probe: 'studio', env: 1, point: true, light: [0.6, 0.7, 0.6], irr: 3,
  fitted: null,               // {measured: item, fitted: item}
};

// ---------- models and URL state ----------
const spec = (name) => registry.find((m) => m.name === name);
const defaultText = (p) => Array.isArray(p.default) ? p.default.join(',') : String(p.default);

function item(m) {
  let s = m.name;
  for (const [k, v] of Object.entries(m.given)) s += ':' + k + '=' + v;
  return s;
}

function parseItem(text) {
  const [name, ...rest] = text.split(':');
  const given = {};
  for (const kv of rest) {
    const i = kv.indexOf('=');
    if (i > 0) given[kv.slice(0, i)] = kv.slice(i + 1);
  }
  return { name, given };
}

function shown() {
  const solo = state.models.filter((m) => m.solo);
  return (solo.length ? solo : state.models.filter((m) => m.visible));
}

function activeModel() { return state.models[state.active] || state.models[0]; }

// The address follows the state at most every 200 ms: browsers refuse more than about ten
// history updates a second, and a dragged slider changes the state at 60 Hz.
let urlTimer = 0;
function writeUrl() {
  if (!urlTimer) urlTimer = setTimeout(writeUrlNow, 200);
}

function writeUrlNow() {
  urlTimer = 0;
  const u = new URLSearchParams();
  for (const m of state.models) u.append('m', item(m) + (m.visible ? '' : '!hidden') + (m.solo ? '!solo' : ''));
  for (const k of ['active', 'ti', 'pi', 'phid', 'channel', 'quantity', 'object', 'probe', 'env', 'irr']) u.set(k, state[k]);
  u.set('log', state.log ? 1 : 0);
  u.set('point', state.point ? 1 : 0);
  u.set('light', state.light.map((v) => v.toFixed(4)).join(','));
  history.replaceState(null, '', '#' + u.toString());
}

function readUrl() {
  const u = new URLSearchParams(location.hash.slice(1));
  const ms = u.getAll('m');
  state.models = [];
  for (let text of ms) {
    const solo = text.endsWith('!solo');
    if (solo) text = text.slice(0, -5);
    const hidden = text.endsWith('!hidden');
    const m = parseItem(hidden ? text.slice(0, -7) : text);
    if (spec(m.name)) {
      addModel(m.name, m.given, !hidden, false);
      state.models[state.models.length - 1].solo = solo;
    }
  }
  if (!state.models.length) addModel('ggx', {}, true, false);
  for (const k of ['ti', 'pi', 'phid', 'env', 'irr', 'active']) if (u.has(k) && isFinite(+u.get(k))) state[k] = +u.get(k);
  for (const k of ['channel', 'quantity', 'object', 'probe']) if (u.has(k)) state[k] = u.get(k);
  if (u.has('log')) state.log = u.get('log') === '1';
  if (u.has('point')) state.point = u.get('point') === '1';
  if (u.has('light')) {
    const l = u.get('light').split(',').map(Number);
    if (l.length === 3 && l.every(isFinite)) state.light = l;
  }
  const clamp = (v, lo, hi) => Math.min(hi, Math.max(lo, v));
  state.ti = clamp(state.ti, 0, 89); state.pi = clamp(state.pi, -180, 180); state.phid = clamp(state.phid, 0, 180);
  state.env = clamp(state.env, 0, 2); state.irr = clamp(state.irr, 0, 10);
  state.active = clamp(state.active | 0, 0, state.models.length - 1);
}

function addModel(name, given, visible, select) {
  const used = new Set(state.models.map((m) => m.colour));
  const colour = COLOURS.find((c) => !used.has(c)) || COLOURS[state.models.length % COLOURS.length];
  state.models.push({ name, given: { ...given }, visible, solo: false, colour });
  if (select) state.active = state.models.length - 1;
}

// ---------- the model panel, generated from the ParamSpecs ----------
function hexOf(rgb) {
  return '#' + rgb.map((v) => Math.round(Math.min(1, Math.max(0, v)) * 255).toString(16).padStart(2, '0')).join('');
}

function paramControl(m, p) {
  const row = document.createElement('div');
  row.className = 'p';
  row.title = p.doc + ' — ' + p.range;
  const label = document.createElement('span');
  label.textContent = p.name;
  row.append(label);
  const cur = m.given[p.name] ?? defaultText(p);
  const set = (text) => {
    if (text === defaultText(p)) delete m.given[p.name]; else m.given[p.name] = text;
    changed('params');
  };
  if (p.kind === 'float') {
    const r = document.createElement('input');
    r.type = 'range';
    r.dataset.param = p.name;
    const log = p.min > 0 && p.max / p.min >= 100;
    const lo = log ? Math.log10(p.min) : p.min, hi = log ? Math.log10(p.max) : Math.min(p.max, 1e4);
    r.min = lo; r.max = hi; r.step = (hi - lo) / 1000;
    const num = document.createElement('input');
    num.className = 'num';
    num.value = cur;
    const toSlider = (v) => { const x = parseFloat(v); if (isFinite(x)) r.value = log ? Math.log10(Math.max(x, p.min)) : x; };
    toSlider(cur);
    r.addEventListener('input', () => {
      const v = log ? 10 ** +r.value : +r.value;
      const text = String(+v.toPrecision(4));
      num.value = text;
      set(text);
    });
    num.addEventListener('change', () => { toSlider(num.value); set(num.value.trim()); });
    row.append(r, num);
    if (p.names) {
      const sel = document.createElement('select');
      sel.append(new Option('named…', ''));
      for (const n of Object.keys(p.names)) sel.append(new Option(n, n));
      sel.addEventListener('change', () => { if (sel.value) { num.value = sel.value; toSlider(p.names[sel.value]); set(sel.value); } });
      const wrap = document.createElement('div');
      wrap.className = 'p wide';
      wrap.append(document.createElement('span'), sel);
      return [row, wrap];
    }
  } else if (p.kind === 'rgb') {
    const txt = document.createElement('input');
    txt.className = 'txt';
    txt.value = cur;
    txt.dataset.param = p.name;
    const parts = () => { const v = txt.value.split(',').map(Number); return v.length === 1 ? [v[0], v[0], v[0]] : v; };
    if (p.max <= 1) {
      const c = document.createElement('input');
      c.type = 'color';
      c.value = hexOf(parts());
      c.addEventListener('input', () => {
        const v = [1, 3, 5].map((i) => +(parseInt(c.value.slice(i, i + 2), 16) / 255).toFixed(4));
        txt.value = v[0] === v[1] && v[1] === v[2] ? String(v[0]) : v.join(',');
        set(txt.value);
      });
      row.append(c);
    } else {
      row.append(document.createElement('span'));
    }
    txt.addEventListener('change', () => set(txt.value.trim()));
    row.append(txt);
  } else if (p.kind === 'choice') {
    const sel = document.createElement('select');
    sel.dataset.param = p.name;
    for (const o of p.options) sel.append(new Option(o, o));
    sel.value = cur;
    sel.addEventListener('change', () => set(sel.value));
    row.className = 'p wide';
    row.append(sel);
  } else if (p.kind === 'bool') {
    const b = document.createElement('input');
    b.type = 'checkbox';
    b.checked = cur === 'true';
    b.addEventListener('change', () => set(String(b.checked)));
    row.className = 'p wide';
    row.append(b);
  } else {
    // path or nested model: typed as on the command line.
    const t = document.createElement('input');
    t.value = cur;
    t.dataset.param = p.name;
    t.addEventListener('change', () => set(t.value.trim()));
    row.className = 'p wide';
    row.append(t);
  }
  return [row];
}

function renderPanel() {
  const box = $('models');
  box.textContent = '';
  state.models.forEach((m, i) => {
    const s = spec(m.name);
    const card = document.createElement('div');
    card.className = 'card' + (i === state.active ? ' active' : '');
    card.style.borderLeftColor = m.colour;
    card.dataset.model = m.name;
    const head = document.createElement('div');
    head.className = 'head';
    const b = document.createElement('b');
    b.textContent = m.name;
    b.title = s.summary + ' — ' + s.reference;
    const vis = document.createElement('input');
    vis.type = 'checkbox';
    vis.checked = m.visible;
    vis.title = 'visible';
    vis.addEventListener('click', (e) => { e.stopPropagation(); m.visible = vis.checked; changed('visibility'); });
    const solo = document.createElement('button');
    solo.textContent = m.solo ? 'unsolo' : 'solo';
    solo.addEventListener('click', (e) => { e.stopPropagation(); m.solo = !m.solo; renderPanel(); changed('visibility'); });
    const del = document.createElement('button');
    del.textContent = '×';
    del.title = 'remove';
    del.disabled = state.models.length === 1;
    del.addEventListener('click', (e) => {
      e.stopPropagation();
      state.models.splice(i, 1);
      state.active = Math.min(state.active, state.models.length - 1);
      renderPanel();
      changed('params');
    });
    head.append(vis, b, solo, del);
    head.addEventListener('click', () => { if (state.active !== i) { state.active = i; renderPanel(); changed('active'); } });
    card.append(head);
    if (i === state.active) for (const p of s.params) card.append(...paramControl(m, p));
    const err = document.createElement('div');
    err.className = 'err small';
    err.id = 'err-' + i;
    card.append(err);
    box.append(card);
  });
}

// ---------- requests ----------
function query(extra) {
  const u = new URLSearchParams({ ti: state.ti, pi: state.pi, phid: state.phid, channel: state.channel });
  for (const [k, v] of Object.entries(extra || {})) {
    if (Array.isArray(v)) for (const x of v) u.append(k, x); else u.set(k, v);
  }
  return u.toString();
}

async function api(path, extra, opts) {
  const r = await fetch('/api/' + path + '?' + query(extra), opts);
  const body = await r.json();
  if (!r.ok) {
    const e = new Error(body.error || r.statusText);
    e.body = body;
    throw e;
  }
  return body;
}

function showError(e) {
  if (e.name === 'AbortError') return;
  const i = state.models.findIndex((m) => e.item && item(m) === e.item);
  const el = i >= 0 ? $('err-' + i) : null;
  if (el) el.textContent = e.message; else $('data-msg').textContent = e.message;
}

function clearErrors() { document.querySelectorAll('.card .err').forEach((e) => { e.textContent = ''; }); }

// Coalesces requests: one in flight per group; a newer state waits and goes next.
function group(run) {
  let busy = false, again = false;
  const go = async () => {
    if (busy) { again = true; return; }
    busy = true;
    do { again = false; await run(); } while (again);
    busy = false;
  };
  return go;
}

let version = 0;
let pending = [];             // [version, t0] of inputs not yet drawn
let views = null;             // the last /api/views answer, models in shown() order

// Albedo samples per point: few while the knobs move (the band shows the noise), many once idle.
const ALBEDO_QUICK = 128, ALBEDO_FINE = 4096;
let albedoTimer = 0;

// One request per change for every 2D view (and the 3D lobe): one round trip, not five.
async function fetchPlots() {
  const v = version;
  const ms = shown();
  if (ms.length) {
    try {
      const t0 = performance.now();
      const res = await api('views', { m: ms.map(item), active: Math.max(0, ms.indexOf(activeModel())), samples: ALBEDO_QUICK });
      stats.timing = { start: t0, request: performance.now() - t0 };
      res.models.forEach((r, i) => { r.colour = ms[i].colour; });
      views = res;
      clearErrors();
    } catch (e) {
      // Name the model at fault: ask for each alone.
      for (const m of ms) {
        try { await api('views', { parts: 'polar', m: item(m) }); } catch (e2) { e2.item = item(m); showError(e2); }
      }
    }
  } else {
    views = { models: [] };
  }
  const t1 = performance.now();
  draw2d();
  stats.timing.draw = performance.now() - t1;
  const now = performance.now();
  pending = pending.filter(([pv, t0]) => {
    if (pv <= v) {
      stats.plotLatencies.push(now - t0);
      stats.plotParts.push({ total: now - t0, request: stats.timing.request, draw: stats.timing.draw });
      return false;
    }
    return true;
  });
  // The 3D lobe, the lit render and the finer albedo wait for the 2D plots, so a slider move's
  // plots get the cores first.
  // (The 3D lobe also follows a long drag, at most every LOBE_EVERY_MS.)
  if (!pending.length || now - lobeDrawn >= LOBE_EVERY_MS) {
    lobeDrawn = now;
    if (window.Lobe3d) window.Lobe3d.draw(views.models, state);
  }
  if (!pending.length) {
    if (litDirty) setTimeout(litWhenStill, LIT_STILL_MS);
    clearTimeout(albedoTimer);
    albedoTimer = setTimeout(() => refineAlbedo(v), 300);
  }
}

async function refineAlbedo(v) {
  const ms = shown();
  if (v !== version || !ms.length) return;
  try {
    const res = await api('views', { parts: 'albedo', m: ms.map(item), samples: ALBEDO_FINE });
    if (v !== version) return;
    res.models.forEach((r, i) => { if (views.models[i]) views.models[i].albedo = r.albedo; });
    drawAlbedo();
  } catch (e) { showError(e); }
}

const LOBE_EVERY_MS = 100;
let lobeDrawn = 0;

// A parameter change restarts the lit views once the knobs have been still this long, so the
// frames do not compete with the plots of a slider being dragged (a light drag restarts at once).
const LIT_STILL_MS = 120;
let litDirty = false, lastChange = 0;
function litWhenStill() {
  if (!litDirty || pending.length) return;
  const wait = LIT_STILL_MS - (performance.now() - lastChange);
  if (wait > 1) { setTimeout(litWhenStill, wait); return; }
  litDirty = false;
  startLit();
}

const refreshPlots = group(fetchPlots);

// What a change touches: 'params' and 'active' (a model) everything; 'direction' the plots,
// checks and read-out; 'view' and 'visibility' the plots; 'light' only the lit views.
function changed(what) {
  lastChange = performance.now();
  writeUrl();
  syncControls();
  refreshCommands();
  if (what === 'light') { startLit(); return; }
  version += 1;
  pending.push([version, performance.now()]);
  refreshPlots();
  if ((what === 'params' || what === 'active') && litKeyNow() !== litKey) {
    // The old parameters' render stops now; the new one starts once the plots are drawn.
    stopLit();
    litDirty = true;
  }
  if (what === 'params' || what === 'active' || what === 'direction') { scheduleCheck(); readoutDefault(); }
}

// ---------- drawing helpers ----------
function ctx2d(id) {
  const c = $(id);
  const g = c.getContext('2d');
  g.clearRect(0, 0, c.width, c.height);
  g.font = '11px system-ui, sans-serif';
  return [c, g];
}

function niceMax(v) {
  if (!(v > 0) || !isFinite(v)) return 1;
  const e = 10 ** Math.floor(Math.log10(v));
  for (const m of [1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10]) if (m * e >= v) return m * e;
  return 10 * e;
}

function fmt(v) { return Math.abs(v) >= 1e4 || (v !== 0 && Math.abs(v) < 1e-3) ? v.toExponential(2) : String(+v.toPrecision(4)); }

function axes(g, box, xmax, ymax, xlabel, ylabel) {
  const [x0, y0, x1, y1] = box;
  g.strokeStyle = '#000'; g.lineWidth = 1; g.fillStyle = '#000';
  g.beginPath(); g.moveTo(x0, y0); g.lineTo(x0, y1); g.lineTo(x1, y1); g.stroke();
  g.textAlign = 'center';
  for (let t = 0; t <= xmax; t += 15) {
    const x = x0 + (t / xmax) * (x1 - x0);
    g.beginPath(); g.moveTo(x, y1); g.lineTo(x, y1 + 4); g.stroke();
    g.fillText(t + '°', x, y1 + 15);
  }
  g.fillText(xlabel, (x0 + x1) / 2, y1 + 28);
  g.textAlign = 'right';
  for (let k = 0; k <= 4; k++) {
    const v = (ymax * k) / 4, y = y1 - (k / 4) * (y1 - y0);
    g.beginPath(); g.moveTo(x0 - 4, y); g.lineTo(x0, y); g.stroke();
    g.fillText(fmt(v), x0 - 6, y + 4);
  }
  g.save(); g.translate(12, (y0 + y1) / 2); g.rotate(-Math.PI / 2); g.textAlign = 'center'; g.fillText(ylabel, 0, 0); g.restore();
}

function polyline(g, pts, colour, dash, width) {
  g.strokeStyle = colour; g.lineWidth = width || 2; g.setLineDash(dash || []);
  g.beginPath();
  let pen = false;
  for (const p of pts) {
    if (!p || !isFinite(p[0]) || !isFinite(p[1])) { pen = false; continue; }
    if (pen) g.lineTo(p[0], p[1]); else g.moveTo(p[0], p[1]);
    pen = true;
  }
  g.stroke(); g.setLineDash([]);
}

// ---------- polar lobe ----------
const polarGeom = { cx: 260, cy: 280, r: 240 };
let polarScale = { rmax: 1, log: false };

function polarValue(m, k) {
  const p = m.polar, rho = p.rho[k];
  if (rho === null) return null;
  const t = ((p.theta0 + k * p.step) * Math.PI) / 180;
  return state.quantity === 'intensity' ? rho * Math.max(0, Math.cos(t)) : rho;
}

function drawPolar() {
  const [c, g] = ctx2d('polar');
  const { cx, cy, r } = polarGeom;
  const ms = (views && views.models) || [];
  let vmax = 0;
  for (const m of ms) if (m.polar) for (let k = 0; k < m.polar.rho.length; k++) { const v = polarValue(m, k); if (v > vmax && isFinite(v)) vmax = v; }
  const rmax = niceMax(vmax);
  const DEC = 4;
  const radius = (v) => {
    if (!(v > 0)) return 0;
    if (state.log) return Math.max(0, 1 + Math.log10(v / rmax) / DEC) * r;
    return (v / rmax) * r;
  };
  polarScale = { rmax, log: state.log };
  g.strokeStyle = '#ccc'; g.lineWidth = 1;
  for (let k = 1; k <= 4; k++) { g.beginPath(); g.arc(cx, cy, (r * k) / 4, Math.PI, 2 * Math.PI); g.stroke(); }
  g.fillStyle = '#666'; g.textAlign = 'left';
  for (let k = 1; k <= 4; k++) g.fillText(state.log ? '1e' + (k - DEC) + '·max' : fmt((rmax * k) / 4), cx + (r * k) / 4 + 2, cy - 3);
  g.strokeStyle = '#000'; g.beginPath(); g.moveTo(cx - r - 10, cy); g.lineTo(cx + r + 10, cy); g.stroke();
  // The light and its mirror direction.
  const ti = (state.ti * Math.PI) / 180;
  g.setLineDash([]); g.strokeStyle = '#333'; g.lineWidth = 2;
  g.beginPath(); g.moveTo(cx, cy); g.lineTo(cx - Math.sin(ti) * r, cy - Math.cos(ti) * r); g.stroke();
  g.fillStyle = '#333'; g.fillText('light θi = ' + state.ti + '°', cx - Math.sin(ti) * r - 40, cy - Math.cos(ti) * r - 6);
  g.setLineDash([5, 4]); g.lineWidth = 1;
  g.beginPath(); g.moveTo(cx, cy); g.lineTo(cx + Math.sin(ti) * r, cy - Math.cos(ti) * r); g.stroke(); g.setLineDash([]);
  let ly = 14;
  for (const m of ms) {
    if (!m.polar) continue;
    const pts = m.polar.rho.map((_, k) => {
      const v = polarValue(m, k);
      if (v === null) return null;
      const t = ((m.polar.theta0 + k * m.polar.step) * Math.PI) / 180, rr = radius(v);
      return [cx + Math.sin(t) * rr, cy - Math.cos(t) * rr];
    });
    polyline(g, pts, m.colour);
    g.fillStyle = m.colour; g.textAlign = 'left';
    g.fillText(m.label + (m.has_delta ? ' (+ delta lobe, not drawn)' : ''), 6, ly); ly += 14;
  }
  g.fillStyle = '#666'; g.textAlign = 'right';
  g.fillText((state.quantity === 'intensity' ? 'ρ·cosθo' : 'ρ') + ', 1/sr, ' + state.channel + (state.log ? ', log (4 decades)' : ''), c.width - 4, 14);
}

// ---------- albedo ----------
function drawAlbedo() {
  const [c, g] = ctx2d('albedo');
  const box = [54, 12, c.width - 10, c.height - 36];
  const ms = (views && views.models) || [];
  let vmax = 1;
  for (const m of ms) if (m.albedo) for (const cur of [m.albedo.over_wi, m.albedo.over_wo]) for (const v of cur.mean) if (v > vmax && isFinite(v)) vmax = v;
  const ymax = niceMax(vmax * 1.05);
  axes(g, box, 90, ymax, 'θo (solid) or θi (dashed)', 'albedo');
  const X = (t) => box[0] + (t / 90) * (box[2] - box[0]), Y = (v) => box[3] - (v / ymax) * (box[3] - box[1]);
  g.strokeStyle = '#999'; g.setLineDash([2, 2]); g.beginPath(); g.moveTo(box[0], Y(1)); g.lineTo(box[2], Y(1)); g.stroke(); g.setLineDash([]);
  for (const m of ms) {
    if (!m.albedo) continue;
    for (const [cur, dash] of [[m.albedo.over_wi, []], [m.albedo.over_wo, [6, 4]]]) {
      g.fillStyle = m.colour + '30';
      g.beginPath();
      cur.theta.forEach((t, k) => g.lineTo(X(t), Y(cur.mean[k] + 2 * cur.se[k])));
      for (let k = cur.theta.length - 1; k >= 0; k--) g.lineTo(X(cur.theta[k]), Y(Math.max(0, cur.mean[k] - 2 * cur.se[k])));
      g.fill();
      polyline(g, cur.theta.map((t, k) => [X(t), Y(cur.mean[k])]), m.colour, dash);
    }
  }
}

// ---------- slice ----------
function magma(t) {
  const stops = [[0, 0, 4], [59, 15, 112], [140, 41, 129], [222, 73, 104], [254, 159, 109], [252, 253, 191]];
  t = Math.min(1, Math.max(0, t)) * (stops.length - 1);
  const k = Math.min(stops.length - 2, Math.floor(t)), f = t - k;
  return stops[k].map((v, i) => v * (1 - f) + stops[k + 1][i] * f);
}

function drawGrid(id, cells, values, colour, title) {
  const [c, g] = ctx2d(id);
  const img = g.createImageData(cells, cells);
  values.forEach((v, i) => {
    const rgb = v === null ? [235, 235, 235] : colour(v);
    img.data.set([rgb[0], rgb[1], rgb[2], 255], i * 4);
  });
  const tmp = document.createElement('canvas');
  tmp.width = cells; tmp.height = cells;
  tmp.getContext('2d').putImageData(img, 0, 0);
  g.imageSmoothingEnabled = false;
  g.drawImage(tmp, 30, 10, c.width - 40, c.height - 40);
  g.fillStyle = '#000'; g.textAlign = 'center';
  g.fillText('θh →  (0°–90°)', c.width / 2, c.height - 16);
  g.fillText(title, c.width / 2, c.height - 3);
  g.save(); g.translate(12, c.height / 2); g.rotate(-Math.PI / 2); g.fillText('θd →', 0, 0); g.restore();
}

function drawSlice() {
  const m = views && views.models.find((x) => x.slice);
  if (!m || !m.slice) { ctx2d('slice'); return; }
  const vals = m.slice.rho.filter((v) => v > 0);
  const vmax = Math.max(...vals, 1e-30);
  const sorted = vals.slice().sort((a, b) => a - b);
  const lo = Math.max(sorted[Math.floor(sorted.length * 0.05)] || vmax * 1e-4, vmax * 1e-8);
  const span = Math.max(Math.log10(vmax / lo), 1e-6);
  drawGrid('slice', m.slice.cells, m.slice.rho, (v) => magma(v > 0 ? 1 + Math.log10(v / vmax) / span : 0),
    m.label + ': log ρ, φd = ' + state.phid + '°');
}

async function drawResidual() {
  const c = $('residual');
  const f = state.fitted;
  c.hidden = !f;
  if (!f) return;
  try {
    const r = await api('residual', { m: f.measured, f: f.fitted });
    drawGrid('residual', r.cells, r.log10_ratio, (v) => {
      const t = Math.max(-1, Math.min(1, v));
      return t < 0 ? [255 * (1 + t), 255 * (1 + t), 255] : [255, 255 * (1 - t), 255 * (1 - t)];
    }, 'log10(measured / fitted): blue < 0 < red (±1)');
  } catch (e) { showError(e); }
}

// ---------- fresnel ----------
function drawFresnel() {
  const [c, g] = ctx2d('fresnel');
  const box = [54, 12, c.width - 10, c.height - 36];
  axes(g, box, 90, 1, 'incident angle θi', 'reflectance');
  const ms = ((views && views.models) || []).filter((m) => m.fresnel);
  const dash = { unpolarised: [], Rs: [7, 4], Rp: [2, 3], Schlick: [10, 3, 2, 3] };
  for (const m of ms) {
    for (const cur of m.fresnel.curves) {
      const pts = cur.values.map((v, k) => [box[0] + ((k * m.fresnel.step) / 90) * (box[2] - box[0]), box[3] - v * (box[3] - box[1])]);
      polyline(g, pts, m.colour, dash[cur.name], cur.name === 'unpolarised' ? 2.2 : 1.4);
    }
  }
  if (!ms.length) { g.fillStyle = '#666'; g.textAlign = 'center'; g.fillText('no shown model has a Fresnel interface', (box[0] + box[2]) / 2, (box[1] + box[3]) / 2); }
}

function draw2d() { drawPolar(); drawAlbedo(); drawFresnel(); drawSlice(); drawDir(); }

function drawAll() {
  draw2d();
  if (window.Lobe3d) window.Lobe3d.draw((views && views.models) || [], state);
}

// ---------- incident direction widget ----------
function drawDir() {
  const [c, g] = ctx2d('dir');
  const R = c.width / 2 - 8, cx = c.width / 2, cy = c.height / 2;
  g.strokeStyle = '#bbb';
  for (const t of [30, 60, 90]) { g.beginPath(); g.arc(cx, cy, R * Math.sin((t * Math.PI) / 180), 0, 2 * Math.PI); g.stroke(); }
  g.beginPath(); g.moveTo(cx - R, cy); g.lineTo(cx + R, cy); g.moveTo(cx, cy - R); g.lineTo(cx, cy + R); g.stroke();
  const w = wiVec();
  g.fillStyle = '#d62728';
  g.beginPath(); g.arc(cx + w[0] * R, cy - w[1] * R, 6, 0, 2 * Math.PI); g.fill();
  g.fillStyle = '#444'; g.fillText('x', cx + R - 6, cy - 4); g.fillText('y', cx + 4, cy - R + 10);
}

function wiVec() {
  const t = (state.ti * Math.PI) / 180, p = (state.pi * Math.PI) / 180;
  return [-Math.sin(t) * Math.cos(p), -Math.sin(t) * Math.sin(p), Math.cos(t)];
}

function dragDir(e) {
  const c = $('dir'), rect = c.getBoundingClientRect();
  const R = c.width / 2 - 8;
  const x = (e.clientX - rect.left - c.width / 2) / R, y = -(e.clientY - rect.top - c.height / 2) / R;
  const s = Math.min(Math.hypot(x, y), Math.sin((89 * Math.PI) / 180));
  state.ti = +((Math.asin(s) * 180) / Math.PI).toFixed(1);
  state.pi = Math.round((Math.atan2(-y, -x) * 180) / Math.PI);
  changed('direction');
}

function dragPolar(e) {
  const c = $('polar'), rect = c.getBoundingClientRect();
  const x = e.clientX - rect.left - polarGeom.cx, y = polarGeom.cy - (e.clientY - rect.top);
  if (x >= 0) return;
  state.ti = Math.min(89, Math.max(0, +((Math.atan2(-x, Math.max(y, 0)) * 180) / Math.PI).toFixed(1)));
  changed('direction');
}

// ---------- read-out ----------
const dirText = (w) => w.map((v) => (Math.abs(v) < 5e-7 ? 0 : +v.toFixed(6))).join(',');

async function readout(wo, where) {
  const wi = dirText(wiVec()), woT = dirText(wo);
  const lines = ['wi = ' + wi + '   wo = ' + woT + '   (' + where + ')'];
  const ms = shown();
  try {
    const r = await api('eval', { m: ms.map(item), wi, wo: woT });
    r.results.forEach((x, i) => lines.push(item(ms[i]) + '\n  ρ = ' + x.brdf.join(' ') + ' 1/sr   pdf = ' + x.pdf + ' 1/sr'));
  } catch (e) { lines.push(e.message); }
  $('readout').textContent = lines.join('\n');
  $('readout').dataset.wi = wi;
  $('readout').dataset.wo = woT;
}

function readoutDefault() {
  const w = wiVec();
  readoutSoon([-w[0], -w[1], w[2]], 'the mirror direction', LIT_STILL_MS);
}

let readoutTimer = 0;
function readoutSoon(wo, where, delay) {
  clearTimeout(readoutTimer);
  readoutTimer = setTimeout(() => readout(wo, where), delay || 30);
}

function hoverPolar(e) {
  const c = $('polar'), rect = c.getBoundingClientRect();
  const x = e.clientX - rect.left - polarGeom.cx, y = polarGeom.cy - (e.clientY - rect.top);
  if (y < 0) return;
  const t = Math.atan2(x, y), p = (state.pi * Math.PI) / 180;
  const wo = [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
  readoutSoon(wo, 'θo = ' + ((t * 180) / Math.PI).toFixed(1) + '° in the plane of incidence');
}

function hoverSlice(e) {
  const c = $('slice'), rect = c.getBoundingClientRect();
  const u = (e.clientX - rect.left - 30) / (c.width - 40), v = (e.clientY - rect.top - 10) / (c.height - 40);
  if (u < 0 || u > 1 || v < 0 || v > 1) return;
  const th = u * 90, td = (1 - v) * 90;
  // (wi, wo) from the half and difference angles, as the slice plot builds them.
  const r = (d) => (d * Math.PI) / 180, pd = r(state.phid);
  const d = [Math.sin(r(td)) * Math.cos(pd), Math.sin(r(td)) * Math.sin(pd), Math.cos(r(td))];
  const rot = (w) => [w[0] * Math.cos(r(th)) + w[2] * Math.sin(r(th)), w[1], -w[0] * Math.sin(r(th)) + w[2] * Math.cos(r(th))];
  const wi = rot(d), wo = rot([-d[0], -d[1], d[2]]);
  // The read-out's wi is the page's; show the slice point's pair instead.
  readoutPair(wi, wo, 'θh = ' + th.toFixed(1) + '°, θd = ' + td.toFixed(1) + '°');
}

async function readoutPair(wiV, woV, where) {
  clearTimeout(readoutTimer);
  readoutTimer = setTimeout(async () => {
    const wi = dirText(wiV), wo = dirText(woV);
    const m = activeModel();
    try {
      const r = (await api('eval', { m: item(m), wi, wo })).results[0];
      $('readout').textContent = 'wi = ' + wi + '   wo = ' + wo + '   (' + where + ')\n' + item(m) + '\n  ρ = ' + r.brdf.join(' ') + ' 1/sr   pdf = ' + r.pdf + ' 1/sr';
      $('readout').dataset.wi = wi; $('readout').dataset.wo = wo;
    } catch (e) { showError(e); }
  }, 60);
}

// ---------- checks ----------
let checkTimer = 0, checkAbort = null;
// The check of the selected model at the incident direction last asked for: another model's
// change does not check this one again.
let checkedKey = '';
function scheduleCheck() {
  const key = item(activeModel()) + '|' + state.ti + '|' + state.pi;
  if (key === checkedKey) return;
  checkedKey = key;
  clearTimeout(checkTimer);
  $('check-info').textContent = 'checking…';
  checkTimer = setTimeout(runCheck, 350);
}

async function runCheck() {
  if (checkAbort) checkAbort.abort();
  checkAbort = new AbortController();
  const m = activeModel();
  try {
    const r = await api('check', { m: item(m) }, { signal: checkAbort.signal });
    const t = $('findings');
    t.textContent = '';
    for (const f of r.findings) {
      const tr = t.insertRow();
      const mark = f.passed ? ['ok', '✓'] : f.claimed ? ['fail', '✗'] : ['no', '–'];
      tr.className = mark[0];
      tr.dataset.property = f.property;
      tr.insertCell().textContent = mark[1];
      tr.insertCell().textContent = f.property + (f.claimed ? '' : ' (not claimed)');
      tr.insertCell().textContent = f.detail;
    }
    const chi = r.chi2;
    $('chi-p').textContent = chi.delta_only ? 'delta lobe only: nothing to test'
      : 'p = ' + chi.p_value.toPrecision(3) + ' (χ² = ' + chi.statistic.toFixed(1) + ', ' + chi.dof + ' dof, ' + chi.samples + ' draws)' + (chi.note ? '; ' + chi.note : '');
    const vmax = Math.max(...chi.observed, ...chi.expected, 1e-30);
    for (const [id, vals] of [['chi-obs', chi.observed], ['chi-exp', chi.expected]]) heat(id, chi.rows, chi.cols, vals, vmax);
    drawCloud(r.cloud, chi);
    $('check-info').textContent = (r.ok ? 'every claimed property holds' : 'a claimed property FAILS') + ' · ' + r.seconds.toFixed(2) + ' s';
    $('check-info').className = r.ok ? 'msg' : 'msg err';
  } catch (e) {
    if (e.name !== 'AbortError') $('check-info').textContent = e.message;
  }
}

function heat(id, rows, cols, vals, vmax) {
  const [c, g] = ctx2d(id);
  const w = c.width / cols, h = c.height / rows;
  for (let i = 0; i < rows; i++) for (let j = 0; j < cols; j++) {
    const rgb = magma(vals[i * cols + j] / vmax);
    g.fillStyle = 'rgb(' + rgb.map(Math.round).join(',') + ')';
    // cos θ rises by row: the pole at the top.
    g.fillRect(j * w, c.height - (i + 1) * h, w + 0.5, h + 0.5);
  }
}

function drawCloud(cloud, chi) {
  const [c, g] = ctx2d('cloud');
  const R = c.width / 2 - 4, cx = c.width / 2, cy = c.height / 2;
  // The expected density as the background, in the disk x = sinθ cosφ, y = sinθ sinφ.
  const vmax = Math.max(...chi.expected, 1e-30);
  const img = g.createImageData(c.width, c.height);
  for (let py = 0; py < c.height; py++) for (let px = 0; px < c.width; px++) {
    const x = (px - cx) / R, y = -(py - cy) / R, s2 = x * x + y * y;
    if (s2 >= 1) continue;
    const cos = Math.sqrt(1 - s2);
    let phi = Math.atan2(y, x); if (phi < 0) phi += 2 * Math.PI;
    const i = Math.min(chi.rows - 1, Math.floor(cos * chi.rows)), j = Math.min(chi.cols - 1, Math.floor((phi / (2 * Math.PI)) * chi.cols));
    const rgb = magma(0.15 + 0.85 * (chi.expected[i * chi.cols + j] / vmax));
    img.data.set([rgb[0], rgb[1], rgb[2], 255], (py * c.width + px) * 4);
  }
  g.putImageData(img, 0, 0);
  g.fillStyle = '#7fffd4';
  for (const w of cloud) g.fillRect(cx + w[0] * R - 1, cy - w[1] * R - 1, 2, 2);
}

// ---------- lit sphere and object ----------
let litAbort = null;

// Names this page's lit renders to the server: a new sphere render (`P/lit`) stops both old
// ones, a new object render (`P/lit/object`) the old object render.
const PAGE_ID = Math.random().toString(36).slice(2);

function litQuery(object) {
  const q = { m: item(activeModel()), object, probe: state.probe, env: state.env, size: 256, spp: 512 };
  if (state.point) { q.light = state.light.map((v) => v.toFixed(4)).join(','); q.irradiance = state.irr; }
  return q;
}

async function streamInto(canvasId, q, signal, onFirst) {
  const t0 = performance.now();
  const r = await fetch('/api/render?' + query(q), { signal });
  if (!r.ok) { const b = await r.json(); throw new Error(b.error); }
  const reader = r.body.getReader();
  const g = $(canvasId).getContext('2d');
  // Frames are copied into one buffer of a frame's size as the bytes arrive.
  const head = new Uint8Array(16);
  let frame = null, filled = 0, first = true, w = 0, h = 0, spp = 0;
  for (;;) {
    const { value, done } = await reader.read();
    if (done) return;
    let at = 0;
    while (at < value.length) {
      if (!frame) {
        const take = Math.min(16 - filled, value.length - at);
        head.set(value.subarray(at, at + take), filled);
        filled += take; at += take;
        if (filled < 16) break;
        const dv = new DataView(head.buffer);
        w = dv.getUint32(4, true); h = dv.getUint32(8, true); spp = dv.getUint32(12, true);
        frame = new Uint8ClampedArray(w * h * 4);
        filled = 0;
        continue;
      }
      const take = Math.min(frame.length - filled, value.length - at);
      frame.set(value.subarray(at, at + take), filled);
      filled += take; at += take;
      if (filled === frame.length) {
        g.putImageData(new ImageData(frame, w, h), 0, 0);
        $(canvasId).dataset.spp = spp;
        if (first) { first = false; onFirst(performance.now() - t0); }
        $('lit-info').textContent = canvasId + ': ' + spp + ' spp';
        frame = null; filled = 0;
      }
    }
  }
}

// Stops both lit views' renders on the server at once (closing the stream alone would stop
// them only after their current pass).
function stopLit() {
  if (!litAbort) return;
  litAbort.abort();
  litAbort = null;
  fetch('/api/stop?stream=' + PAGE_ID + '/lit', { method: 'POST' }).catch(() => {});
}

// What the lit views show; a change elsewhere (another model) leaves them rendering.
const litKeyNow = () => JSON.stringify([litQuery('sphere'), state.object]);
let litKey = '';

function startLit() {
  litKey = litKeyNow();
  if (litAbort) litAbort.abort();
  litAbort = new AbortController();
  const signal = litAbort.signal;
  const fail = (e) => { if (e.name !== 'AbortError') $('lit-info').textContent = e.message; };
  streamInto('sphere', { ...litQuery('sphere'), stream: PAGE_ID + '/lit' }, signal, (ms) => {
    stats.litFirstFrame.push(ms);
    // The object starts once the sphere shows, so the first frame has both cores.
    streamInto('object-view', { ...litQuery(state.object), stream: PAGE_ID + '/lit/object' }, signal, () => {}).catch(fail);
  }).catch(fail);
}

function dragLight(e) {
  const c = $('sphere'), rect = c.getBoundingClientRect();
  const x = ((e.clientX - rect.left) / rect.width) * 2 - 1, y = 1 - ((e.clientY - rect.top) / rect.height) * 2;
  const s = Math.min(1, Math.hypot(x, y));
  const z = Math.sqrt(Math.max(0, 1 - s * s));
  state.light = [x, y, z + 0.05];
  state.point = true;
  changed('light');
}

// ---------- commands ----------
let commandTimer = 0;
function refreshCommands() {
  clearTimeout(commandTimer);
  commandTimer = setTimeout(async () => {
    const w = wiVec();
    const q = litQuery(state.object);
    Object.assign(q, { m: item(activeModel()), quantity: state.quantity, wi: dirText(w), wo: dirText([-w[0], -w[1], w[2]]), samples: ALBEDO_FINE });
    try {
      const r = await api('command', q);
      $('commands').textContent = [r.eval, ...Object.values(r.plot), r.render, '', r.mitsuba].join('\n');
    } catch (e) { $('commands').textContent = e.message; }
  }, 250);
}

// ---------- measured data ----------
async function openItem(kindItem) {
  $('data-msg').textContent = '';
  try {
    await api('views', { parts: 'polar', m: kindItem });
    const m = parseItem(kindItem);
    addModel(m.name, m.given, true, true);
    renderPanel();
    changed('params');
    $('data-msg').textContent = 'opened ' + m.given.filename;
  } catch (e) { $('data-msg').textContent = e.message; $('data-msg').className = 'msg err'; }
}

const measuredItem = (name) => (/\.binary$/i.test(name) ? 'merl' : 'tabulated') + ':filename=' + name;

async function upload(input, then) {
  const f = input.files[0];
  if (!f) return;
  try {
    const r = await fetch('/api/upload?name=' + encodeURIComponent(f.name), { method: 'POST', body: f });
    const b = await r.json();
    if (!r.ok) throw new Error(b.error);
    then(b);
  } catch (e) { $('data-msg').textContent = e.message; $('data-msg').className = 'msg err'; }
  input.value = '';
}

async function runFit() {
  const m = activeModel();
  $('fit-msg').textContent = 'fitting…';
  try {
    const r = await api('fit', { m: item(m), model: $('fit-model').value });
    const f = parseItem(r.item);
    addModel(f.name, f.given, true, false);
    state.fitted = { measured: item(m), fitted: r.item };
    $('fit-msg').textContent = r.options + ' · error ' + r.relative_error.toPrecision(3) + ' · ' + r.seconds.toFixed(2) + ' s' + (r.note ? ' · ' + r.note : '');
    renderPanel();
    changed('params');
    drawResidual();
  } catch (e) { $('fit-msg').textContent = e.message; }
}

// ---------- controls ----------
function syncControls() {
  $('ti').value = state.ti; $('ti-v').textContent = state.ti;
  $('pi').value = state.pi; $('pi-v').textContent = state.pi;
  $('phid').value = state.phid; $('phid-v').textContent = state.phid;
  $('channel').value = state.channel; $('quantity').value = state.quantity; $('log').checked = state.log;
  $('env').value = state.env; $('irr').value = state.irr; $('point').checked = state.point;
  $('object').value = state.object; $('probe').value = state.probe;
  const measured = (activeModel() && /^(merl|tabulated)$/.test(activeModel().name));
  $('fit').disabled = !measured;
  $('fit-row').title = measured ? '' : 'select a measured model (merl or tabulated) to fit';
}

function bind() {
  const num = (id, key, what) => $(id).addEventListener('input', () => { state[key] = +$(id).value; changed(what); });
  num('ti', 'ti', 'direction'); num('pi', 'pi', 'direction'); num('phid', 'phid', 'view');
  num('env', 'env', 'light'); num('irr', 'irr', 'light');
  $('channel').addEventListener('change', () => { state.channel = $('channel').value; changed('view'); });
  $('quantity').addEventListener('change', () => { state.quantity = $('quantity').value; writeUrl(); drawAll(); refreshCommands(); });
  $('log').addEventListener('change', () => { state.log = $('log').checked; writeUrl(); drawAll(); });
  $('point').addEventListener('change', () => { state.point = $('point').checked; changed('light'); });
  $('object').addEventListener('change', () => { state.object = $('object').value; changed('light'); });
  $('probe').addEventListener('change', () => { state.probe = $('probe').value; changed('light'); });
  $('add').addEventListener('click', () => { addModel($('add-model').value, {}, true, true); renderPanel(); changed('params'); });
  $('open-file').addEventListener('click', () => { if ($('data-file').value) openItem(measuredItem($('data-file').value)); });
  $('open-path').addEventListener('click', () => { const p = $('data-path').value.trim(); if (p) openItem(measuredItem(p)); });
  $('upload').addEventListener('change', () => upload($('upload'), (b) => openItem(b.item)));
  $('upload-mesh').addEventListener('change', () => upload($('upload-mesh'), (b) => {
    $('object').append(new Option(b.name.split('/').pop() + ' (uploaded)', b.name));
    state.object = b.name;
    changed('light');
  }));
  $('fit').addEventListener('click', runFit);
  $('copy-commands').addEventListener('click', () => navigator.clipboard && navigator.clipboard.writeText($('commands').textContent).catch(() => {}));
  $('copy-link').addEventListener('click', () => { writeUrlNow(); if (navigator.clipboard) navigator.clipboard.writeText(location.href).catch(() => {}); });
  const drag = (id, fn) => {
    const c = $(id);
    let down = false;
    c.addEventListener('pointerdown', (e) => { down = true; c.setPointerCapture(e.pointerId); fn(e); });
    c.addEventListener('pointermove', (e) => { if (down) fn(e); });
    c.addEventListener('pointerup', () => { down = false; });
  };
  drag('dir', dragDir);
  drag('sphere', dragLight);
  drag('polar', dragPolar);
  $('polar').addEventListener('mousemove', (e) => { if (!e.buttons) hoverPolar(e); });
  $('slice').addEventListener('mousemove', hoverSlice);
}

async function start() {
  window.addEventListener('error', (e) => stats.errors.push(String(e.message)));
  registry = await (await fetch('/api/models')).json();
  files = await (await fetch('/api/files')).json();
  for (const m of registry) $('add-model').append(new Option(m.name + ' — ' + m.summary.slice(0, 50), m.name));
  $('add-model').value = 'phong';
  for (const f of files.measured) $('data-file').append(new Option(f, f));
  if (!files.measured.length) $('data-file').append(new Option(files.roots.length ? '(no measured files in the data folders)' : '(start with --data DIR to list files)', ''));
  for (const f of files.meshes) $('object').append(new Option(f, f));
  for (const f of files.probes) $('probe').append(new Option(f, f));
  readUrl();
  // A file named in the address that this server does not offer falls back to the defaults.
  const offered = (id) => [...$(id).options].map((o) => o.value);
  if (!offered('object').includes(state.object)) state.object = 'suzanne';
  if (!offered('probe').includes(state.probe)) state.probe = 'studio';
  if (!['luminance', 'max', 'r', 'g', 'b'].includes(state.channel)) state.channel = 'luminance';
  if (!['intensity', 'brdf'].includes(state.quantity)) state.quantity = 'intensity';
  bind();
  // A hidden tab renders nothing (and holds no connection: browsers allow a host six).
  document.addEventListener('visibilitychange', () => { if (document.hidden) stopLit(); else startLit(); });
  renderPanel();
  syncControls();
  changed('params');
  window.gonioReady = true;
}

start().catch((e) => { stats.errors.push(String(e)); document.body.prepend(String(e)); });
