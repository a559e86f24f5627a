// The live view in headless Chromium (docs/viewer.md "Live view"): robophi run
// --live on scenes/pendulum.json, driven through the page.
//
//   node tests/viewer/live.test.mjs ROBOPHI_BINARY ARTIFACT_DIR
//
// 1. A plain run of 6 s and a live run of the same with a viewer attached, paused
//    and resumed on the way, no drag: the same state hash.
// 2. Frames come at >= 20 per second (measured over 1.2 s of wall time at real
//    time; the pendulum runs ~1000 times faster than that).
// 3. Paused, the time stops; resumed, it goes on.
// 4. A ctrl-drag with the mouse grabs the bob; pulled (the same code path) to above
//    the pivot it rests there: summary.json's outcomes.live.dragWork is positive and
//    is the run's external work. The live energy plot holds the frames as they came.
// 5. A rigid robot's link (the bare iiwa, --rigid; ROBOPHI_ROBOTS_DIR, skipped
//    without it) dragged: it moves towards the mouse point and the drag books work.
import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '..', '..');
const require = createRequire(path.join(repo, 'viewer', 'package.json'));
const { chromium } = require('playwright-core');

const robophi = path.resolve(process.argv[2] || process.env.ROBOPHI_BINARY || '');
const artifacts = path.resolve(process.argv[3] || process.env.ROBOPHI_ARTIFACTS || os.tmpdir());
const chromiumPath = process.env.ROBOPHI_CHROMIUM || '/usr/bin/chromium';
const scene = path.join(repo, 'scenes', 'pendulum.json');
const bob = 3;  // scenes/pendulum.json: the pivot's three fixed particles, then the bob

const sleep = (ms) => new Promise((resolve) => { setTimeout(resolve, ms); });
const summaryOf = (dir) => JSON.parse(fs.readFileSync(path.join(dir, 'summary.json'), 'utf8'));

// Starts `robophi run --live`; resolves with {child, url, exit (a promise of the code)}.
function startLive(out, extra, sceneFile = scene) {
  fs.rmSync(out, { recursive: true, force: true });
  const child = spawn(robophi, ['run', sceneFile, '--live', '--live-port', '0', '--live-wait', '60',
    '--out', out, '--quiet', ...extra], { stdio: ['ignore', 'pipe', 'pipe'] });
  let stderr = '';
  const exit = new Promise((resolve) => { child.on('exit', (code) => resolve(code)); });
  const url = new Promise((resolve, reject) => {
    child.stderr.on('data', (chunk) => {
      stderr += chunk;
      const match = /live view at (http:\/\/127\.0\.0\.1:\d+\/)/.exec(stderr);
      if (match) resolve(match[1]);
    });
    child.on('exit', (code) => reject(new Error(`robophi run --live exited ${code}: ${stderr}`)));
  });
  return { child, url, exit, stderr: () => stderr };
}

let context;
const consoleErrors = [];
before(async () => {
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'robophi-chromium-'));
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: 960, height: 600 },  // (software WebGL: a smaller view leaves the cores to the run)
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
  });
});
after(async () => {
  if (context) await context.close();
});

// Opens the live page and waits for its first frames.
async function openPage(url) {
  const page = await context.newPage();
  page.on('console', (message) => { if (message.type() === 'error') consoleErrors.push(message.text()); });
  page.on('pageerror', (error) => consoleErrors.push(`page error: ${error.message}`));
  // Nothing beyond the run's own server on loopback.
  await page.route((u) => !u.href.startsWith(url) && !u.href.startsWith(url.replace('http:', 'ws:')),
    (route) => { consoleErrors.push(`network request: ${route.request().url()}`); return route.abort(); });
  await page.goto(url);
  await page.waitForFunction(() => window.robophiReplay && window.robophiReplay.live() &&
    window.robophiReplay.live().frames() > 2, null, { timeout: 60000 });
  return page;
}
const live = (page, expression) => page.evaluate(`window.robophiReplay.live().${expression}`);

test('a live run with a viewer (paused and resumed, no drag) ends in the plain run\'s state', async () => {
  const plainDir = path.join(artifacts, 'live_plain');
  fs.rmSync(plainDir, { recursive: true, force: true });
  const plain = spawnSync(robophi, ['run', scene, '--duration', '6', '--out', plainDir, '--quiet']);
  assert.equal(plain.status, 0, String(plain.stderr));

  const liveDir = path.join(artifacts, 'live_view');
  const run = startLive(liveDir, ['--duration', '6']);
  const page = await openPage(await run.url);

  // Frames per second at real time (the scene runs far faster), over 1.2 s.
  const frames0 = await live(page, 'frames()');
  const wall0 = Date.now();
  await sleep(1200);
  const fps = ((await live(page, 'frames()')) - frames0) / ((Date.now() - wall0) / 1000);
  console.log(`# live frames per second at real time: ${fps.toFixed(1)}`);
  assert.ok(fps >= 20, `${fps} frames per second`);

  // Paused: the time stops (the last frames in flight may still come).
  await live(page, 'pause()');
  await sleep(300);
  const paused0 = await live(page, 'time()');
  await sleep(500);
  const paused1 = await live(page, 'time()');
  console.log(`# paused at t = ${paused0} s, ${paused1} s 0.5 s later`);
  assert.equal(paused1, paused0);
  assert.ok(paused0 > 0 && paused0 < 6, `paused at ${paused0}`);
  await live(page, 'resume()');
  await sleep(500);
  const resumed = await live(page, 'time()');
  console.log(`# resumed: t = ${resumed} s 0.5 s later`);
  assert.ok(resumed > paused1, `${resumed} after ${paused1}`);
  await live(page, 'setSpeed(0)');  // as fast as possible to the end
  assert.equal(await run.exit, 0, run.stderr());
  await page.screenshot({ path: path.join(artifacts, 'live.png') });
  await page.close();

  const a = summaryOf(plainDir);
  const b = summaryOf(liveDir);
  console.log(`# state hash: plain ${a.state_hash}, live ${b.state_hash}`);
  assert.equal(b.state_hash, a.state_hash);
  assert.equal(b.outcomes.live.dragWork, 0);
  assert.equal(b.energy.external_work_J, a.energy.external_work_J);
  assert.deepEqual(consoleErrors, []);
});

test('a ctrl-drag lifts the bob and its work is external work in summary.json', async () => {
  const liveDir = path.join(artifacts, 'live_drag');
  const run = startLive(liveDir, ['--duration', '1000']);
  const page = await openPage(await run.url);
  await live(page, 'setSpeed(1)');
  await sleep(300);
  // The page's own drag: ctrl + left button on the bob (paused, so that it stays
  // under the mouse), the mouse moved up, the run resumed, then let go.
  // Paused where the bob is in the open view: a pointer press over one of the view's
  // overlays (legend, toggles, help) goes to the overlay, as it does for a user, so
  // where the swing happened to stop under one, the run goes on a little and pauses
  // again. (Until the run says it is paused and no frame moves the bob any more: on
  // a loaded machine the pause can come a few frames after it is asked for.)
  let x = 0;
  let y = 0;
  for (let attempt = 0; ; ++attempt) {
    await live(page, 'pause()');
    await page.waitForFunction(() => {
      const status = window.robophiReplay.live().status();
      return status && status.paused === true;
    }, null, { timeout: 30000 });
    await sleep(300);
    [x, y] = await live(page, `screenOf(${bob})`);
    const open = await page.evaluate(([px, py]) => {
      const element = document.elementFromPoint(px, py);
      return element !== null && element.closest('#view') !== null;
    }, [x, y]);
    if (open) break;
    console.log(`# the bob paused under an overlay of the view at (${x}, ${y}): on a little`);
    assert.ok(attempt < 20, `the bob stayed under an overlay of the view (${x}, ${y})`);
    await live(page, 'resume()');
    await sleep(150);
  }
  assert.equal(await live(page, `pick(${x}, ${y})`), bob);
  await page.keyboard.down('Control');
  await page.mouse.move(x, y);
  await page.mouse.down();
  // The run takes the grab (its status names the dragged particle) before the move.
  await page.waitForFunction((i) => {
    const status = window.robophiReplay.live().status();
    return status && status.dragging === i;
  }, bob, { timeout: 30000 });
  for (let k = 1; k <= 10; ++k) {
    await page.mouse.move(x, y - 15 * k);
    await sleep(50);
  }
  await live(page, 'resume()');
  await sleep(500);
  await page.mouse.up();
  await page.keyboard.up('Control');
  // Then the same drag code path to a point 1.1 m above the pivot, out of the rod's
  // reach: held there the swinging bob comes to rest at the top, 1 m above where it
  // started at rest (from 14.7 J to about 24.5 J): the drag must have put work in.
  await live(page, `dragTo(${bob}, [0, 0, 2.6])`);
  await sleep(2500);
  const [held, plotted] = await page.evaluate(() => {
    const hook = window.robophiReplay.live();
    return [hook.energy(), hook.plot()];
  });
  const top = await live(page, `position(${bob})`);
  await live(page, 'release()');
  // The live energy plot has the frames as they came, the last one's values.
  console.log(`# live energy plot: ${plotted.points} frames, last ${JSON.stringify(plotted.last)}`);
  assert.ok(plotted.points > 50, `${plotted.points} frames plotted`);
  assert.deepEqual(plotted.series, ['kinetic', 'potential', 'dissipated', 'external', 'drag', 'total']);
  for (const name of ['kinetic', 'potential', 'dissipated', 'external']) assert.equal(plotted.last[name], held[name]);
  assert.equal(plotted.last.drag, held.dragWork);
  console.log(`# while dragged: drag work ${held.dragWork} J, external ${held.external} J, ` +
    `bob at z = ${top[2]} m`);
  assert.ok(top[2] > 2.3, `bob at ${top}`);
  await sleep(200);
  await live(page, 'stop()');
  assert.equal(await run.exit, 0, run.stderr());
  await page.close();

  const s = summaryOf(liveDir);
  const work = s.outcomes.live.dragWork;
  console.log(`# summary.json: dragWork ${work} J, external_work_J ${s.energy.external_work_J} J, ` +
    `drags ${s.outcomes.live.drags}, frames ${s.outcomes.live.frames}`);
  assert.equal(s.outcomes.live.drags, 2, 'the mouse\'s grab, then the hook\'s');
  assert.ok(work > 0, `drag work ${work} J: lifting the bob puts energy in`);
  // The pendulum has no other work from outside.
  assert.ok(Math.abs(s.energy.external_work_J - work) <= 1e-9 * Math.max(1, Math.abs(work)),
    `external ${s.energy.external_work_J} J, drag ${work} J`);
  assert.deepEqual(consoleErrors, []);
});

// A rigid robot's link dragged (World::applyImpulse strikes its tree there): the
//    bare iiwa (--rigid, its joints held by servos), its highest particle pulled
//    1 m sideways; the link moves towards the point (its servos hold it back) and
//    the drag books work.
const iiwa = path.join(process.env.ROBOPHI_ROBOTS_DIR || path.join(repo, '..', 'shared', 'robots'),
  'kuka_iiwa', 'model.urdf');
test('a ctrl-drag moves a rigid arm\'s link and books its work', { skip: !fs.existsSync(iiwa) && `no ${iiwa}` }, async () => {
  const liveDir = path.join(artifacts, 'live_drag_rigid');
  const run = startLive(liveDir, ['--duration', '1000', '--rigid'], iiwa);
  const page = await openPage(await run.url);
  await live(page, 'setSpeed(1)');
  await live(page, 'pause()');
  await sleep(300);
  // The highest particle (on the last link): fixed in the model, carried by the tree.
  const positions = await page.evaluate(() => window.robophiReplay.currentPositions());
  let tip = 0;
  positions.forEach((p, i) => { if (p[2] > positions[tip][2]) tip = i; });
  const start = await live(page, `position(${tip})`);
  // The page lets the mouse grab it (a carried particle is not "fixed" for the drag).
  const [x, y] = await live(page, `screenOf(${tip})`);
  const picked = await live(page, `pick(${x}, ${y})`);
  assert.ok(picked >= 0, `nothing to grab at the arm's tip (${x}, ${y})`);
  const target = [start[0] + 1.0, start[1], start[2]];
  await live(page, `dragTo(${tip}, ${JSON.stringify(target)})`);
  await live(page, 'resume()');
  await sleep(2500);
  const held = await live(page, 'energy()');
  const moved = await live(page, `position(${tip})`);
  await live(page, 'release()');
  const along = moved[0] - start[0];
  console.log(`# rigid iiwa: tip particle ${tip} moved ${along} m towards the point 1 m away ` +
    `(${JSON.stringify(start)} -> ${JSON.stringify(moved)}), drag work ${held.dragWork} J`);
  assert.ok(along > 0.03, `the tip moved ${along} m towards the mouse point`);
  await sleep(200);
  await live(page, 'stop()');
  assert.equal(await run.exit, 0, run.stderr());
  await page.close();
  const s = summaryOf(liveDir);
  console.log(`# summary.json: dragWork ${s.outcomes.live.dragWork} J, drags ${s.outcomes.live.drags}`);
  assert.equal(s.outcomes.live.drags, 1);
  assert.ok(Math.abs(s.outcomes.live.dragWork) > 1e-6, `drag work ${s.outcomes.live.dragWork} J`);
  assert.deepEqual(consoleErrors, []);
});
