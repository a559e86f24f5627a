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
  const { data, $, particleCount, framePosition, frameTime, radius, fixedFlag, isVirtualParticle, scene3d } = ctx;
  const state = {
    connected: false, ended: false, frames: 0, frameWall: [], time: frameTime[0], step: 0,
    kinetic: 0, potential: 0, dissipated: 0, external: 0, dragWork: 0, status: null, paused: false,
    dragging: -1,
  };

  // ------------------------------------------------------------ the controls
  // The replay's footer becomes the live one: pause/resume, speed, a readout.
  for (const id of ['step-back', 'step-forward', 'scrub', 'loop-label']) $(id).hidden = true;
  $('plots').hidden = true;
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
  // Ctrl + left button on a particle (not fixed, not virtual) holds it; the mouse
  // point is where the ray under the cursor meets the plane through the particle
  // facing the camera; the server pulls the particle to it with a spring.
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
      if (fixedFlag[i] || isVirtualParticle(i)) continue;
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
    pause, resume, setSpeed, dragTo, release,
    stop: () => send({ type: 'stop' }),
  };
}
