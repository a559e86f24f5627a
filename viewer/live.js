// robophi live view (docs/viewer.md "Live view"): the replay page fed by a
// WebSocket. viewer/replay.js loads this module when its data object has "live";
// the page holds one frame, which each binary message overwrites.
//
// Protocol (the WebSocket at data.live.socket, on the page's own host):
//   server → page, binary: 8 little-endian float64 [t, step, kinetic, potential,
//     dissipated, external, dragWork, dragged particle or -1], then float32 x, y, z
//     of every particle;
//   server → page, text: {"type":"status", paused, speed, time, dragWork, dragging, ended};
//   page → server, text: {"type":"pause"} | {"type":"resume"} | {"type":"speed","value":k}
//     (model seconds per wall second; 0: as fast as possible) | {"type":"stop"} |
//     {"type":"drag","particle":i,"target":[x,y,z]} | {"type":"release"}.

const kHeaderNumbers = 8;

export function startLive(ctx) {
  const { data, $, particleCount, framePosition, frameTime, radius, fixedFlag, treeCarried, isVirtualParticle, scene3d } = ctx;
  const state = {
    connected: false, ended: false, frames: 0, frameWall: [], time: frameTime[0], step: 0,
    kinetic: 0, potential: 0, dissipated: 0, external: 0, dragWork: 0, status: null, paused: false,
    dragging: -1,
  };

  // ------------------------------------------------------------ the controls
  // The replay's footer becomes the live one: pause/resume, speed, a readout.
  for (const id of ['step-back', 'step-forward', 'scrub', 'loop-label']) $(id).hidden = true;
  const oldPlay = $('play');
  const pauseButton = oldPlay.cloneNode(true);  // without the replay's listeners
  oldPlay.replaceWith(pauseButton);
  const showPaused = (paused) => {
    pauseButton.innerHTML = paused ? '&#9654;' : '&#10074;&#10074;';
    pauseButton.setAttribute('aria-label', paused ? 'resume' : 'pause');
    pauseButton.title = paused ? 'Resume the run (space)' : 'Pause the run (space)';
  };
  showPaused(false);
  const speedSelect = $('speed');
  speedSelect.innerHTML = '';
  for (const [value, label] of [[0.1, '0.1×'], [0.25, '0.25×'], [0.5, '0.5×'], [1, '1× real time'], [2, '2×'],
    [4, '4×'], [10, '10×'], [0, 'as fast as possible']]) {
    const option = document.createElement('option');
    option.value = String(value);
    option.textContent = label;
    speedSelect.appendChild(option);
  }
  const speedCopy = speedSelect.cloneNode(true);  // without the replay's listener
  speedSelect.replaceWith(speedCopy);
  speedCopy.value = '1';  // (a run starts at real time; the status says what it is)
  const readout = $('time-readout');
  const help = $('help');
  if (help) help.textContent = 'ctrl-drag a body: pull it with a spring · drag: orbit · right-drag: pan · wheel: zoom · space: pause';
  $('run-info').textContent = `live · ${particleCount} particles`;
  document.title = `robophi live: ${data.name || 'run'}`;

  // ------------------------------------------------------------ the energy plot
  // The replay's energy figure fed by the frames as they come: the energy account
  // and the drag's work over the last kPlotWindow model seconds (at most
  // kPlotPoints frames kept), redrawn once per animation frame. The replay's other
  // figures (dt, joints) have no live data and are hidden.
  const kPlotWindow = 20;  // s of model time shown
  const kPlotPoints = 4000;  // frames kept, the oldest dropped
  const liveSeries = [
    { name: 'kinetic', label: 'kinetic', colour: '#e15759', of: (s) => s.kinetic },
    { name: 'potential', label: 'potential', colour: '#4e79a7', of: (s) => s.potential },
    { name: 'dissipated', label: 'dissipated', colour: '#f28e2b', of: (s) => s.dissipated },
    { name: 'external', label: 'external work', colour: '#76b7b2', of: (s) => s.external },
    { name: 'drag', label: 'drag work', colour: '#59a14f', of: (s) => s.dragWork },
    { name: 'total', label: 'total (E + dissipated − external)', colour: '#1f2933', dash: [6, 3],
      of: (s) => s.kinetic + s.potential + s.dissipated - s.external },
  ];
  const plotTimes = [];
  const plotValues = liveSeries.map(() => []);
  for (const id of ['fig-dt', 'fig-joints']) if ($(id)) $(id).hidden = true;
  const replayCanvas = $('plot-energy');
  const plotCanvas = replayCanvas.cloneNode(false);  // without the replay's plot on it
  replayCanvas.replaceWith(plotCanvas);
  const legend = plotCanvas.parentElement.querySelector('.legend');
  legend.innerHTML = '';
  const legendValues = liveSeries.map((series) => ctx.addLegendEntry(legend, series));
  let plotQueued = false;
  function recordPlot() {
    if (plotTimes.length > 0 && state.time < plotTimes[plotTimes.length - 1]) {
      plotTimes.length = 0;
      for (const values of plotValues) values.length = 0;
    }
    plotTimes.push(state.time);
    liveSeries.forEach((series, k) => plotValues[k].push(series.of(state)));
    if (plotTimes.length > kPlotPoints) {
      plotTimes.shift();
      for (const values of plotValues) values.shift();
    }
    if (!plotQueued) {
      plotQueued = true;
      requestAnimationFrame(drawPlot);
    }
  }
  function drawPlot() {
    plotQueued = false;
    const ratio = window.devicePixelRatio || 1;
    const w = plotCanvas.clientWidth;
    const h = plotCanvas.clientHeight;
    if (plotCanvas.width !== Math.round(w * ratio) || plotCanvas.height !== Math.round(h * ratio)) {
      plotCanvas.width = Math.max(1, Math.round(w * ratio));
      plotCanvas.height = Math.max(1, Math.round(h * ratio));
    }
    const g = plotCanvas.getContext('2d');
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    g.clearRect(0, 0, w, h);
    const n = plotTimes.length;
    if (n === 0 || w < 80 || h < 40) return;
    const tHi = plotTimes[n - 1];
    const tLo = Math.max(plotTimes[0], tHi - kPlotWindow);
    let first = 0;
    while (first < n - 1 && plotTimes[first] < tLo) ++first;
    let lo = 0;
    let hi = 0;
    for (const values of plotValues) {
      for (let i = first; i < n; ++i) if (Number.isFinite(values[i])) { lo = Math.min(lo, values[i]); hi = Math.max(hi, values[i]); }
    }
    const pad = hi - lo > 0 ? 0.06 * (hi - lo) : 1;
    lo -= pad;
    hi += pad;
    const m = { left: 58, right: 10, top: 8, bottom: 22 };
    const span = tHi - tLo || 1;
    const xOf = (t) => m.left + (t - tLo) / span * (w - m.left - m.right);
    const yOf = (v) => m.top + (hi - v) / (hi - lo) * (h - m.top - m.bottom);
    g.font = '11px system-ui, sans-serif';
    g.lineWidth = 1;
    g.strokeStyle = '#e6eaef';
    g.fillStyle = '#667085';
    g.textAlign = 'right';
    g.textBaseline = 'middle';
    for (const v of ctx.ticks(lo, hi, Math.max(2, Math.floor((h - m.top - m.bottom) / 34)))) {
      const y = Math.round(yOf(v)) + 0.5;
      g.beginPath(); g.moveTo(m.left, y); g.lineTo(w - m.right, y); g.stroke();
      g.fillText(ctx.formatNumber(v, 4), m.left - 5, y);
    }
    g.textAlign = 'center';
    g.textBaseline = 'top';
    for (const t of ctx.ticks(tLo, tLo + span, Math.max(2, Math.floor((w - m.left - m.right) / 70)))) {
      const x = Math.round(xOf(t)) + 0.5;
      g.beginPath(); g.moveTo(x, m.top); g.lineTo(x, h - m.bottom); g.stroke();
      g.fillText(ctx.formatNumber(t, 3), x, h - m.bottom + 4);
    }
    g.strokeStyle = '#98a2b3';
    g.strokeRect(m.left + 0.5, m.top + 0.5, w - m.left - m.right - 1, h - m.top - m.bottom - 1);
    g.textAlign = 'right';
    g.fillText('t (s)', m.left - 5, h - m.bottom + 4);
    g.lineWidth = 1.6;
    g.lineJoin = 'round';
    liveSeries.forEach((series, k) => {
      g.strokeStyle = series.colour;
      g.setLineDash(series.dash || []);
      g.beginPath();
      for (let i = first; i < n; ++i) {
        if (i === first) g.moveTo(xOf(plotTimes[i]), yOf(plotValues[k][i]));
        else g.lineTo(xOf(plotTimes[i]), yOf(plotValues[k][i]));
      }
      g.stroke();
      legendValues[k].textContent = `${ctx.formatNumber(plotValues[k][n - 1])} J`;
    });
    g.setLineDash([]);
  }

  // ------------------------------------------------------------ the socket
  const socket = new WebSocket(`ws://${window.location.host}${data.live.socket}`);
  socket.binaryType = 'arraybuffer';
  const send = (message) => {
    if (socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
  };
  const pause = () => { send({ type: 'pause' }); state.paused = true; showPaused(true); };
  const resume = () => { send({ type: 'resume' }); state.paused = false; showPaused(false); };
  const setSpeed = (k) => { send({ type: 'speed', value: k }); speedCopy.value = String(k); };
  pauseButton.addEventListener('click', () => (state.paused ? resume() : pause()));
  speedCopy.addEventListener('change', () => setSpeed(Number(speedCopy.value)));

  const fps = () => {
    const now = performance.now();
    const recent = state.frameWall.filter((w) => now - w <= 1000);
    return recent.length;
  };
  const showReadout = () => {
    const parts = [`t = ${state.time.toFixed(3)} s`, `${fps()} frames/s`];
    if (state.dragWork !== 0) parts.push(`drag work ${state.dragWork.toPrecision(3)} J`);
    if (state.paused) parts.push('paused');
    if (state.ended) parts.push('run ended');
    else if (!state.connected) parts.push('not connected');
    readout.textContent = parts.join(' · ');
  };
  socket.addEventListener('open', () => { state.connected = true; showReadout(); });
  socket.addEventListener('close', () => { state.connected = false; showReadout(); });
  socket.addEventListener('message', (event) => {
    if (typeof event.data === 'string') {
      const message = JSON.parse(event.data);
      if (message.type !== 'status') return;
      state.status = message;
      if (message.ended) state.ended = true;
      if (typeof message.paused === 'boolean') { state.paused = message.paused; showPaused(message.paused); }
      if (typeof message.dragWork === 'number') state.dragWork = message.dragWork;
      if (typeof message.speed === 'number' && [...speedCopy.options].some((o) => Number(o.value) === message.speed)) {
        speedCopy.value = String(message.speed);
      }
      showReadout();
      return;
    }
    const buffer = event.data;
    if (buffer.byteLength !== 8 * kHeaderNumbers + 12 * particleCount) return;
    const header = new Float64Array(buffer, 0, kHeaderNumbers);
    [state.time, state.step, state.kinetic, state.potential, state.dissipated, state.external, state.dragWork] = header;
    state.dragging = header[7];
    framePosition.set(new Float32Array(buffer, 8 * kHeaderNumbers, 3 * particleCount));
    frameTime[0] = state.time;
    state.frames += 1;
    const now = performance.now();
    state.frameWall.push(now);
    while (state.frameWall.length > 0 && now - state.frameWall[0] > 5000) state.frameWall.shift();
    ctx.showFrame(state.time);
    recordPlot();
    updateDragLine();
    showReadout();
  });
  window.addEventListener('keydown', (event) => {
    if (event.key === ' ' && !(event.target instanceof HTMLSelectElement)) {
      event.preventDefault();
      event.stopImmediatePropagation();
      pauseButton.click();
    }
  }, true);

  // ------------------------------------------------------------ the drag
  // Ctrl + left button on a particle (not fixed, or carried by a rigid tree's body;
  // not virtual) holds it; the mouse point is where the ray under the cursor meets
  // the plane through the particle facing the camera; the server pulls the particle
  // to it with a spring (a rigid tree: struck at that point, World::applyImpulse).
  let drag = null;  // {particle, plane, target}
  let dragLine = null;
  const THREE = scene3d && scene3d.THREE;
  if (THREE && scene3d.canvas) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6), 3));
    dragLine = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: 0x2ca02c }));
    dragLine.visible = false;
    dragLine.frustumCulled = false;
    scene3d.scene.add(dragLine);
  }
  function positionOf(i) {
    return [framePosition[3 * i], framePosition[3 * i + 1], framePosition[3 * i + 2]];
  }
  function updateDragLine() {
    if (!dragLine) return;
    dragLine.visible = drag !== null;
    if (!drag) return;
    const p = dragLine.geometry.attributes.position;
    p.array.set([...positionOf(drag.particle), drag.target.x, drag.target.y, drag.target.z]);
    p.needsUpdate = true;
  }
  // The draggable particle nearest the screen point (client pixels), within 24 px
  // or its own drawn radius, or -1.
  function pick(clientX, clientY) {
    if (!THREE || !scene3d.canvas) return -1;
    const rect = scene3d.canvas.getBoundingClientRect();
    const camera = scene3d.camera;
    const v = new THREE.Vector3();
    let best = -1;
    let bestDistance = Infinity;
    for (let i = 0; i < particleCount; ++i) {
      if ((fixedFlag[i] && !treeCarried[i]) || isVirtualParticle(i)) continue;
      v.set(...positionOf(i)).project(camera);
      if (v.z < -1 || v.z > 1) continue;
      const x = rect.left + (v.x + 1) / 2 * rect.width;
      const y = rect.top + (1 - v.y) / 2 * rect.height;
      // The particle's radius on screen, roughly (at its distance).
      const distance = camera.position.distanceTo(new THREE.Vector3(...positionOf(i)));
      const pixels = radius[i] / Math.max(distance * Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2), 1e-12) *
        rect.height / 2;
      const d = Math.hypot(x - clientX, y - clientY);
      if (d <= Math.max(24, pixels) && d < bestDistance) { best = i; bestDistance = d; }
    }
    return best;
  }
  function pointOnPlane(clientX, clientY) {
    const rect = scene3d.canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2((clientX - rect.left) / rect.width * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(ndc, scene3d.camera);
    const target = new THREE.Vector3();
    return raycaster.ray.intersectPlane(drag.plane, target) ? target : null;
  }
  function sendDrag() {
    send({ type: 'drag', particle: drag.particle, target: [drag.target.x, drag.target.y, drag.target.z] });
  }
  // Holds particle i and pulls it towards target [x, y, z] (m): what a mouse drag does.
  function dragTo(particle, target) {
    if (!THREE) {
      send({ type: 'drag', particle, target });
      return;
    }
    const normal = new THREE.Vector3();
    if (scene3d.camera) scene3d.camera.getWorldDirection(normal);
    drag = drag && drag.particle === particle ? drag : {
      particle, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, new THREE.Vector3(...positionOf(particle))),
    };
    drag.target = new THREE.Vector3(...target);
    sendDrag();
    updateDragLine();
  }
  function release() {
    drag = null;
    send({ type: 'release' });
    updateDragLine();
    if (scene3d && scene3d.controls) scene3d.controls.enabled = true;
  }
  if (THREE && scene3d.canvas) {
    const viewElement = $('view');
    viewElement.addEventListener('pointerdown', (event) => {
      if (event.button !== 0 || !event.ctrlKey) return;
      const particle = pick(event.clientX, event.clientY);
      if (particle < 0) return;
      event.stopPropagation();  // not an orbit
      event.preventDefault();
      if (scene3d.controls) scene3d.controls.enabled = false;
      dragTo(particle, positionOf(particle));
    }, true);
    window.addEventListener('pointermove', (event) => {
      if (!drag) return;
      const target = pointOnPlane(event.clientX, event.clientY);
      if (!target) return;
      drag.target = target;
      sendDrag();
      updateDragLine();
    });
    window.addEventListener('pointerup', () => { if (drag) release(); });
  }

  showReadout();
  // The test hook (window.robophiReplay.live()).
  return {
    connected: () => state.connected,
    ended: () => state.ended,
    frames: () => state.frames,
    /** Frames received in the last `seconds` (≤ 5) of wall time, per second. */
    framesPerSecond: (seconds = 1) => {
      const now = performance.now();
      return state.frameWall.filter((w) => now - w <= 1000 * seconds).length / seconds;
    },
    time: () => state.time,
    energy: () => ({ kinetic: state.kinetic, potential: state.potential, dissipated: state.dissipated,
      external: state.external, dragWork: state.dragWork }),
    status: () => state.status,
    position: (i) => positionOf(i),
    /** Where particle i is drawn, in client pixels (null without the 3D view). */
    screenOf: (i) => {
      if (!THREE || !scene3d.canvas) return null;
      const rect = scene3d.canvas.getBoundingClientRect();
      const v = new THREE.Vector3(...positionOf(i)).project(scene3d.camera);
      return [rect.left + (v.x + 1) / 2 * rect.width, rect.top + (1 - v.y) / 2 * rect.height];
    },
    pick,
    /** The live energy plot: {points, series (names), last: the last value of each (J)}. */
    plot: () => ({
      points: plotTimes.length,
      series: liveSeries.map((series) => series.name),
      last: Object.fromEntries(liveSeries.map((series, k) => [series.name, plotValues[k][plotValues[k].length - 1]])),
    }),
    pause, resume, setSpeed, dragTo, release,
    stop: () => send({ type: 'stop' }),
  };
}
