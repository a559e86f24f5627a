// robophi replay viewer (docs/viewer.md). Inlined into replay.html at build time.
//
// The run data is the JSON in <script id="robophi-data">, and its series are the
// <script data-series> elements before it (src/output/replay_html.cpp writes both). The page works in three layers, so that a browser without WebGL
// still shows the data: (1) data, time and plots; (2) the three.js scene graph;
// (3) the WebGL renderer, drawn when available.

const data = JSON.parse(document.getElementById('robophi-data').textContent);
const $ = (id) => document.getElementById(id);

// ---------------------------------------------------------------- the data
const particleCount = data.particles.count;
const radius = data.particles.radius;
const objectOf = data.particles.object;
const fixedFlag = data.particles.fixed;
const linear = data.linear;  // flat: a, b, restLength, ...
const linkCount = linear.length / 3;

// The series are binary: base64 of little-endian numbers (docs/viewer.md, "The
// page's data"): times as doubles, what is drawn (positions, plotted values,
// contact forces) as floats. Each series comes in pieces (the run writes its page
// as it goes), each piece a <script data-series="name"> element of its own base64,
// in order.
const seriesPieces = new Map();
for (const element of document.querySelectorAll('script[data-series]')) {
  const name = element.dataset.series;
  if (!seriesPieces.has(name)) seriesPieces.set(name, []);
  seriesPieces.get(name).push(atob(element.textContent));
}
function decodeNumbers(name, Type) {
  const pieces = seriesPieces.get(name) ?? [];
  const buffer = new Uint8Array(pieces.reduce((bytes, piece) => bytes + piece.length, 0));
  let at = 0;
  for (const piece of pieces) {
    for (let i = 0; i < piece.length; ++i) buffer[at++] = piece.charCodeAt(i);
  }
  return new Type(buffer.buffer);
}
const frameTime = decodeNumbers('frames.t', Float64Array);
const frameCount = frameTime.length;
// (frame, particle, xyz)
const framePosition = Float64Array.from(decodeNumbers('frames.position', Float32Array));
const tStart = frameTime[0];
const tEnd = frameTime[frameCount - 1];

// A table's rows: {count, t (Float64Array), value(r, c) for the columns after t, row(r)};
// `name` names its series ("energy": "energy.t" and "energy.values").
function rowsOf(table, name) {
  const t = decodeNumbers(`${name}.t`, Float64Array);
  const values = decodeNumbers(`${name}.values`, Float32Array);
  const width = table.columns.length - 1;  // after t
  const value = (r, c) => values[r * width + c];
  const row = (r) => [t[r], ...values.subarray(r * width, (r + 1) * width)];
  return { count: t.length, t, value, row };
}
// A table of rows as named columns of Float64Array.
function columnsOf(table, name) {
  const { count, t, value } = rowsOf(table, name);
  const out = {};
  table.columns.forEach((name, c) => {
    out[name] = c === 0 ? t : Float64Array.from({ length: count }, (_, r) => value(r, c - 1));
  });
  return out;
}
const energy = columnsOf(data.energy, 'energy');
const joints = data.joints ? columnsOf(data.joints, 'joints') : null;
// joints.csv: t, each joint's value, then "<name>:q", ":rate", ":effort" (plotted: the values).
const jointNames = data.joints ? data.joints.columns.slice(1).filter((c) => !c.includes(':')) : [];

// Contacts grouped by time: [{t, rows: [[a, b, fx, fy, fz, ...], ...]}], times increasing.
const contactGroups = [];
if (data.contacts) {
  const contactRows = rowsOf(data.contacts, 'contacts');
  for (let r = 0; r < contactRows.count; ++r) {
    const row = contactRows.row(r);
    const t = row[0];
    if (contactGroups.length === 0 || contactGroups[contactGroups.length - 1].t !== t) {
      contactGroups.push({ t, rows: [] });
    }
    contactGroups[contactGroups.length - 1].rows.push(row.slice(1));
  }
}
// Which columns of a contact row (after t) hold what: the particles, the normal
// force and, when the run folder has them, the friction (tangential) force.
const contactColumns = (data.contacts && data.contacts.columns ? data.contacts.columns.slice(1)
  : ['a', 'b', 'fx', 'fy', 'fz']).map((name) => String(name).trim().toLowerCase());
function columnTriple(candidates) {
  for (const names of candidates) {
    const index = names.map((n) => contactColumns.indexOf(n));
    if (index.every((i) => i >= 0)) return index;
  }
  return null;
}
const contactA = Math.max(0, contactColumns.indexOf('a'));
const contactB = contactColumns.indexOf('b') >= 0 ? contactColumns.indexOf('b') : 1;
const normalColumns = columnTriple([['fnx', 'fny', 'fnz'], ['fx_n', 'fy_n', 'fz_n'], ['fx', 'fy', 'fz']]) || [2, 3, 4];
// (robophi run writes t,a,b,fx,fy,fz,tx,ty,tz,sliding: f normal, t tangential.)
const frictionColumns = columnTriple([['tx', 'ty', 'tz'], ['ftx', 'fty', 'ftz'], ['fx_t', 'fy_t', 'fz_t'],
  ['frictionx', 'frictiony', 'frictionz'], ['friction_x', 'friction_y', 'friction_z']]);

// ---------------------------------------------------------------- the world
// The world description (src/output/world_view.cpp, world.json): environment,
// goals, paths, virtual obstacles. Absent for older run folders: then only the
// particles are known and a reference grid stands for the ground.
const world = data.world || null;
const objectKinds = data.objects.map((o) => o.kind);
const isVirtualParticle = (i) => objectKinds[objectOf[i]] === 'virtual';
// Linear springs that are attractors (goal, path, finger tips: MODEL §5), not
// connectors: drawn apart, and left out of the strain scale.
const attractor = new Uint8Array(linkCount);
if (world && Array.isArray(world.attractors)) {
  for (const s of world.attractors) if (s >= 0 && s < linkCount) attractor[s] = 1;
}
for (let s = 0; s < linkCount; ++s) {
  if (linear[3 * s + 2] <= 1e-6 || isVirtualParticle(linear[3 * s]) || isVirtualParticle(linear[3 * s + 1])) {
    attractor[s] = 1;
  }
}
const connectorIndex = [];
const attractorIndex = [];
for (let s = 0; s < linkCount; ++s) (attractor[s] ? attractorIndex : connectorIndex).push(s);
const environment = (world && world.environment) || { planes: [], heightfields: [], boxes: [], spheres: [] };
for (const key of ['planes', 'heightfields', 'boxes', 'spheres']) environment[key] = environment[key] || [];
const goals = (world && world.goals) || [];
const paths = (world && world.paths) || [];

// ---------------------------------------------------------------- helpers
const palette = ['#4e79a7', '#f28e2b', '#59a14f', '#e15759', '#76b7b2', '#edc948', '#b07aa1',
  '#ff9da7', '#9c755f', '#86bcb6'];
const fixedColour = '#4a4f57';
const virtualColour = '#7fd17f';  // virtual particles (goal copies, path ends)
const objectColour = (o) => palette[((o % palette.length) + palette.length) % palette.length];

// Largest index k with times[k] <= t (0 if t is before the first).
function indexAtOrBefore(times, t) {
  const tolerance = 1e-9 * Math.max(1, Math.abs(t));
  let lo = 0;
  let hi = times.length - 1;
  if (hi < 0 || t + tolerance < times[0]) return 0;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (times[mid] <= t + tolerance) lo = mid; else hi = mid - 1;
  }
  return lo;
}

function formatNumber(v, digits = 4) {
  if (!Number.isFinite(v)) return String(v);
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a >= 1e5 || a < 1e-3) return v.toExponential(digits - 2);
  return Number(v.toPrecision(digits)).toString();
}

function formatSeconds(t) {
  return (tEnd - tStart) >= 10 ? t.toFixed(2) : t.toFixed(3);
}

function notice(text) {
  const div = document.createElement('div');
  div.className = 'notice';
  div.textContent = text;
  $('notices').appendChild(div);
}

// ---------------------------------------------------------------- header and notices
document.title = `robophi replay: ${data.name || 'run'}`;
$('run-name').textContent = data.name || 'run';
$('run-info').textContent = [
  `${particleCount} particles`, `${connectorIndex.length} connectors`,
  `${frameCount} frame${frameCount === 1 ? '' : 's'}`, `t = ${formatNumber(tStart)} to ${formatNumber(tEnd)} s`,
].join(' · ');

const capMb = Number((data.sizeCapBytes / 1e6).toPrecision(3));
const ordinal = (n) => {
  const tens = n % 100;
  const suffix = tens >= 11 && tens <= 13 ? 'th' : ({ 1: 'st', 2: 'nd', 3: 'rd' }[n % 10] || 'th');
  return `${n}${suffix}`;
};
if (data.frames.stride > 1) {
  notice(`Frames dropped to keep this page under ${capMb} MB: showing ${frameCount} of ` +
    `${data.frames.sourceCount} frames (every ${ordinal(data.frames.stride)}). ` +
    'Export again with a larger --size-cap-mb to see them all.');
}
const decimatedTables = [['energy', data.energy], ['joints', data.joints], ['contacts', data.contacts]]
  .filter(([, table]) => table && table.stride > 1).map(([name, table]) => `${name} (every ${ordinal(table.stride)} row)`);
if (decimatedTables.length > 0) {
  notice(`Plot rows thinned to keep this page under ${capMb} MB: ${decimatedTables.join(', ')}.`);
}

// ---------------------------------------------------------------- playback state
const view = {
  time: tStart,
  frame: 0,
  playing: false,
  speed: 1,
  loop: true,
};
const listeners = [];  // called with the displayed frame on every change

function showTime(t) {
  view.time = Math.min(Math.max(t, tStart), tEnd);
  view.frame = indexAtOrBefore(frameTime, view.time);
  for (const listener of listeners) listener(view.frame);
}

// ---------------------------------------------------------------- plots
// A time-series plot drawn on a <canvas>: the curves are drawn once per size into
// an offscreen canvas; each redraw copies it and adds the time marker and legend.
// Appends a series' entry (its line's colour and dash, its label) to a plot's
// legend; returns the element that shows its value.
function addLegendEntry(legend, s) {
  const item = document.createElement('span');
  item.className = 'legend-item';
  const key = document.createElement('span');
  key.className = 'legend-key';
  key.style.borderTopColor = s.colour;
  if (s.dash) key.style.borderTopStyle = 'dashed';
  const value = document.createElement('span');
  value.className = 'legend-value';
  item.append(key, `${s.label} `, value);
  legend.appendChild(item);
  return value;
}

class Plot {
  constructor(canvas, legend, series, options = {}) {
    this.canvas = canvas;
    this.legend = legend;  // an element beside the caption: one entry per series with its value
    this.legendValues = series.map((s) => addLegendEntry(legend, s));
    this.series = series;  // [{name, label, colour, t, v, unit}]
    this.options = options;
    this.cache = null;
    this.margin = { left: 58, right: 10, top: 8, bottom: 22 };
    new ResizeObserver(() => { this.cache = null; this.draw(); }).observe(canvas);
    const seekAt = (event) => {
      const rect = canvas.getBoundingClientRect();
      const x = event.clientX - rect.left;
      showTime(this.timeAt(x));
    };
    canvas.addEventListener('pointerdown', (event) => {
      canvas.setPointerCapture(event.pointerId);
      seekAt(event);
      const move = (e) => seekAt(e);
      const up = () => { canvas.removeEventListener('pointermove', move); canvas.removeEventListener('pointerup', up); };
      canvas.addEventListener('pointermove', move);
      canvas.addEventListener('pointerup', up);
    });
    this.computeRange();
  }

  computeRange() {
    let lo = Infinity;
    let hi = -Infinity;
    for (const s of this.series) {
      for (const v of s.v) {
        if (Number.isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
      }
      for (const v of s.limits || []) {
        if (Number.isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
      }
    }
    if (!Number.isFinite(lo)) { lo = 0; hi = 1; }
    if (this.options.includeZero) { lo = Math.min(lo, 0); hi = Math.max(hi, 0); }
    if (hi - lo <= 1e-12 * Math.max(Math.abs(hi), Math.abs(lo), 1e-300)) {
      const pad = Math.abs(hi) > 0 ? 0.1 * Math.abs(hi) : 1;
      lo -= pad; hi += pad;
    } else {
      const pad = 0.06 * (hi - lo);
      lo -= pad; hi += pad;
    }
    this.yLo = lo;
    this.yHi = hi;
  }

  get width() { return this.canvas.clientWidth; }
  get height() { return this.canvas.clientHeight; }
  xOf(t) {
    const span = tEnd - tStart || 1;
    return this.margin.left + (t - tStart) / span * (this.width - this.margin.left - this.margin.right);
  }
  timeAt(x) {
    const w = this.width - this.margin.left - this.margin.right;
    return tStart + (x - this.margin.left) / w * (tEnd - tStart);
  }
  yOf(v) {
    const h = this.height - this.margin.top - this.margin.bottom;
    return this.margin.top + (this.yHi - v) / (this.yHi - this.yLo) * h;
  }

  // Ticks at 1, 2 or 5 × 10^n, about `count` of them.
  static ticks(lo, hi, count) {
    const raw = (hi - lo) / count;
    const power = 10 ** Math.floor(Math.log10(raw));
    const step = [1, 2, 5, 10].map((m) => m * power).find((s) => s >= raw) || raw;
    const out = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) {
      out.push(Math.abs(v) < 1e-12 * step ? 0 : v);
    }
    return out;
  }

  renderCache() {
    const ratio = window.devicePixelRatio || 1;
    const w = this.width;
    const h = this.height;
    const cache = document.createElement('canvas');
    cache.width = Math.max(1, Math.round(w * ratio));
    cache.height = Math.max(1, Math.round(h * ratio));
    const g = cache.getContext('2d');
    g.scale(ratio, ratio);
    const m = this.margin;
    g.font = '11px system-ui, sans-serif';
    // Grid and axes.
    g.strokeStyle = '#e6eaef';
    g.fillStyle = '#667085';
    g.lineWidth = 1;
    g.textAlign = 'right';
    g.textBaseline = 'middle';
    const yTicks = Plot.ticks(this.yLo, this.yHi, Math.max(2, Math.floor((h - m.top - m.bottom) / 34)));
    const largest = Math.max(...yTicks.map(Math.abs));
    const label = (largest >= 1e5 || (largest < 1e-2 && largest > 0))
      ? (v) => (v === 0 ? '0' : v.toExponential(2).replace(/\.?0+e/, 'e')) : (v) => formatNumber(v, 4);
    for (const v of yTicks) {
      const y = Math.round(this.yOf(v)) + 0.5;
      g.beginPath(); g.moveTo(m.left, y); g.lineTo(w - m.right, y); g.stroke();
      g.fillText(label(v), m.left - 5, y);
    }
    g.textAlign = 'center';
    g.textBaseline = 'top';
    for (const t of Plot.ticks(tStart, tEnd || 1, Math.max(2, Math.floor((w - m.left - m.right) / 70)))) {
      const x = Math.round(this.xOf(t)) + 0.5;
      g.beginPath(); g.moveTo(x, m.top); g.lineTo(x, h - m.bottom); g.stroke();
      g.fillText(formatNumber(t, 3), x, h - m.bottom + 4);
    }
    g.strokeStyle = '#98a2b3';
    g.strokeRect(m.left + 0.5, m.top + 0.5, w - m.left - m.right - 1, h - m.top - m.bottom - 1);
    g.textAlign = 'right';
    g.fillText('t (s)', m.left - 5, h - m.bottom + 4);
    // Curves, clipped to the plot area.
    g.save();
    g.beginPath();
    g.rect(m.left, m.top, w - m.left - m.right, h - m.top - m.bottom);
    g.clip();
    g.lineWidth = 1.6;
    g.lineJoin = 'round';
    // A series' limits (a joint's lower and upper position): thin dotted lines in its colour.
    g.lineWidth = 1;
    for (const s of this.series) {
      g.strokeStyle = s.colour;
      g.setLineDash([2, 3]);
      for (const v of s.limits || []) {
        if (!Number.isFinite(v)) continue;
        const y = Math.round(this.yOf(v)) + 0.5;
        g.beginPath(); g.moveTo(m.left, y); g.lineTo(w - m.right, y); g.stroke();
      }
    }
    g.lineWidth = 1.6;
    for (const s of this.series) {
      g.strokeStyle = s.colour;
      g.setLineDash(s.dash || []);
      g.beginPath();
      let pen = false;
      for (let i = 0; i < s.t.length; ++i) {
        if (!Number.isFinite(s.v[i])) { pen = false; continue; }
        const x = this.xOf(s.t[i]);
        const y = this.yOf(s.v[i]);
        if (pen) g.lineTo(x, y); else g.moveTo(x, y);
        pen = true;
      }
      g.stroke();
      if (s.t.length < 3) {
        // Too few points for a line: mark them.
        g.fillStyle = s.colour;
        for (let i = 0; i < s.t.length; ++i) {
          if (Number.isFinite(s.v[i])) g.fillRect(this.xOf(s.t[i]) - 2.5, this.yOf(s.v[i]) - 2.5, 5, 5);
        }
      }
    }
    g.restore();
    this.cache = cache;
  }

  draw() {
    const w = this.width;
    const h = this.height;
    if (w <= 0 || h <= 0) return;
    const ratio = window.devicePixelRatio || 1;
    if (this.canvas.width !== Math.round(w * ratio) || this.canvas.height !== Math.round(h * ratio)) {
      this.canvas.width = Math.round(w * ratio);
      this.canvas.height = Math.round(h * ratio);
      this.cache = null;
    }
    if (!this.cache) this.renderCache();
    const g = this.canvas.getContext('2d');
    g.setTransform(1, 0, 0, 1, 0, 0);
    g.clearRect(0, 0, this.canvas.width, this.canvas.height);
    g.drawImage(this.cache, 0, 0);
    g.scale(ratio, ratio);
    // The time marker.
    const x = Math.round(this.xOf(view.time)) + 0.5;
    g.strokeStyle = '#1f2933';
    g.lineWidth = 1;
    g.setLineDash([4, 3]);
    g.beginPath(); g.moveTo(x, this.margin.top); g.lineTo(x, h - this.margin.bottom); g.stroke();
    g.setLineDash([]);
    // The legend shows the values at the marker.
    this.series.forEach((s, n) => {
      const v = s.v[indexAtOrBefore(s.t, view.time)];
      this.legendValues[n].textContent = `${formatNumber(v)}${s.unit ? ' ' + s.unit : ''}`;
    });
  }
}

const plots = [];
const plotSeriesNames = [];
function addPlot(canvasId, series, options) {
  const canvas = $(canvasId);
  const plot = new Plot(canvas, canvas.parentElement.querySelector('.legend'), series, options);
  plots.push(plot);
  for (const s of series) plotSeriesNames.push(s.name);
  return plot;
}

// External work W_ext (J, EnergyTally::external): energy.csv's column when it has
// one, else what its total implies (total = E + dissipated − W_ext).
const externalWork = energy.external || Float64Array.from(energy.t,
  (_, i) => energy.kinetic[i] + energy.potential[i] + energy.dissipated[i] - energy.total[i]);
const energySeries = [
  { name: 'kinetic', label: 'kinetic', colour: '#e15759', t: energy.t, v: energy.kinetic, unit: 'J' },
  { name: 'potential', label: 'potential', colour: '#4e79a7', t: energy.t, v: energy.potential, unit: 'J' },
  { name: 'dissipated', label: 'dissipated', colour: '#f28e2b', t: energy.t, v: energy.dissipated, unit: 'J' },
];
// Shown when anything was done from outside (a moving virtual robot, edits between steps).
let scaleOfEnergy = 1e-300;
for (const column of [energy.total, energy.potential, energy.kinetic]) {
  for (const v of column) if (Number.isFinite(v)) scaleOfEnergy = Math.max(scaleOfEnergy, Math.abs(v));
}
if (externalWork.some((v) => Number.isFinite(v) && Math.abs(v) > 1e-9 * scaleOfEnergy) || energy.external) {
  energySeries.push({ name: 'external', label: 'external work', colour: '#76b7b2', t: energy.t, v: externalWork, unit: 'J' });
}
energySeries.push({ name: 'total', label: 'total (E + dissipated − external)', colour: '#1f2933', t: energy.t,
  v: energy.total, unit: 'J', dash: [6, 3] });
addPlot('plot-energy', energySeries, { includeZero: true });
addPlot('plot-dt', [
  { name: 'dt', label: 'dt', colour: '#59a14f', t: energy.t, v: energy.dt, unit: 's' },
], { includeZero: false });
if (joints && jointNames.length > 0) {
  const kinds = data.jointKinds || [];
  const unitOf = (j) => (kinds[j] === 'prismatic' ? 'm' : 'rad');
  const units = [...new Set(jointNames.map((_, j) => unitOf(j)))];
  // The joint position q in the robot's own coordinates (joints.csv's "NAME:q",
  // jointPosition: a URDF's q), with the joint's limits when world.json has them;
  // an older run folder without it: the raw value.
  const limitOf = new Map(((world && world.jointLimits) || []).map((l) => [l.joint, [l.lower, l.upper]]));
  const robotCoordinates = jointNames.every((name) => joints[`${name}:q`]);
  $('joints-caption').textContent = `Joint positions q (${units.join(', ')})` +
    (limitOf.size > 0 ? ', limits dotted' : '');
  $('fig-joints').hidden = false;
  addPlot('plot-joints', jointNames.map((name, j) => ({
    name, label: name, colour: palette[(j + 4) % palette.length], t: joints.t,
    v: robotCoordinates ? joints[`${name}:q`] : joints[name], unit: unitOf(j), limits: limitOf.get(name),
  })), { includeZero: false });
}
listeners.push(() => { for (const plot of plots) plot.draw(); });

// ---------------------------------------------------------------- controls
const scrub = $('scrub');
const scrubMax = Number(scrub.max);
function setPlaying(playing) {
  view.playing = playing && frameCount > 1;
  $('play').innerHTML = view.playing ? '&#10074;&#10074;' : '&#9654;';
  $('play').setAttribute('aria-label', view.playing ? 'pause' : 'play');
}
$('play').addEventListener('click', () => {
  if (!view.playing && view.time >= tEnd) showTime(tStart);
  setPlaying(!view.playing);
});
$('step-back').addEventListener('click', () => { setPlaying(false); showTime(frameTime[Math.max(0, view.frame - 1)]); });
$('step-forward').addEventListener('click', () => {
  setPlaying(false);
  showTime(frameTime[Math.min(frameCount - 1, view.frame + 1)]);
});
scrub.addEventListener('input', () => {
  showTime(tStart + (tEnd - tStart) * Number(scrub.value) / scrubMax);
});
$('speed').addEventListener('change', () => { view.speed = Number($('speed').value); });
$('loop').addEventListener('change', () => { view.loop = $('loop').checked; });
window.addEventListener('keydown', (event) => {
  if (event.target instanceof HTMLInputElement && event.target.type !== 'range' && event.target.type !== 'checkbox') return;
  if (event.key === ' ') { event.preventDefault(); $('play').click(); }
  else if (event.key === 'ArrowRight') { event.preventDefault(); $('step-forward').click(); }
  else if (event.key === 'ArrowLeft') { event.preventDefault(); $('step-back').click(); }
  else if (event.key === 'Home') showTime(tStart);
  else if (event.key === 'End') showTime(tEnd);
  else if (event.key === 'f' || event.key === 'F') $('reset-view').click();
});
listeners.push((frame) => {
  if (tEnd > tStart) scrub.value = String(Math.round((view.time - tStart) / (tEnd - tStart) * scrubMax));
  $('time-readout').textContent =
    `t = ${formatSeconds(view.time)} s · frame ${frame + 1}/${frameCount}`;
});
if (!data.contacts) {
  const box = $('show-contacts');
  box.checked = false;
  box.disabled = true;
  box.parentElement.classList.add('disabled');
  box.parentElement.title = 'this run folder has no contacts.csv';
}
if (connectorIndex.length === 0 && attractorIndex.length === 0) {
  $('show-connectors').disabled = true;
  $('show-connectors').parentElement.classList.add('disabled');
}

// Object legend.
{
  const legend = $('legend');
  const objects = data.objects.length > 0 ? data.objects : [{ name: 'particles', kind: '' }];
  const objectRow = (o, i) => {
    const row = document.createElement('div');
    row.innerHTML = `<span class="swatch" style="background:${o.kind === 'virtual' ? virtualColour : objectColour(i)}"></span>`;
    const fixedObject = world && world.objects && world.objects[i] && world.objects[i].fixed && o.kind !== 'virtual';
    row.append(`${o.name}${o.kind ? ` (${o.kind})` : ''}${fixedObject ? ', fixed' : ''}`);
    return row;
  };
  // A robot's links ("<robot>.<link>", kind link, and their carriers): one entry,
  // its links inside when opened.
  const robotOf = (o) => (o.kind === 'link' || o.kind === 'virtual') && o.name.includes('.')
    ? o.name.slice(0, o.name.indexOf('.')) : null;
  const members = new Map();
  objects.forEach((o, i) => {
    const r = robotOf(o);
    if (r !== null) { if (!members.has(r)) members.set(r, []); members.get(r).push(i); }
  });
  const collapsed = new Set([...members].filter(([, list]) => list.some((i) => objects[i].kind === 'link') &&
    list.length >= 2).map(([r]) => r));
  const shownRobots = new Set();
  objects.forEach((o, i) => {
    const r = robotOf(o);
    if (r === null || !collapsed.has(r)) { legend.appendChild(objectRow(o, i)); return; }
    if (shownRobots.has(r)) return;
    shownRobots.add(r);
    const list = members.get(r);
    const links = list.filter((k) => objects[k].kind === 'link').length;
    const entry = document.createElement('details');
    entry.className = 'legend-robot';
    const summary = document.createElement('summary');
    summary.innerHTML = `<span class="swatch" style="background:${objectColour(i)}"></span>`;
    summary.append(`${r} (robot, ${links} link${links === 1 ? '' : 's'})`);
    entry.appendChild(summary);
    for (const k of list) entry.appendChild(objectRow(objects[k], k));
    legend.appendChild(entry);
  });
  if (fixedFlag.some((f, i) => f && !isVirtualParticle(i))) {
    const row = document.createElement('div');
    row.innerHTML = `<span class="swatch" style="background:${fixedColour}"></span>`;
    row.append('fixed particles');
    legend.appendChild(row);
  }
}

// ---------------------------------------------------------------- the 3D scene
function webglAvailable() {
  try {
    const canvas = document.createElement('canvas');
    return Boolean(canvas.getContext('webgl2') || canvas.getContext('webgl'));
  } catch {
    return false;
  }
}

function showViewMessage(text) {
  $('view-message').hidden = false;
  $('view-message').textContent = text;
}

// Extent of the whole run (every kept frame of the particles that collide, plus
// radii; virtual particles, such as far inertia carriers, left out) and of the
// environment and goals: what the camera frames (the robots' shapes are added).
function runBounds() {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  const add = (p, r = 0) => {
    for (let d = 0; d < 3; ++d) {
      const v = p[d];
      if (!Number.isFinite(v)) continue;
      lo[d] = Math.min(lo[d], v - r);
      hi[d] = Math.max(hi[d], v + r);
    }
  };
  for (let k = 0; k < frameCount; ++k) {
    for (let i = 0; i < particleCount; ++i) {
      if (isVirtualParticle(i)) continue;  // goal copies, inertia carriers: not what is seen
      const base = (k * particleCount + i) * 3;
      add([framePosition[base], framePosition[base + 1], framePosition[base + 2]], radius[i]);
    }
  }
  for (const h of environment.heightfields) {
    let zLo = Infinity;
    let zHi = -Infinity;
    for (const z of h.heights) if (Number.isFinite(z)) { zLo = Math.min(zLo, z); zHi = Math.max(zHi, z); }
    add([h.origin[0], h.origin[1], zLo]);
    add([h.origin[0] + (h.columns - 1) * h.cellSize[0], h.origin[1] + (h.rows - 1) * h.cellSize[1], zHi]);
  }
  for (const b of environment.boxes) {
    for (let corner = 0; corner < 8; ++corner) {
      const p = b.center.slice();
      for (let a = 0; a < 3; ++a) {
        const sign = (corner >> a) & 1 ? 1 : -1;
        for (let d = 0; d < 3; ++d) p[d] += sign * b.halfExtents[a] * b.axes[a][d];
      }
      add(p);
    }
  }
  for (const s of environment.spheres) add(s.center, s.radius);
  for (const g of goals) for (const p of g.positions || []) add(p, g.tolerance || 0);
  for (const p of paths) {
    if (p.type === 'line') { add(p.from); add(p.to); } else if (p.type === 'arc') add(p.center, p.radius);
  }
  if (!Number.isFinite(lo[0]) || !Number.isFinite(lo[1]) || !Number.isFinite(lo[2])) {
    return { lo: [-1, -1, -1], hi: [1, 1, 1], fallback: true };
  }
  return { lo, hi };
}

// Largest |strain| of any connector (attractors left out) over the run, for the colour scale.
function maxStrain() {
  let largest = 0;
  for (let k = 0; k < frameCount; ++k) {
    for (const s of connectorIndex) {
      const strain = strainOf(k, s);
      if (Number.isFinite(strain)) largest = Math.max(largest, Math.abs(strain));
    }
  }
  return largest;
}
function strainOf(frame, s) {
  const a = (frame * particleCount + linear[3 * s]) * 3;
  const b = (frame * particleCount + linear[3 * s + 1]) * 3;
  const rest = linear[3 * s + 2];
  const length = Math.hypot(framePosition[b] - framePosition[a], framePosition[b + 1] - framePosition[a + 1],
    framePosition[b + 2] - framePosition[a + 2]);
  return rest > 0 ? (length - rest) / rest : 0;
}

// Colours of the world.
const worldColour = {
  plane: 0xd9dee5, planeGrid: 0xa9b2bf, box: 0x9a8f80, sphere: 0x8d99a6, security: 0xf2a93b,
  virtualObstacle: 0x9467bd, goal: 0x2ca02c, path: 0x17a2b8, attractor: 0x2ca02c,
  terrainLow: [0.55, 0.68, 0.45], terrainHigh: [0.69, 0.55, 0.36], friction: 0xff7f0e,
};

// ---------------------------------------------------------------- robots as they look
// world.json's "robots" block (docs/viewer.md "Robots as they look"): each URDF
// <visual> (a mesh or a box, cylinder, sphere) at its pose as built, moved by the
// best-fit rigid motion of the particles that carry it (its link's body, or the
// particles its rigid tree body moves) from where they started.
const robots = (world && world.robots) || null;
const robotVisuals = robots ? robots.visuals || [] : [];
const robotCarriers = robots ? robots.carriers || [] : [];
const meshFiles = data.meshFiles || [];
// Particles drawn as their link's shapes (their spheres are the optional particle layer).
const carriesVisual = new Uint8Array(particleCount);
for (const c of robotCarriers) for (const i of c.particles) if (i >= 0 && i < particleCount) carriesVisual[i] = 1;
// Fixed particles a rigid tree's body moves: the live view may drag them (the tree struck there).
const treeCarried = new Uint8Array(particleCount);
for (const c of robotCarriers) if (c.rigidTree) for (const i of c.particles) if (i >= 0 && i < particleCount) treeCarried[i] = 1;

if (robotVisuals.length === 0) {
  $('show-particles').parentElement.hidden = true;
  if (!(world && world.shapes)) $('show-robots').parentElement.hidden = true;
} else {
  // The robots as they look; their particles and connectors are the optional layer.
  $('show-particles').checked = false;
  $('show-connectors').checked = false;
}

// (carrier) per frame the rigid motion x = R r + t of its particles from rest r:
// R row by row, then t (12 numbers). The rotation is the polar part of
// A = Σ (x − x̄)(r − r̄)ᵀ, found by Müller et al.'s iteration ("A robust method to
// extract the rotational part of deformations", 2016), from the previous frame's.
function carrierMotions() {
  const motions = [];
  for (const c of robotCarriers) {
    const n = c.particles.length;
    const motion = new Float64Array(frameCount * 12);
    const r0 = [0, 0, 0];
    for (let k = 0; k < n; ++k) for (let d = 0; d < 3; ++d) r0[d] += c.rest[3 * k + d] / n;
    let q = [1, 0, 0, 0];  // w, x, y, z
    const R = new Float64Array(9);
    const toMatrix = () => {
      const [w, x, y, z] = q;
      R.set([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]);
    };
    for (let f = 0; f < frameCount; ++f) {
      const base = f * particleCount * 3;
      const x0 = [0, 0, 0];
      let finite = n > 0;
      for (const i of c.particles) {
        for (let d = 0; d < 3; ++d) x0[d] += framePosition[base + 3 * i + d] / n;
      }
      finite = finite && x0.every(Number.isFinite);
      if (finite) {
        const A = new Float64Array(9);  // row-major
        c.particles.forEach((i, k) => {
          for (let a = 0; a < 3; ++a) {
            const xa = framePosition[base + 3 * i + a] - x0[a];
            for (let b = 0; b < 3; ++b) A[3 * a + b] += xa * (c.rest[3 * k + b] - r0[b]);
          }
        });
        for (let iteration = 0; iteration < 40; ++iteration) {
          toMatrix();
          // ω = Σ_j R_j × A_j / (|Σ_j R_j · A_j| + ε), over the columns j.
          const w = [0, 0, 0];
          let dot = 0;
          for (let j = 0; j < 3; ++j) {
            const r = [R[j], R[3 + j], R[6 + j]];
            const a = [A[j], A[3 + j], A[6 + j]];
            w[0] += r[1] * a[2] - r[2] * a[1];
            w[1] += r[2] * a[0] - r[0] * a[2];
            w[2] += r[0] * a[1] - r[1] * a[0];
            dot += r[0] * a[0] + r[1] * a[1] + r[2] * a[2];
          }
          const scale = 1 / (Math.abs(dot) + 1e-300);
          const angle = Math.hypot(w[0], w[1], w[2]) * scale;
          if (!(angle > 1e-12)) break;
          const s = Math.sin(angle / 2) / (angle / scale);
          const dq = [Math.cos(angle / 2), w[0] * s, w[1] * s, w[2] * s];
          q = [dq[0] * q[0] - dq[1] * q[1] - dq[2] * q[2] - dq[3] * q[3],
            dq[0] * q[1] + dq[1] * q[0] + dq[2] * q[3] - dq[3] * q[2],
            dq[0] * q[2] - dq[1] * q[3] + dq[2] * q[0] + dq[3] * q[1],
            dq[0] * q[3] + dq[1] * q[2] - dq[2] * q[1] + dq[3] * q[0]];
          const norm = Math.hypot(...q);
          q = q.map((v) => v / norm);
        }
      }
      toMatrix();
      const out = motion.subarray(12 * f, 12 * f + 12);
      out.set(R);
      for (let d = 0; d < 3; ++d) {
        const t = finite ? x0[d] - (R[3 * d] * r0[0] + R[3 * d + 1] * r0[1] + R[3 * d + 2] * r0[2])
          : (f > 0 ? motion[12 * (f - 1) + 9 + d] : 0);
        out[9 + d] = t;
      }
    }
    motions.push(motion);
  }
  return motions;
}

// The robots' shapes: a group per visual, its matrix the carrier's motion (set per
// frame) times the visual's pose as built. Meshes are parsed once by three.js's
// loaders and shared by the visuals that use them.
async function buildRobots(THREE) {
  const group = new THREE.Group();
  group.name = 'robots';
  // (meshTriangles: each parsed mesh file's triangles, by its index in meshFiles.)
  const counts = { visuals: robotVisuals.length, drawn: 0, meshes: 0, shapes: 0, missing: 0, meshTriangles: {} };
  const holders = [];
  if (robotVisuals.length === 0) return { group, holders, counts, motions: [] };
  const motions = carrierMotions();
  const parsed = new Map();
  const parseMesh = async (index) => {
    if (parsed.has(index)) return parsed.get(index);
    const file = meshFiles[index];
    let object = null;
    if (file && file.data) {
      if (file.decimatedFrom) {
        console.info(`robophi replay: mesh ${index} decimated from ${file.decimatedFrom} to ${file.triangles} triangles (the page's budget per mesh)`);
      }
      const binary = atob(file.data);
      const bytes = new Uint8Array(binary.length);
      for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
      const text = () => new TextDecoder().decode(bytes);
      try {
        if (file.format === 'stl') {
          const { STLLoader } = await import('three/addons/loaders/STLLoader.js');
          const geometry = new STLLoader().parse(bytes.buffer);
          if (!geometry.attributes.normal) geometry.computeVertexNormals();
          object = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ color: 0xb8bcc4, roughness: 0.55,
            metalness: 0.1 }));
        } else if (file.format === 'obj') {
          const { OBJLoader } = await import('three/addons/loaders/OBJLoader.js');
          const loader = new OBJLoader();
          if (file.mtl) {
            // Its materials' colours (its .mtl as robophi read it; or a mesh robophi
            // wrote back, decimated or a DAE converted: those of its file).
            const { MTLLoader } = await import('three/addons/loaders/MTLLoader.js');
            const materials = new MTLLoader().parse(file.mtl, '');
            materials.preload();
            loader.setMaterials(materials);
          }
          object = loader.parse(text());
        } else if (file.format === 'dae') {
          const { ColladaLoader } = await import('three/addons/loaders/ColladaLoader.js');
          const collada = new ColladaLoader().parse(text(), '');
          object = collada ? collada.scene : null;
          // A URDF's DAE is in its link's frame: the loader's turn of a Z_UP file
          // into three.js's Y-up is undone (its unit scale is kept).
          if (object) object.rotation.set(0, 0, 0);
        } else {
          console.warn(`robophi replay: mesh format '${file.format}' is not drawn`);
        }
      } catch (error) {
        console.warn('robophi replay: a mesh could not be parsed:', error);
        object = null;
      }
    } else if (file && file.note) {
      console.warn(`robophi replay: mesh ${file.note}`);
    }
    if (object) {
      let triangles = 0;
      object.traverse((o) => {
        if (o.isMesh) triangles += (o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count) / 3;
      });
      counts.meshTriangles[index] = triangles;
    }
    parsed.set(index, object);
    return object;
  };
  for (const v of robotVisuals) {
    let shape = null;
    if (v.kind === 'mesh') {
      const source = v.mesh >= 0 ? await parseMesh(v.mesh) : null;
      if (source) {
        shape = source.clone();
        shape.scale.set(...(v.scale || [1, 1, 1]));
        ++counts.meshes;
      }
    } else {
      let geometry = null;
      if (v.kind === 'box') geometry = new THREE.BoxGeometry(...v.size);
      else if (v.kind === 'sphere') geometry = new THREE.SphereGeometry(v.radius, 32, 20);
      else if (v.kind === 'cylinder') {
        geometry = new THREE.CylinderGeometry(v.radius, v.radius, v.length, 40);
        geometry.rotateX(Math.PI / 2);  // along z, as URDF's cylinders
      }
      if (geometry) {
        shape = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ color: 0xb8bcc4, roughness: 0.55 }));
        ++counts.shapes;
      }
    }
    if (!shape) {
      ++counts.missing;
      if (v.warning) console.warn(`robophi replay: ${v.link}: ${v.warning}`);
      continue;
    }
    if (v.rgba) {
      const material = new THREE.MeshStandardMaterial({
        // (A little below full: a white link would burn out where the key light meets it.)
        color: new THREE.Color(v.rgba[0], v.rgba[1], v.rgba[2]).multiplyScalar(0.82), roughness: 0.55,
        metalness: 0.1,
        transparent: v.rgba[3] < 1, opacity: v.rgba[3],
      });
      shape.traverse((o) => { if (o.isMesh) o.material = material; });
    }
    const built = new THREE.Group();
    built.matrixAutoUpdate = false;
    const p = v.pose;
    built.matrix.set(p[0], p[1], p[2], p[9], p[3], p[4], p[5], p[10], p[6], p[7], p[8], p[11], 0, 0, 0, 1);
    built.add(shape);
    const holder = new THREE.Group();
    holder.matrixAutoUpdate = false;
    holder.add(built);
    holder.userData = { carrier: v.carrier, robot: v.robot, link: v.link };
    group.add(holder);
    holders.push(holder);
    ++counts.drawn;
  }
  return { group, holders, counts, motions };
}

// Moves the robots' shapes to frame `frame`.
function placeRobots(robotsView, frame) {
  for (const holder of robotsView.holders) {
    const m = robotsView.motions[holder.userData.carrier];
    if (!m) continue;
    const b = 12 * frame;
    holder.matrix.set(m[b], m[b + 1], m[b + 2], m[b + 9], m[b + 3], m[b + 4], m[b + 5], m[b + 10],
      m[b + 6], m[b + 7], m[b + 8], m[b + 11], 0, 0, 0, 1);
    holder.matrixWorldNeedsUpdate = true;
  }
}

// ---------------------------------------------------------------- objects' shapes
// world.json's "shapes" (docs/viewer.md "Objects' shapes"): round bodies (balls,
// wheels' rims, cylinder wheels) and surface meshes (cloths, meshed objects), drawn
// from the particles of each frame.
const objectShapes = (world && world.shapes) || null;
function buildObjectShapes(THREE) {
  const group = new THREE.Group();
  group.name = 'shapes';
  const updates = [];
  const counts = { rims: 0, surfaceTriangles: 0 };
  if (!objectShapes) return { group, updates, counts };
  const at = (base, i) => new THREE.Vector3(framePosition[base + 3 * i], framePosition[base + 3 * i + 1],
    framePosition[base + 3 * i + 2]);
  const zAxis = new THREE.Vector3(0, 0, 1);
  for (const rim of objectShapes.rims || []) {
    if (!(rim.count > 0) || rim.first + rim.count > particleCount) continue;
    if (carriesVisual[rim.first]) continue;  // a robot's link: drawn as its URDF visual
    const colour = objectColour(objectOf[rim.first]);
    const material = new THREE.MeshStandardMaterial({ color: colour, roughness: 0.7, transparent: true, opacity: 0.85 });
    let mesh;
    let place;
    if (rim.axisParticle >= 0 && rim.hub >= 0) {
      // A cylinder wheel about the hub → axis particle line.
      const geometry = new THREE.CylinderGeometry(rim.sphereRadius, rim.sphereRadius, 2 * rim.halfLength, 40);
      geometry.rotateX(Math.PI / 2);
      mesh = new THREE.Mesh(geometry, material);
      place = (base) => {
        const hub = at(base, rim.hub);
        const n = at(base, rim.axisParticle).sub(hub).normalize();
        mesh.position.copy(hub).addScaledVector(n, rim.axialOffset);
        mesh.quaternion.setFromUnitVectors(zAxis, n);
      };
    } else if (rim.sphereRadius > 0) {
      // A ball: the sphere about its particles' centre.
      mesh = new THREE.Mesh(new THREE.SphereGeometry(rim.sphereRadius, 32, 20), material);
      place = (base) => {
        const c = new THREE.Vector3();
        for (let k = 0; k < rim.count; ++k) c.add(at(base, rim.first + k));
        mesh.position.copy(c.multiplyScalar(1 / rim.count));
      };
    } else if (rim.hub >= 0 && rim.count >= 3) {
      // A wheel's rim ring: a disc through its particles, about its hub.
      const width = 2 * radius[rim.first];
      mesh = new THREE.Mesh(new THREE.CylinderGeometry(1, 1, width, 40).rotateX(Math.PI / 2), material);
      place = (base) => {
        const hub = at(base, rim.hub);
        const a = at(base, rim.first).sub(hub);
        const b = at(base, rim.first + Math.floor(rim.count / 3)).sub(hub);
        const n = new THREE.Vector3().crossVectors(a, b).normalize();
        const r = a.length() + radius[rim.first];
        mesh.position.copy(hub);
        mesh.quaternion.setFromUnitVectors(zAxis, n);
        mesh.scale.set(r, r, 1);
      };
    } else continue;
    group.add(mesh);
    updates.push(place);
    ++counts.rims;
  }
  const s = objectShapes.surfaces;
  if (s && s.triangles && s.triangles.length > 0) {
    const slots = s.slots || 8;
    const vertexCount = s.particles.length / slots;
    const positions = new Float32Array(vertexCount * 3);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3).setUsage(THREE.DynamicDrawUsage));
    // A robot's link's surface is drawn as its URDF visual instead.
    const covered = (v) => s.particles.slice(v * slots, (v + 1) * slots).some((i) => i >= 0 && carriesVisual[i]);
    const kept = [];
    for (let t = 0; t < s.triangles.length; t += 3) {
      if (!covered(s.triangles[t])) kept.push(s.triangles[t], s.triangles[t + 1], s.triangles[t + 2]);
    }
    if (kept.length === 0) return { group, updates, counts };
    geometry.setIndex(kept);
    // Colour by the triangles' object: one mesh a colour would need splitting; the first object's.
    const colour = s.objects.length > 0 ? objectColour(s.objects[0]) : '#999999';
    const mesh = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ color: colour, roughness: 0.8,
      side: THREE.DoubleSide, transparent: true, opacity: 0.85 }));
    mesh.frustumCulled = false;
    group.add(mesh);
    counts.surfaceTriangles = kept.length / 3;
    updates.push((base) => {
      for (let v = 0; v < vertexCount; ++v) {
        let x = 0, y = 0, z = 0;
        for (let k = 0; k < slots; ++k) {
          const i = s.particles[v * slots + k];
          const w = s.weights[v * slots + k];
          if (i < 0 || i >= particleCount || w === 0) continue;
          x += w * framePosition[base + 3 * i];
          y += w * framePosition[base + 3 * i + 1];
          z += w * framePosition[base + 3 * i + 2];
        }
        positions[3 * v] = x; positions[3 * v + 1] = y; positions[3 * v + 2] = z;
      }
      geometry.attributes.position.needsUpdate = true;
      geometry.computeVertexNormals();
      geometry.computeBoundingBox();
    });
  }
  return { group, updates, counts };
}

let scene3d = null;
async function setupScene() {
  const THREE = await import('three');
  const { OrbitControls } = await import('three/addons/controls/OrbitControls.js');

  const gravity = new THREE.Vector3(...data.gravity);
  const up = gravity.lengthSq() > 0 ? gravity.clone().negate().normalize() : new THREE.Vector3(0, 0, 1);
  THREE.Object3D.DEFAULT_UP.copy(up);

  const scene = new THREE.Scene();
  const bounds = runBounds();
  // The robots' shapes, and their extent over the run (some frames of it) in the bounds.
  const robotsView = await buildRobots(THREE);
  scene.add(robotsView.group);
  const shapesView = buildObjectShapes(THREE);
  robotsView.group.add(shapesView.group);
  if (robotsView.holders.length > 0 || shapesView.updates.length > 0) {
    const box = new THREE.Box3();
    const samples = Math.min(frameCount, 24);
    for (let k = 0; k < samples; ++k) {
      const frame = Math.round((k * (frameCount - 1)) / Math.max(samples - 1, 1));
      placeRobots(robotsView, frame);
      for (const place of shapesView.updates) place(frame * particleCount * 3);
      robotsView.group.updateMatrixWorld(true);
      box.expandByObject(robotsView.group);
    }
    if (!box.isEmpty()) {
      const hadParticles = particleCount > 0 && Number.isFinite(bounds.lo[0]) && !bounds.fallback;
      for (let d = 0; d < 3; ++d) {
        bounds.lo[d] = hadParticles ? Math.min(bounds.lo[d], box.min.getComponent(d)) : box.min.getComponent(d);
        bounds.hi[d] = hadParticles ? Math.max(bounds.hi[d], box.max.getComponent(d)) : box.max.getComponent(d);
      }
    }
  }
  const centre = new THREE.Vector3(...bounds.lo).add(new THREE.Vector3(...bounds.hi)).multiplyScalar(0.5);
  const size = Math.max(new THREE.Vector3(...bounds.hi).sub(new THREE.Vector3(...bounds.lo)).length(), 1e-3);
  // Typical particle radius (non-virtual): the size of markers.
  const realRadii = radius.filter((r, i) => !isVirtualParticle(i) && r > 0).sort((a, b) => a - b);
  const typicalRadius = realRadii.length > 0 ? realRadii[realRadii.length >> 1] : 0.01 * size;
  const markerSize = Math.max(typicalRadius, 0.006 * size);

  // Lights: sky/ground fill and a key light from above.
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8f99, 1.6));
  const key = new THREE.DirectionalLight(0xffffff, 1.8);
  key.position.copy(up).multiplyScalar(2 * size).add(new THREE.Vector3(size, size * 0.6, 0));
  scene.add(key);

  const counts = {
    planes: 0, heightfields: 0, heightfieldTriangles: 0, boxes: 0, spheres: 0, securityShells: 0,
    virtualObstacles: 0, goals: 0, goalMarkers: 0, paths: 0, attractors: attractorIndex.length,
    connectors: connectorIndex.length,
  };
  const environmentGroup = new THREE.Group();
  environmentGroup.name = 'environment';
  scene.add(environmentGroup);
  const goalGroup = new THREE.Group();
  goalGroup.name = 'goals';
  scene.add(goalGroup);

  // Grid spacing 1-2-5 × 10^n for about 16 cells over the scene.
  const spanDesired = 2.5 * size;
  const cell = Plot.ticks(0, spanDesired, 16)[1] || 1;
  const divisions = Math.max(4, Math.ceil(spanDesired / cell / 2) * 2);
  const snap = (v) => new THREE.Vector3(Math.round(v.x / cell) * cell, Math.round(v.y / cell) * cell,
    Math.round(v.z / cell) * cell);
  const grids = [];

  // Planes (ground, walls): a light square with a grid, centred where the scene projects on it.
  for (const p of environment.planes) {
    const normal = new THREE.Vector3(...p.normal).normalize();
    const point = new THREE.Vector3(...p.point);
    const foot = centre.clone().sub(normal.clone().multiplyScalar(centre.clone().sub(point).dot(normal)));
    const quad = new THREE.Mesh(new THREE.PlaneGeometry(divisions * cell, divisions * cell),
      new THREE.MeshStandardMaterial({ color: worldColour.plane, roughness: 0.95, side: THREE.DoubleSide,
        transparent: true, opacity: 0.75, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 }));
    quad.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), normal);
    quad.position.copy(foot);
    quad.userData.kind = 'plane';
    environmentGroup.add(quad);
    const grid = new THREE.GridHelper(divisions * cell, divisions, worldColour.planeGrid, worldColour.planeGrid);
    grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), normal);
    grid.position.copy(foot);
    grids.push(grid);
    scene.add(grid);
    ++counts.planes;
  }
  // Without a plane in the world, a reference grid just below the scene (normal to "up").
  if (environment.planes.length === 0) {
    const grid = new THREE.GridHelper(divisions * cell, divisions, 0x98a2b3, 0xc8cfd8);
    grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), up);
    let lowest = Infinity;
    for (let corner = 0; corner < 8; ++corner) {
      const p = [0, 1, 2].map((d) => ((corner >> d) & 1 ? bounds.hi[d] : bounds.lo[d]));
      lowest = Math.min(lowest, new THREE.Vector3(...p).dot(up));
    }
    // Through the origin when the scene reaches it (the classic ground), else under the scene.
    const level = world ? lowest - 0.002 * size : Math.min(0, lowest);
    const onGround = centre.clone().sub(up.clone().multiplyScalar(centre.dot(up) - level));
    grid.position.copy(snap(onGround.clone().sub(up.clone().multiplyScalar(onGround.dot(up)))))
      .add(up.clone().multiplyScalar(level));
    grids.push(grid);
    scene.add(grid);
  }

  // The x (red), y (green), z (blue) axes at the origin, with the grid toggle.
  const axes = new THREE.AxesHelper(Math.max(cell, 0.1 * size));
  grids.push(axes);
  scene.add(axes);

  // Heightfields z = h(x, y): a shaded surface coloured by height, with its grid lines.
  for (const h of environment.heightfields) {
    const { columns, rows } = h;
    if (!(columns >= 2 && rows >= 2) || h.heights.length !== columns * rows) continue;
    let zLo = Infinity;
    let zHi = -Infinity;
    for (const z of h.heights) { zLo = Math.min(zLo, z); zHi = Math.max(zHi, z); }
    const positions = new Float32Array(columns * rows * 3);
    const colours = new Float32Array(columns * rows * 3);
    for (let j = 0; j < rows; ++j) {
      for (let i = 0; i < columns; ++i) {
        const v = j * columns + i;
        const z = h.heights[v];
        positions.set([h.origin[0] + i * h.cellSize[0], h.origin[1] + j * h.cellSize[1], z], 3 * v);
        const w = zHi > zLo ? (z - zLo) / (zHi - zLo) : 0;
        colours.set([0, 1, 2].map((c) => worldColour.terrainLow[c] + w * (worldColour.terrainHigh[c] - worldColour.terrainLow[c])), 3 * v);
      }
    }
    const index = [];
    for (let j = 0; j + 1 < rows; ++j) {
      for (let i = 0; i + 1 < columns; ++i) {
        const v = j * columns + i;
        index.push(v, v + 1, v + columns + 1, v, v + columns + 1, v + columns);
      }
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    geometry.setIndex(index);
    geometry.computeVertexNormals();
    const mesh = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.95,
      side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 }));
    mesh.userData.kind = 'heightfield';
    environmentGroup.add(mesh);
    // Grid lines along rows and columns (not for a large terrain: a haze of lines).
    const lines = [];
    for (let j = 0; j < rows && columns * rows <= 40000; ++j) {
      for (let i = 0; i + 1 < columns; ++i) lines.push(...positions.slice(3 * (j * columns + i), 3 * (j * columns + i) + 6));
    }
    for (let i = 0; i < columns && columns * rows <= 40000; ++i) {
      for (let j = 0; j + 1 < rows; ++j) {
        lines.push(...positions.slice(3 * (j * columns + i), 3 * (j * columns + i) + 3),
          ...positions.slice(3 * ((j + 1) * columns + i), 3 * ((j + 1) * columns + i) + 3));
      }
    }
    const lineGeometry = new THREE.BufferGeometry();
    lineGeometry.setAttribute('position', new THREE.BufferAttribute(Float32Array.from(lines), 3));
    environmentGroup.add(new THREE.LineSegments(lineGeometry,
      new THREE.LineBasicMaterial({ color: 0x5f6b52, transparent: true, opacity: 0.35 })));
    ++counts.heightfields;
    counts.heightfieldTriangles += index.length / 3;
  }

  // Items that appear during the run (virtual obstacles): shown from their time on.
  const timed = [];
  const securityMaterial = new THREE.MeshStandardMaterial({ color: worldColour.security, transparent: true,
    opacity: 0.3, depthWrite: false, roughness: 0.6 });
  const virtualMaterial = new THREE.MeshStandardMaterial({ color: worldColour.virtualObstacle, transparent: true,
    opacity: 0.35, depthWrite: false, roughness: 0.5 });

  // Boxes: solid; a robotics obstacle's security distance as a translucent shell.
  for (const b of environment.boxes) {
    const margin = b.securityDistance || 0;
    const basis = new THREE.Matrix4().makeBasis(new THREE.Vector3(...b.axes[0]), new THREE.Vector3(...b.axes[1]),
      new THREE.Vector3(...b.axes[2]));
    const make = (half, material) => {
      const mesh = new THREE.Mesh(new THREE.BoxGeometry(2 * half[0], 2 * half[1], 2 * half[2]), material);
      mesh.quaternion.setFromRotationMatrix(basis);
      mesh.position.set(...b.center);
      return mesh;
    };
    const core = b.halfExtents.map((v) => Math.max(v - margin, 1e-9));
    const solid = make(core, b.virtual ? virtualMaterial
      : new THREE.MeshStandardMaterial({ color: worldColour.box, roughness: 0.8, transparent: true, opacity: 0.92 }));
    solid.userData.kind = b.virtual ? 'virtual obstacle' : 'box';
    environmentGroup.add(solid);
    if (b.virtual) { timed.push({ object: solid, time: b.addedAt }); ++counts.virtualObstacles; } else ++counts.boxes;
    if (margin > 0) {
      const shell = make(b.halfExtents, securityMaterial);
      environmentGroup.add(shell);
      ++counts.securityShells;
    }
  }
  // Spheres: the same; virtual obstacles of the escape task in violet.
  for (const sp of environment.spheres) {
    const margin = sp.securityDistance || 0;
    const make = (r, material) => {
      const mesh = new THREE.Mesh(new THREE.SphereGeometry(r, 40, 24), material);
      mesh.position.set(...sp.center);
      return mesh;
    };
    const solid = make(Math.max(sp.radius - margin, 1e-9), sp.virtual ? virtualMaterial
      : new THREE.MeshStandardMaterial({ color: worldColour.sphere, roughness: 0.6 }));
    solid.userData.kind = sp.virtual ? 'virtual obstacle' : 'sphere';
    environmentGroup.add(solid);
    if (sp.virtual) { timed.push({ object: solid, time: sp.addedAt }); ++counts.virtualObstacles; } else ++counts.spheres;
    if (margin > 0) {
      environmentGroup.add(make(sp.radius, securityMaterial));
      ++counts.securityShells;
    }
  }

  // Goals: the goal pose (a green sphere of the goal's tolerance and a marker);
  // the attractors from the robot to its virtual copy follow the frames.
  const goalMaterial = new THREE.MeshStandardMaterial({ color: worldColour.goal, transparent: true, opacity: 0.3,
    depthWrite: false });
  const markerMaterial = new THREE.MeshStandardMaterial({ color: worldColour.goal, roughness: 0.4 });
  for (const g of goals) {
    for (const p of g.positions || []) {
      // At least a little larger than a particle, so that a robot at its goal does not hide it.
      const tolerance = new THREE.Mesh(new THREE.SphereGeometry(Math.max(g.tolerance || 0, 1.4 * markerSize), 24, 16),
        goalMaterial);
      tolerance.position.set(...p);
      goalGroup.add(tolerance);
      const marker = new THREE.Mesh(new THREE.OctahedronGeometry(0.9 * markerSize), markerMaterial);
      marker.position.set(...p);
      marker.userData.kind = 'goal';
      goalGroup.add(marker);
      ++counts.goalMarkers;
    }
    ++counts.goals;
  }
  // Paths of motion generation: a line segment or a circle.
  const pathMaterial = new THREE.LineBasicMaterial({ color: worldColour.path });
  for (const p of paths) {
    let points = [];
    if (p.type === 'line') {
      points = [new THREE.Vector3(...p.from), new THREE.Vector3(...p.to)];
    } else if (p.type === 'arc') {
      const n = new THREE.Vector3(...(p.normal || [0, 0, 1])).normalize();
      const u = new THREE.Vector3().crossVectors(n, Math.abs(n.x) < 0.9 ? new THREE.Vector3(1, 0, 0)
        : new THREE.Vector3(0, 1, 0)).normalize();
      const v = new THREE.Vector3().crossVectors(n, u);
      const c = new THREE.Vector3(...p.center);
      for (let k = 0; k <= 128; ++k) {
        const a = (2 * Math.PI * k) / 128;
        points.push(c.clone().addScaledVector(u, p.radius * Math.cos(a)).addScaledVector(v, p.radius * Math.sin(a)));
      }
      const hub = new THREE.Mesh(new THREE.OctahedronGeometry(0.6 * markerSize), new THREE.MeshBasicMaterial({ color: worldColour.path }));
      hub.position.copy(c);
      goalGroup.add(hub);
    } else continue;
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(points), pathMaterial);
    line.userData.kind = 'path';
    goalGroup.add(line);
    ++counts.paths;
  }

  // Particles: one instanced sphere mesh, unit sphere scaled by each radius
  // (virtual particles, 0.1 mm, as goal-coloured markers).
  const sphere = new THREE.SphereGeometry(1, 24, 16);
  const material = new THREE.MeshStandardMaterial({ roughness: 0.45, metalness: 0.05 });
  const spheres = new THREE.InstancedMesh(sphere, material, Math.max(particleCount, 1));
  spheres.count = particleCount;
  spheres.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
  spheres.frustumCulled = false;
  const colour = new THREE.Color();
  const shownRadius = new Float64Array(particleCount);
  for (let i = 0; i < particleCount; ++i) {
    const virtual = isVirtualParticle(i);
    colour.set(virtual ? virtualColour : fixedFlag[i] ? fixedColour : objectColour(objectOf[i]));
    spheres.setColorAt(i, colour);
    shownRadius[i] = virtual ? Math.max(radius[i], 0.35 * markerSize) : radius[i];
  }
  scene.add(spheres);

  // Connectors: line segments coloured by strain (blue compressed, grey at rest, red stretched).
  const linkPositions = new Float32Array(connectorIndex.length * 6);
  const linkColours = new Float32Array(connectorIndex.length * 6);
  const linkGeometry = new THREE.BufferGeometry();
  linkGeometry.setAttribute('position', new THREE.BufferAttribute(linkPositions, 3).setUsage(THREE.DynamicDrawUsage));
  linkGeometry.setAttribute('color', new THREE.BufferAttribute(linkColours, 3).setUsage(THREE.DynamicDrawUsage));
  const links = new THREE.LineSegments(linkGeometry, new THREE.LineBasicMaterial({ vertexColors: true }));
  links.frustumCulled = false;
  scene.add(links);
  // Attractors (goal, path, finger tips): thin green lines, no strain colour.
  const pullPositions = new Float32Array(attractorIndex.length * 6);
  const pullGeometry = new THREE.BufferGeometry();
  pullGeometry.setAttribute('position', new THREE.BufferAttribute(pullPositions, 3).setUsage(THREE.DynamicDrawUsage));
  const pulls = new THREE.LineSegments(pullGeometry, new THREE.LineBasicMaterial({ color: worldColour.attractor,
    transparent: true, opacity: 0.7 }));
  pulls.frustumCulled = false;
  scene.add(pulls);
  const strainScale = Math.max(maxStrain(), 1e-6);
  if (connectorIndex.length > 0) {
    const row = document.createElement('div');
    row.innerHTML = `strain −${formatNumber(100 * strainScale, 2)}%<span class="bar"></span>+${formatNumber(100 * strainScale, 2)}%`;
    row.title = 'connector strain (length − rest) / rest, over the connectors (goal and tip attractors left out)';
    row.id = 'strain-legend';
    $('legend').appendChild(row);
  }
  // World legend entries.
  const legendLine = (css, text) => {
    const row = document.createElement('div');
    row.innerHTML = `<span class="swatch" style="${css}"></span>`;
    row.append(text);
    $('legend').appendChild(row);
  };
  const hex = (c) => `#${c.toString(16).padStart(6, '0')}`;
  if (counts.heightfields > 0) legendLine('background:linear-gradient(#b08d5c,#8cae73);border-radius:2px', 'terrain');
  if (counts.boxes + counts.spheres > 0) legendLine(`background:${hex(worldColour.box)};border-radius:2px`, 'obstacles');
  if (counts.securityShells > 0) legendLine(`background:${hex(worldColour.security)};opacity:0.5`, 'security distance');
  if (counts.virtualObstacles > 0) legendLine(`background:${hex(worldColour.virtualObstacle)};opacity:0.6`, 'virtual obstacles (escape)');
  if (counts.goals > 0) legendLine(`background:${hex(worldColour.goal)}`, 'goal (tolerance)');
  if (counts.paths > 0) legendLine(`background:${hex(worldColour.path)};border-radius:0;height:3px`, 'path');

  // Contact forces: a segment from the contact point along the normal force
  // (red) and, when the run has it, the friction force (orange).
  let maxForce = 0;
  for (const group of contactGroups) {
    for (const r of group.rows) {
      maxForce = Math.max(maxForce, Math.hypot(r[normalColumns[0]], r[normalColumns[1]], r[normalColumns[2]]) || 0);
      if (frictionColumns) {
        maxForce = Math.max(maxForce, Math.hypot(r[frictionColumns[0]], r[frictionColumns[1]], r[frictionColumns[2]]) || 0);
      }
    }
  }
  const forceScale = maxForce > 0 ? (0.15 * size) / maxForce : 0;
  const maxContacts = contactGroups.reduce((m, g) => Math.max(m, g.rows.length), 0);
  const contactPositions = new Float32Array(Math.max(maxContacts, 1) * 6);
  const contactGeometry = new THREE.BufferGeometry();
  contactGeometry.setAttribute('position', new THREE.BufferAttribute(contactPositions, 3).setUsage(THREE.DynamicDrawUsage));
  const contacts = new THREE.LineSegments(contactGeometry, new THREE.LineBasicMaterial({ color: 0xd62728 }));
  contacts.frustumCulled = false;
  scene.add(contacts);
  const contactPoints = new THREE.Points(contactGeometry, new THREE.PointsMaterial({ color: 0xd62728, size: 5, sizeAttenuation: false }));
  contactPoints.frustumCulled = false;
  scene.add(contactPoints);
  const frictionPositions = new Float32Array(Math.max(maxContacts, 1) * 6);
  const frictionGeometry = new THREE.BufferGeometry();
  frictionGeometry.setAttribute('position', new THREE.BufferAttribute(frictionPositions, 3).setUsage(THREE.DynamicDrawUsage));
  const friction = new THREE.LineSegments(frictionGeometry, new THREE.LineBasicMaterial({ color: worldColour.friction }));
  friction.frustumCulled = false;
  scene.add(friction);
  if (frictionColumns) {
    const row = document.createElement('div');
    row.innerHTML = '<span class="swatch" style="background:#d62728;border-radius:0;height:3px"></span>normal force ' +
      '<span class="swatch" style="background:#ff7f0e;border-radius:0;height:3px;margin-left:6px"></span>friction';
    $('legend').appendChild(row);
  }
  const shown = { contacts: 0, friction: 0, virtualObstacles: 0 };

  const matrix = new THREE.Matrix4();
  const frameInterval = frameCount > 1 ? (tEnd - tStart) / (frameCount - 1) : Infinity;
  function update(frame) {
    const base = frame * particleCount * 3;
    placeRobots(robotsView, frame);
    for (const place of shapesView.updates) place(frame * particleCount * 3);
    const particleLayer = $('show-particles').checked;
    for (let i = 0; i < particleCount; ++i) {
      const r = particleLayer || !carriesVisual[i] ? shownRadius[i] : 0;
      matrix.makeScale(r, r, r);
      matrix.setPosition(framePosition[base + 3 * i], framePosition[base + 3 * i + 1], framePosition[base + 3 * i + 2]);
      spheres.setMatrixAt(i, matrix);
    }
    spheres.instanceMatrix.needsUpdate = true;
    // The n-th segment of `positions` from spring s's particle a to its particle b.
    const placeSpring = (positions, s, n) => {
      const a = base + 3 * linear[3 * s];
      const b = base + 3 * linear[3 * s + 1];
      for (let d = 0; d < 3; ++d) {
        positions[6 * n + d] = framePosition[a + d];
        positions[6 * n + 3 + d] = framePosition[b + d];
      }
    };
    connectorIndex.forEach((s, n) => {
      placeSpring(linkPositions, s, n);
      const x = Math.max(-1, Math.min(1, strainOf(frame, s) / strainScale));
      // dark grey (0.22, 0.24, 0.27) toward red (0.85, 0.15, 0.10) or blue (0.10, 0.35, 0.85)
      const to = x >= 0 ? [0.85, 0.15, 0.10] : [0.10, 0.35, 0.85];
      const w = Math.abs(x);
      const rgb = [0.22 + w * (to[0] - 0.22), 0.24 + w * (to[1] - 0.24), 0.27 + w * (to[2] - 0.27)];
      linkColours.set(rgb, 6 * n);
      linkColours.set(rgb, 6 * n + 3);
    });
    linkGeometry.attributes.position.needsUpdate = true;
    linkGeometry.attributes.color.needsUpdate = true;
    attractorIndex.forEach((s, n) => placeSpring(pullPositions, s, n));
    pullGeometry.attributes.position.needsUpdate = true;
    // Virtual obstacles from the frame at which they appeared.
    shown.virtualObstacles = 0;
    for (const item of timed) {
      item.object.visible = !(frameTime[frame] + 1e-9 < item.time);
      if (item.object.visible) ++shown.virtualObstacles;
    }
    // The contact group at this frame: the latest one not older than a frame.
    let nContacts = 0;
    let nFriction = 0;
    if (contactGroups.length > 0) {
      const g = indexAtOrBefore(contactGroups.map((c) => c.t), frameTime[frame]);
      const group = contactGroups[g];
      if (group.t <= frameTime[frame] + 1e-9 && group.t > frameTime[frame] - frameInterval) {
        for (const row of group.rows) {
          const a = row[contactA];
          const b = row[contactB];
          const fn = normalColumns.map((c) => row[c]);
          if (!(a >= 0 && a < particleCount)) continue;
          const pa = base + 3 * a;
          let p;
          if (b >= 0 && b < particleCount) {
            const pb = base + 3 * b;
            p = [0, 1, 2].map((d) => 0.5 * (framePosition[pa + d] + framePosition[pb + d]));
          } else {
            // Against the environment: the point of the sphere facing the normal force.
            const f = Math.hypot(...fn) || 1;
            p = fn.map((v, d) => framePosition[pa + d] - radius[a] * v / f);
          }
          if (!p.every(Number.isFinite)) continue;
          contactPositions.set(p, 6 * nContacts);
          contactPositions.set([p[0] + forceScale * fn[0], p[1] + forceScale * fn[1], p[2] + forceScale * fn[2]], 6 * nContacts + 3);
          ++nContacts;
          if (frictionColumns) {
            const ft = frictionColumns.map((c) => row[c]);
            if (ft.every(Number.isFinite) && Math.hypot(...ft) > 0) {
              frictionPositions.set(p, 6 * nFriction);
              frictionPositions.set([p[0] + forceScale * ft[0], p[1] + forceScale * ft[1], p[2] + forceScale * ft[2]], 6 * nFriction + 3);
              ++nFriction;
            }
          }
        }
      }
    }
    shown.contacts = nContacts;
    shown.friction = nFriction;
    contactGeometry.setDrawRange(0, 2 * nContacts);
    contactGeometry.attributes.position.needsUpdate = true;
    frictionGeometry.setDrawRange(0, 2 * nFriction);
    frictionGeometry.attributes.position.needsUpdate = true;
  }

  // Camera framing the whole scene (objects, environment, goals) from a three-quarter view.
  const camera = new THREE.PerspectiveCamera(40, 1, size * 1e-3, size * 100);
  const side = Math.abs(up.x) < 0.9 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 1, 0);
  const across = new THREE.Vector3().crossVectors(up, side).normalize();
  // Higher above a flat scene (an arm in a plane), lower beside a tall one.
  const extent = new THREE.Vector3(...bounds.hi).sub(new THREE.Vector3(...bounds.lo));
  const height = Math.abs(extent.dot(up));
  const flat = height < 0.25 * extent.length();
  const homeDirection = new THREE.Vector3().addScaledVector(side, 1.1).addScaledVector(across, -1.6)
    .addScaledVector(up, flat ? 1.6 : 0.8).normalize();
  // The bounding sphere's radius is size/2; distance so that it fits the smaller field of view.
  const fitDistance = (aspect) => {
    const vertical = THREE.MathUtils.degToRad(camera.fov) / 2;
    const horizontal = Math.atan(Math.tan(vertical) * aspect);
    return (0.5 * size) / Math.sin(Math.min(vertical, horizontal)) * 1.05;
  };

  let renderer = null;
  let controls = null;
  if (webglAvailable()) {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0x000000, 0);
    $('view').appendChild(renderer.domElement);
    controls = new OrbitControls(camera, renderer.domElement);
    controls.enableDamping = true;
    controls.screenSpacePanning = true;
  } else {
    showViewMessage('This browser gave no WebGL context, so the 3D view is off. ' +
      'The plots, the time scrubber and the data are all here.');
  }
  function resetView() {
    const w = $('view').clientWidth || 1;
    const h = $('view').clientHeight || 1;
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    camera.position.copy(homeDirection).multiplyScalar(fitDistance(camera.aspect)).add(centre);
    camera.up.copy(up);
    camera.lookAt(centre);
    if (controls) { controls.target.copy(centre); controls.update(); }
  }
  resetView();
  $('reset-view').addEventListener('click', resetView);
  // Looks at `target` (m) from `distance` (m) along the home direction, or one
  // `elevation` high (the weight of "up" in it; test hook, screenshots).
  function setView(target, distance, elevation) {
    const at = new THREE.Vector3(...target);
    const direction = elevation === undefined ? homeDirection : new THREE.Vector3().addScaledVector(side, 1.1)
      .addScaledVector(across, -1.6).addScaledVector(up, elevation).normalize();
    camera.position.copy(direction).multiplyScalar(distance).add(at);
    camera.up.copy(up);
    camera.lookAt(at);
    if (controls) { controls.target.copy(at); controls.update(); }
  }

  const setVisible = () => {
    links.visible = $('show-connectors').checked;
    robotsView.group.visible = $('show-robots').checked;
    pulls.visible = $('show-connectors').checked && $('show-goals').checked;
    contacts.visible = contactPoints.visible = friction.visible = $('show-contacts').checked;
    for (const grid of grids) grid.visible = $('show-grid').checked;
    environmentGroup.visible = $('show-environment').checked;
    goalGroup.visible = $('show-goals').checked;
  };
  for (const id of ['show-connectors', 'show-contacts', 'show-grid', 'show-environment', 'show-goals',
    'show-robots']) {
    $(id).addEventListener('change', setVisible);
  }
  $('show-particles').addEventListener('change', () => update(view.frame));
  setVisible();

  function render() {
    if (!renderer) return;
    const w = $('view').clientWidth;
    const h = $('view').clientHeight;
    const canvas = renderer.domElement;
    if (canvas.width !== Math.round(w * renderer.getPixelRatio()) || canvas.height !== Math.round(h * renderer.getPixelRatio())) {
      renderer.setSize(w, h, false);
      canvas.style.width = '100%';
      canvas.style.height = '100%';
      camera.aspect = w / Math.max(h, 1);
      camera.updateProjectionMatrix();
    }
    if (controls) controls.update();
    renderer.render(scene, camera);
  }
  // The screen box of the robots' pixels alone (the rest hidden for one render): the
  // fraction of the view's width and height it spans, and of its area.
  function robotPixelBox() {
    if (!renderer || robotsView.holders.length === 0) return null;
    const hidden = [];
    for (const child of scene.children) {
      if (child !== robotsView.group && child.visible && !child.isLight) { hidden.push(child); child.visible = false; }
    }
    render();
    const canvas = renderer.domElement;
    const copy = document.createElement('canvas');
    copy.width = canvas.width;
    copy.height = canvas.height;
    const context = copy.getContext('2d');
    context.drawImage(canvas, 0, 0);
    const pixels = context.getImageData(0, 0, copy.width, copy.height).data;
    for (const child of hidden) child.visible = true;
    render();
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity, lit = 0;
    for (let y = 0; y < copy.height; ++y) {
      for (let x = 0; x < copy.width; ++x) {
        if (pixels[4 * (y * copy.width + x) + 3] === 0) continue;
        ++lit;
        x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
      }
    }
    if (lit === 0) return { width: 0, height: 0, area: 0, lit: 0 };
    const width = (x1 - x0 + 1) / copy.width;
    const height = (y1 - y0 + 1) / copy.height;
    return { width, height, area: width * height, lit: lit / (copy.width * copy.height) };
  }
  // After "reset view", the 3D view drawn into a canvas `width` pixels wide (the
  // browser's smoothing averages the pixels away), as a PNG data: URL.
  function viewImage(width) {
    if (!renderer) return null;
    resetView();
    render();
    const canvas = renderer.domElement;
    const copy = document.createElement('canvas');
    copy.width = Math.max(1, Math.round(width));
    copy.height = Math.max(1, Math.round(width * canvas.height / Math.max(canvas.width, 1)));
    const context = copy.getContext('2d');
    context.imageSmoothingEnabled = true;
    context.imageSmoothingQuality = 'high';
    context.drawImage(canvas, 0, 0, copy.width, copy.height);
    return copy.toDataURL('image/png');
  }
  return {
    spheres, update, render, setView, webgl: Boolean(renderer), counts, shown, strainScale,
    frictionDrawn: Boolean(frictionColumns), robotCounts: robotsView.counts, robotPixelBox, resetView,
    viewImage,
    shapeCounts: shapesView.counts,
    // For the live view's drag (viewer/live.js).
    THREE, scene, camera, controls, canvas: renderer ? renderer.domElement : null,
  };
}

try {
  scene3d = await setupScene();
  listeners.push((frame) => scene3d.update(frame));
} catch (error) {
  showViewMessage(`The 3D view could not start (${error.message}). The plots and the time scrubber still work.`);
  console.warn('robophi replay: 3D view unavailable:', error);
}

// ---------------------------------------------------------------- the live view
// Served by `robophi run --live` or world.view() (docs/viewer.md "Live view"): the
// page holds one frame, which viewer/live.js overwrites with each frame that comes.
let live = null;
if (data.live) {
  const { startLive } = await import('robophi/live.js');
  live = startLive({
    data, $, particleCount, framePosition, frameTime, radius, fixedFlag, treeCarried, isVirtualParticle, scene3d,
    ticks: Plot.ticks, formatNumber, addLegendEntry,
    showFrame: (t) => {
      view.time = t;
      view.frame = 0;
      for (const listener of listeners) listener(0);
    },
  });
}

// ---------------------------------------------------------------- the loop
let lastWall = null;
function tick(now) {
  if (view.playing) {
    const elapsed = lastWall === null ? 0 : (now - lastWall) / 1000;
    let t = view.time + elapsed * view.speed;
    if (t >= tEnd) {
      if (view.loop) t = tStart + (t - tEnd) % Math.max(tEnd - tStart, 1e-12);
      else { t = tEnd; setPlaying(false); }
    }
    showTime(t);
  }
  lastWall = now;
  if (scene3d) scene3d.render();
  requestAnimationFrame(tick);
}
// A moment to show from the address: replay.html#t=2.0 (s).
function timeFromAddress() {
  const match = /(?:^#|[#&])t=([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)/.exec(window.location.hash);
  return match && Number.isFinite(Number(match[1])) ? Number(match[1]) : null;
}
showTime(timeFromAddress() ?? tStart);
window.addEventListener('hashchange', () => {
  const t = timeFromAddress();
  if (t !== null) { setPlaying(false); showTime(t); }
});
requestAnimationFrame(tick);

// ---------------------------------------------------------------- test hook
window.robophiReplay = {
  /** Spheres in the scene (0 when three.js could not start). */
  sphereCount: () => (scene3d ? scene3d.spheres.count : 0),
  frameCount: () => frameCount,
  /** Shows the frame at time t (the last frame at or before t); returns its time. */
  seek: (t) => {
    setPlaying(false);
    showTime(t);
    if (scene3d) scene3d.render();
    return frameTime[view.frame];
  },
  /** [x, y, z] of every particle in the displayed frame. */
  currentPositions: () => {
    const base = view.frame * particleCount * 3;
    return Array.from({ length: particleCount },
      (_, i) => [framePosition[base + 3 * i], framePosition[base + 3 * i + 1], framePosition[base + 3 * i + 2]]);
  },
  frameTimes: () => Array.from(frameTime),
  plotSeries: () => plotSeriesNames.slice(),
  /** The values a plot draws for series `name` (the joint plot's: q), as numbers. */
  plotValues: (name) => {
    for (const plot of plots) for (const s of plot.series) if (s.name === name) return Array.from(s.v);
    return null;
  },
  webgl: () => Boolean(scene3d && scene3d.webgl),
  /** What the scene graph holds of the world: {planes, heightfields, heightfieldTriangles,
   * boxes, spheres, securityShells, virtualObstacles, goals, goalMarkers, paths,
   * attractors, connectors} (all 0 when three.js could not start). */
  worldCounts: () => (scene3d ? { ...scene3d.counts } : {}),
  /** Drawn at the displayed frame: {contacts, friction, virtualObstacles}. */
  shownCounts: () => (scene3d ? { ...scene3d.shown } : {}),
  /** The strain legend's scale: the largest |strain| of a connector over the run (-). */
  strainScale: () => (scene3d ? scene3d.strainScale : NaN),
  /** Whether the contact rows carry friction forces that are drawn. */
  frictionDrawn: () => Boolean(scene3d && scene3d.frictionDrawn),
  /** Looks at target [x, y, z] (m) from `distance` (m) along the home view direction
   * (or one of the given elevation, the weight of "up" against 1.1 and 1.6 across). */
  setView: (target, distance, elevation) => {
    if (scene3d) { scene3d.setView(target, distance, elevation); scene3d.render(); }
  },
  /** The robots' visuals: {visuals, drawn, meshes, shapes, missing, meshTriangles: {meshFile index:
   * triangles parsed}} (docs/viewer.md). */
  robotCounts: () => (scene3d ? { ...scene3d.robotCounts } : {}),
  /** The objects' shapes drawn: {rims, surfaceTriangles}. */
  shapeCounts: () => (scene3d ? { ...scene3d.shapeCounts } : {}),
  /** After "reset view": the screen box of the robots' own pixels, {width, height, area}
   * as fractions of the view, and `lit`, the fraction of its pixels they cover (null: none). */
  robotPixelBox: () => {
    if (!scene3d) return null;
    scene3d.resetView();
    return scene3d.robotPixelBox();
  },
  /** After "reset view": the 3D view scaled to `width` pixels wide, a PNG data: URL
   * (null without WebGL); the reference images' test (tests/viewer/reference.test.mjs). */
  viewImage: (width) => (scene3d ? scene3d.viewImage(width) : null),
  /** Whether the page has the run's world description (world.json). */
  hasWorld: () => Boolean(world),
  /** The live view's hook (viewer/live.js), or null on a replay page. */
  live: () => live,
  ready: true,
};
document.body.dataset.ready = 'true';
