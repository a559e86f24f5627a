// robophi replay viewer (docs/viewer.md). Inlined into replay.html at build time.
//
// The run data is the JSON in <script id="robophi-data"> (src/output/replay_html.cpp
// writes it). The page works in three layers, so that a browser without WebGL
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

const num = (v) => (v === null ? NaN : v);
const frameRows = data.frames.rows;
const frameCount = frameRows.length;
const frameTime = new Float64Array(frameCount);
const framePosition = new Float64Array(frameCount * particleCount * 3);  // (frame, particle, xyz)
frameRows.forEach((row, k) => {
  frameTime[k] = num(row[0]);
  const base = k * particleCount * 3;
  for (let v = 1; v < row.length; ++v) framePosition[base + v - 1] = num(row[v]);
});
const tStart = frameTime[0];
const tEnd = frameTime[frameCount - 1];

// A table of rows as named columns of Float64Array.
function columnsOf(table) {
  const out = {};
  table.columns.forEach((name, c) => {
    out[name] = Float64Array.from(table.rows, (row) => num(row[c]));
  });
  return out;
}
const energy = columnsOf(data.energy);
const joints = data.joints ? columnsOf(data.joints) : null;
const jointNames = data.joints ? data.joints.columns.slice(1) : [];

// Contacts grouped by time: [{t, rows: [[a, b, fx, fy, fz], ...]}], times increasing.
const contactGroups = [];
if (data.contacts) {
  for (const row of data.contacts.rows) {
    const t = num(row[0]);
    if (contactGroups.length === 0 || contactGroups[contactGroups.length - 1].t !== t) {
      contactGroups.push({ t, rows: [] });
    }
    contactGroups[contactGroups.length - 1].rows.push(row.slice(1).map(num));
  }
}

// ---------------------------------------------------------------- helpers
const palette = ['#4e79a7', '#f28e2b', '#59a14f', '#e15759', '#76b7b2', '#edc948', '#b07aa1',
  '#ff9da7', '#9c755f', '#86bcb6'];
const fixedColour = '#4a4f57';
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
  `${particleCount} particles`, `${linkCount} connectors`,
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
class Plot {
  constructor(canvas, legend, series, options = {}) {
    this.canvas = canvas;
    this.legend = legend;  // an element beside the caption: one entry per series with its value
    this.legendValues = series.map((s) => {
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
    });
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

addPlot('plot-energy', [
  { name: 'kinetic', label: 'kinetic', colour: '#e15759', t: energy.t, v: energy.kinetic, unit: 'J' },
  { name: 'potential', label: 'potential', colour: '#4e79a7', t: energy.t, v: energy.potential, unit: 'J' },
  { name: 'dissipated', label: 'dissipated', colour: '#f28e2b', t: energy.t, v: energy.dissipated, unit: 'J' },
  { name: 'total', label: 'total', colour: '#1f2933', t: energy.t, v: energy.total, unit: 'J', dash: [6, 3] },
], { includeZero: true });
addPlot('plot-dt', [
  { name: 'dt', label: 'dt', colour: '#59a14f', t: energy.t, v: energy.dt, unit: 's' },
], { includeZero: false });
if (joints && jointNames.length > 0) {
  const kinds = data.jointKinds || [];
  const unitOf = (j) => (kinds[j] === 'prismatic' ? 'm' : 'rad');
  const units = [...new Set(jointNames.map((_, j) => unitOf(j)))];
  $('joints-caption').textContent = `Joints (${units.join(', ')})`;
  $('fig-joints').hidden = false;
  addPlot('plot-joints', jointNames.map((name, j) => ({
    name, label: name, colour: palette[(j + 4) % palette.length], t: joints.t, v: joints[name], unit: unitOf(j),
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
if (linkCount === 0) {
  $('show-connectors').disabled = true;
  $('show-connectors').parentElement.classList.add('disabled');
}

// Object legend.
{
  const legend = $('legend');
  const objects = data.objects.length > 0 ? data.objects : [{ name: 'particles', kind: '' }];
  objects.forEach((o, i) => {
    const row = document.createElement('div');
    row.innerHTML = `<span class="swatch" style="background:${objectColour(i)}"></span>`;
    row.append(`${o.name}${o.kind ? ` (${o.kind})` : ''}`);
    legend.appendChild(row);
  });
  if (fixedFlag.some((f) => f)) {
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

// Extent of the whole run (every kept frame, plus radii).
function runBounds() {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let k = 0; k < frameCount; ++k) {
    for (let i = 0; i < particleCount; ++i) {
      const base = (k * particleCount + i) * 3;
      for (let d = 0; d < 3; ++d) {
        const v = framePosition[base + d];
        if (!Number.isFinite(v)) continue;
        lo[d] = Math.min(lo[d], v - radius[i]);
        hi[d] = Math.max(hi[d], v + radius[i]);
      }
    }
  }
  if (!Number.isFinite(lo[0])) return { lo: [-1, -1, -1], hi: [1, 1, 1] };
  return { lo, hi };
}

// Largest |strain| of any connector over the run, for the colour scale.
function maxStrain() {
  let largest = 0;
  for (let k = 0; k < frameCount; ++k) {
    for (let s = 0; s < linkCount; ++s) {
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

let scene3d = null;
async function setupScene() {
  const THREE = await import('three');
  const { OrbitControls } = await import('three/addons/controls/OrbitControls.js');

  const gravity = new THREE.Vector3(...data.gravity);
  const up = gravity.lengthSq() > 0 ? gravity.clone().negate().normalize() : new THREE.Vector3(0, 0, 1);
  THREE.Object3D.DEFAULT_UP.copy(up);

  const scene = new THREE.Scene();
  const bounds = runBounds();
  const centre = new THREE.Vector3(...bounds.lo).add(new THREE.Vector3(...bounds.hi)).multiplyScalar(0.5);
  const size = Math.max(new THREE.Vector3(...bounds.hi).sub(new THREE.Vector3(...bounds.lo)).length(), 1e-3);

  // Lights: sky/ground fill and a key light from above.
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8f99, 1.6));
  const key = new THREE.DirectionalLight(0xffffff, 1.8);
  key.position.copy(up).multiplyScalar(2 * size).add(new THREE.Vector3(size, size * 0.6, 0));
  scene.add(key);

  // Ground grid in the plane through the origin normal to `up`, with 1-2-5 spacing.
  const spanDesired = 2.5 * size;
  const cell = Plot.ticks(0, spanDesired, 16)[1] || 1;
  const divisions = Math.max(4, Math.ceil(spanDesired / cell / 2) * 2);
  const grid = new THREE.GridHelper(divisions * cell, divisions, 0x98a2b3, 0xc8cfd8);
  grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), up);
  const centreOnGround = centre.clone().sub(up.clone().multiplyScalar(centre.dot(up)));
  grid.position.set(Math.round(centreOnGround.x / cell) * cell, Math.round(centreOnGround.y / cell) * cell,
    Math.round(centreOnGround.z / cell) * cell);
  scene.add(grid);
  scene.add(new THREE.AxesHelper(Math.max(cell, 0.1 * size)));

  // Particles: one instanced sphere mesh, unit sphere scaled by each radius.
  const sphere = new THREE.SphereGeometry(1, 24, 16);
  const material = new THREE.MeshStandardMaterial({ roughness: 0.45, metalness: 0.05 });
  const spheres = new THREE.InstancedMesh(sphere, material, Math.max(particleCount, 1));
  spheres.count = particleCount;
  spheres.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
  spheres.frustumCulled = false;
  const colour = new THREE.Color();
  for (let i = 0; i < particleCount; ++i) {
    colour.set(fixedFlag[i] ? fixedColour : objectColour(objectOf[i]));
    spheres.setColorAt(i, colour);
  }
  scene.add(spheres);

  // Connectors: line segments coloured by strain (blue compressed, grey at rest, red stretched).
  const linkPositions = new Float32Array(linkCount * 6);
  const linkColours = new Float32Array(linkCount * 6);
  const linkGeometry = new THREE.BufferGeometry();
  linkGeometry.setAttribute('position', new THREE.BufferAttribute(linkPositions, 3).setUsage(THREE.DynamicDrawUsage));
  linkGeometry.setAttribute('color', new THREE.BufferAttribute(linkColours, 3).setUsage(THREE.DynamicDrawUsage));
  const links = new THREE.LineSegments(linkGeometry, new THREE.LineBasicMaterial({ vertexColors: true }));
  links.frustumCulled = false;
  scene.add(links);
  const strainScale = Math.max(maxStrain(), 1e-6);
  if (linkCount > 0) {
    const row = document.createElement('div');
    row.innerHTML = `strain −${formatNumber(100 * strainScale, 2)}%<span class="bar"></span>+${formatNumber(100 * strainScale, 2)}%`;
    row.title = 'connector strain (length − rest) / rest';
    $('legend').appendChild(row);
  }

  // Contact forces: a segment from the contact point along the force.
  let maxForce = 0;
  for (const group of contactGroups) {
    for (const r of group.rows) maxForce = Math.max(maxForce, Math.hypot(r[2], r[3], r[4]) || 0);
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

  const matrix = new THREE.Matrix4();
  const frameInterval = frameCount > 1 ? (tEnd - tStart) / (frameCount - 1) : Infinity;
  function update(frame) {
    const base = frame * particleCount * 3;
    for (let i = 0; i < particleCount; ++i) {
      const r = radius[i];
      matrix.makeScale(r, r, r);
      matrix.setPosition(framePosition[base + 3 * i], framePosition[base + 3 * i + 1], framePosition[base + 3 * i + 2]);
      spheres.setMatrixAt(i, matrix);
    }
    spheres.instanceMatrix.needsUpdate = true;
    for (let s = 0; s < linkCount; ++s) {
      const a = base + 3 * linear[3 * s];
      const b = base + 3 * linear[3 * s + 1];
      for (let d = 0; d < 3; ++d) {
        linkPositions[6 * s + d] = framePosition[a + d];
        linkPositions[6 * s + 3 + d] = framePosition[b + d];
      }
      const x = Math.max(-1, Math.min(1, strainOf(frame, s) / strainScale));
      // dark grey (0.22, 0.24, 0.27) toward red (0.85, 0.15, 0.10) or blue (0.10, 0.35, 0.85)
      const to = x >= 0 ? [0.85, 0.15, 0.10] : [0.10, 0.35, 0.85];
      const w = Math.abs(x);
      const rgb = [0.22 + w * (to[0] - 0.22), 0.24 + w * (to[1] - 0.24), 0.27 + w * (to[2] - 0.27)];
      linkColours.set(rgb, 6 * s);
      linkColours.set(rgb, 6 * s + 3);
    }
    linkGeometry.attributes.position.needsUpdate = true;
    linkGeometry.attributes.color.needsUpdate = true;
    // The contact group at this frame: the latest one not older than a frame.
    let shown = 0;
    if (contactGroups.length > 0) {
      const g = indexAtOrBefore(contactGroups.map((c) => c.t), frameTime[frame]);
      const group = contactGroups[g];
      if (group.t <= frameTime[frame] + 1e-9 && group.t > frameTime[frame] - frameInterval) {
        for (const [a, b, fx, fy, fz] of group.rows) {
          if (!(a >= 0 && a < particleCount)) continue;
          const pa = base + 3 * a;
          let p;
          if (b >= 0 && b < particleCount) {
            const pb = base + 3 * b;
            p = [0, 1, 2].map((d) => 0.5 * (framePosition[pa + d] + framePosition[pb + d]));
          } else {
            // Against the environment: the point of the sphere facing the force.
            const f = Math.hypot(fx, fy, fz) || 1;
            p = [fx, fy, fz].map((v, d) => framePosition[pa + d] - radius[a] * v / f);
          }
          contactPositions.set(p, 6 * shown);
          contactPositions.set([p[0] + forceScale * fx, p[1] + forceScale * fy, p[2] + forceScale * fz], 6 * shown + 3);
          ++shown;
        }
      }
    }
    contactGeometry.setDrawRange(0, 2 * shown);
    contactGeometry.attributes.position.needsUpdate = true;
  }

  // Camera framing the whole run from a three-quarter view.
  const camera = new THREE.PerspectiveCamera(40, 1, size * 1e-3, size * 100);
  const side = Math.abs(up.x) < 0.9 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 1, 0);
  const across = new THREE.Vector3().crossVectors(up, side).normalize();
  const home = new THREE.Vector3().addScaledVector(side, 1.1).addScaledVector(across, -1.6).addScaledVector(up, 0.8)
    .normalize().multiplyScalar(1.25 * size).add(centre);

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
    camera.position.copy(home);
    camera.up.copy(up);
    camera.lookAt(centre);
    if (controls) { controls.target.copy(centre); controls.update(); }
  }
  resetView();
  $('reset-view').addEventListener('click', resetView);

  const setVisible = () => {
    links.visible = $('show-connectors').checked;
    contacts.visible = contactPoints.visible = $('show-contacts').checked;
    grid.visible = $('show-grid').checked;
  };
  for (const id of ['show-connectors', 'show-contacts', 'show-grid']) $(id).addEventListener('change', setVisible);
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
  return { spheres, update, render, webgl: Boolean(renderer) };
}

try {
  scene3d = await setupScene();
  listeners.push((frame) => scene3d.update(frame));
} catch (error) {
  showViewMessage(`The 3D view could not start (${error.message}). The plots and the time scrubber still work.`);
  console.warn('robophi replay: 3D view unavailable:', error);
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
showTime(tStart);
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
  webgl: () => Boolean(scene3d && scene3d.webgl),
  ready: true,
};
document.body.dataset.ready = 'true';
