// Drives replay.html in headless Chromium (playwright-core, Debian's /usr/bin/chromium)
// and checks it against the run folder it was made from.
//
//   node tests/viewer/replay.test.mjs RUN_DIR [SCREENSHOT.png]
//   (or ROBOPHI_RUN_DIR / ROBOPHI_SCREENSHOT in the environment)
//
// RUN_DIR must hold replay.html (robophi export html RUN_DIR), model.json,
// particles.csv. Uses node's test runner; exit code 0 when every check passes.
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '..', '..');
// playwright-core lives in viewer/node_modules (viewer/package.json devDependencies).
const require = createRequire(path.join(repo, 'viewer', 'package.json'));
const { chromium } = require('playwright-core');

const runDir = path.resolve(process.argv[2] || process.env.ROBOPHI_RUN_DIR || '');
const screenshot = process.argv[3] || process.env.ROBOPHI_SCREENSHOT || '';
const chromiumPath = process.env.ROBOPHI_CHROMIUM || '/usr/bin/chromium';
// ROBOPHI_VIEWER_NO_WEBGL=1 checks the page without WebGL (plots and data only).
const noWebgl = process.env.ROBOPHI_VIEWER_NO_WEBGL === '1';
const gpuArgs = noWebgl ? ['--disable-webgl', '--disable-3d-apis']
  : ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'];

// particles.csv as {t: [...], positions: [[[x,y,z] per particle] per frame]}.
function readParticles(file) {
  const lines = fs.readFileSync(file, 'utf8').split(/\r?\n/).filter((l) => l.trim() !== '');
  const t = [];
  const positions = [];
  // Columns by name: x<i>, y<i>, z<i> (velocities vx<i>... may follow each particle).
  const header = lines[0].split(',').map((c) => c.trim());
  const xColumns = [];
  header.forEach((name, column) => { if (/^x\d+$/.test(name)) xColumns.push(column); });
  for (const line of lines.slice(1)) {
    const values = line.split(',').map(Number);
    t.push(values[0]);
    const frame = [];
    for (const v of xColumns) frame.push([values[v], values[v + 1], values[v + 2]]);
    positions.push(frame);
  }
  return { t, positions };
}

const model = JSON.parse(fs.readFileSync(path.join(runDir, 'model.json'), 'utf8'));
const particles = readParticles(path.join(runDir, 'particles.csv'));
const consoleErrors = [];
let context;
let page;

before(async () => {
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'robophi-chromium-'));
  // playwright-core wants the profile folder as an argument, not as --user-data-dir.
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: 1400, height: 820 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      ...gpuArgs],
  });
  page = context.pages()[0] || await context.newPage();
  page.on('console', (message) => {
    if (message.type() === 'error') consoleErrors.push(message.text());
  });
  page.on('pageerror', (error) => consoleErrors.push(`page error: ${error.message}`));
  // The page must need nothing from the network.
  await page.route(/^(https?|wss?):/, (route) => {
    consoleErrors.push(`network request: ${route.request().url()}`);
    return route.abort();
  });
  await page.goto(pathToFileURL(path.join(runDir, 'replay.html')).href);
  await page.waitForFunction(() => window.robophiReplay && window.robophiReplay.ready, null,
    { timeout: 30000 });
});

after(async () => {
  if (context) await context.close();
});

test('loads with no console error', () => {
  assert.deepEqual(consoleErrors, []);
});

test('one sphere per particle', async () => {
  const webgl = await page.evaluate(() => window.robophiReplay.webgl());
  console.log(`# WebGL: ${webgl ? 'yes' : 'no (3D view off; data, scrubber and plots only)'}`);
  assert.equal(await page.evaluate(() => window.robophiReplay.sphereCount()),
    model.particles.count);
});

test('frame times are those of particles.csv', async () => {
  const times = await page.evaluate(() => window.robophiReplay.frameTimes());
  assert.equal(await page.evaluate(() => window.robophiReplay.frameCount()), particles.t.length);
  assert.deepEqual(times, particles.t);
});

test('seek(t) shows the positions of particles.csv at t', async () => {
  const last = particles.t.length - 1;
  const picks = [0, Math.min(1, last), Math.floor(particles.t.length / 2), last];
  for (const k of [...new Set(picks)]) {
    const t = particles.t[k];
    const shown = await page.evaluate((time) => {
      window.robophiReplay.seek(time);
      return window.robophiReplay.currentPositions();
    }, t);
    assert.equal(shown.length, model.particles.count);
    shown.forEach((p, i) => {
      for (let d = 0; d < 3; ++d) {
        const expected = particles.positions[k][i][d];
        // (The page holds positions in single precision: within 6e-8 of them, relative.)
        assert.ok(Math.abs(p[d] - expected) <= 1e-6 * Math.max(1, Math.abs(expected)),
          `frame ${k} (t = ${t}) particle ${i} axis ${d}: shown ${p[d]}, particles.csv ${expected}`);
      }
    });
  }
});

test('plots energy and time step', async () => {
  const series = await page.evaluate(() => window.robophiReplay.plotSeries());
  for (const name of ['kinetic', 'potential', 'dissipated', 'total', 'dt']) {
    assert.ok(series.includes(name), `plot series ${JSON.stringify(series)} lack ${name}`);
  }
  if (model.joints && model.joints.length > 0 && fs.existsSync(path.join(runDir, 'joints.csv'))) {
    for (const joint of model.joints) assert.ok(series.includes(joint.name), `no plot of ${joint.name}`);
  }
});

// The world (world.json, src/output/world_view.cpp): what the scene graph holds
// must be what the file describes, and drawing it must change the picture.
const worldFile = path.join(runDir, 'world.json');
const worldView = fs.existsSync(worldFile) ? JSON.parse(fs.readFileSync(worldFile, 'utf8')) : null;

test('draws the environment, goals and paths of world.json', { skip: !worldView }, async () => {
  assert.equal(await page.evaluate(() => window.robophiReplay.hasWorld()), true);
  const counts = await page.evaluate(() => window.robophiReplay.worldCounts());
  console.log(`# world: ${JSON.stringify(counts)}`);
  const env = worldView.environment;
  const virtualSpheres = env.spheres.filter((s) => s.virtual).length;
  const virtualBoxes = env.boxes.filter((b) => b.virtual).length;
  assert.equal(counts.planes, env.planes.length);
  assert.equal(counts.heightfields, env.heightfields.length);
  const triangles = env.heightfields.reduce((n, h) => n + 2 * (h.columns - 1) * (h.rows - 1), 0);
  assert.equal(counts.heightfieldTriangles, triangles);
  assert.equal(counts.boxes, env.boxes.length - virtualBoxes);
  assert.equal(counts.spheres, env.spheres.length - virtualSpheres);
  assert.equal(counts.virtualObstacles, virtualSpheres + virtualBoxes);
  const shells = [...env.spheres, ...env.boxes].filter((item) => item.securityDistance > 0).length;
  assert.equal(counts.securityShells, shells);
  assert.equal(counts.goals, worldView.goals.length);
  assert.equal(counts.goalMarkers, worldView.goals.reduce((n, g) => n + g.positions.length, 0));
  assert.equal(counts.paths, worldView.paths.length);
  assert.equal(counts.attractors, worldView.attractors.length);
});

test('virtual obstacles appear at their time', { skip: !worldView }, async () => {
  const timed = [...worldView.environment.spheres, ...worldView.environment.boxes]
    .filter((item) => item.virtual).map((item) => item.addedAt).sort((a, b) => a - b);
  if (timed.length === 0) return;
  const before = timed[0] - 1e-6;
  if (before >= particles.t[0]) {
    const shown = await page.evaluate((t) => { window.robophiReplay.seek(t); return window.robophiReplay.shownCounts(); },
      before);
    assert.equal(shown.virtualObstacles, 0);
  }
  const end = particles.t[particles.t.length - 1];
  const shown = await page.evaluate((t) => { window.robophiReplay.seek(t); return window.robophiReplay.shownCounts(); },
    end);
  assert.equal(shown.virtualObstacles, timed.filter((t) => t <= end + 1e-9).length);
});

test('the strain scale comes from connectors only', async () => {
  // The largest |strain| over the run of the linear springs that are not attractors,
  // from the positions as the page holds them (single precision).
  const attractors = new Set(worldView ? worldView.attractors : []);
  const isVirtual = (i) => (model.objects[model.particles.object[i]] || {}).kind === 'virtual';
  let largest = 0;
  model.connectors.linear.forEach(([a, b, rest], s) => {
    if (attractors.has(s) || rest <= 1e-6 || isVirtual(a) || isVirtual(b)) return;
    for (const frame of particles.positions) {
      const length = Math.hypot(...[0, 1, 2].map((d) => Math.fround(frame[b][d]) - Math.fround(frame[a][d])));
      if (rest > 0) largest = Math.max(largest, Math.abs(length - rest) / rest);
    }
  });
  const scale = await page.evaluate(() => window.robophiReplay.strainScale());
  if (!Number.isFinite(scale)) return;  // no 3D view at all
  assert.ok(Math.abs(scale - Math.max(largest, 1e-6)) <= 1e-9 * Math.max(1, largest),
    `strain scale ${scale}, connectors' largest strain ${largest}`);
});

test('plots external work beside the total', async () => {
  // W_ext is energy.csv's column, or what its total implies: total = K + P + dissipated − W_ext.
  const lines = fs.readFileSync(path.join(runDir, 'energy.csv'), 'utf8').split(/\r?\n/).filter((l) => l.trim());
  const header = lines[0].split(',').map((c) => c.trim());
  const col = (name) => header.indexOf(name);
  let implied = 0;
  let scale = 1e-300;
  for (const line of lines.slice(1)) {
    const v = line.split(',').map(Number);
    const e = v[col('kinetic')] + v[col('potential')];
    implied = Math.max(implied, Math.abs(e + v[col('dissipated')] - v[col('total')]));
    scale = Math.max(scale, Math.abs(v[col('total')]), Math.abs(v[col('potential')]), Math.abs(v[col('kinetic')]));
  }
  const series = await page.evaluate(() => window.robophiReplay.plotSeries());
  if (header.includes('external') || implied > 1e-9 * scale) {
    assert.ok(series.includes('external'), `plot series ${JSON.stringify(series)} lack external work`);
  }
});

test('draws friction forces when contacts.csv has them', async () => {
  const file = path.join(runDir, 'contacts.csv');
  if (!fs.existsSync(file)) return;
  const lines = fs.readFileSync(file, 'utf8').split(/\r?\n/).filter((l) => l.trim() !== '');
  const header = lines[0].split(',').map((c) => c.trim());
  const hasFriction = [['tx', 'ty', 'tz'], ['ftx', 'fty', 'ftz']]
    .some((names) => names.every((c) => header.includes(c)));
  assert.equal(await page.evaluate(() => window.robophiReplay.frictionDrawn()), hasFriction);
  if (!hasFriction || lines.length < 2) return;
  const first = Number(lines[1].split(',')[0]);
  const k = particles.t.findIndex((t) => t >= first - 1e-12);
  const shown = await page.evaluate((t) => { window.robophiReplay.seek(t); return window.robophiReplay.shownCounts(); },
    particles.t[k]);
  assert.ok(shown.contacts > 0 && shown.friction > 0, JSON.stringify(shown));
});

const worldItems = worldView ? ['planes', 'heightfields', 'boxes', 'spheres']
  .reduce((n, kind) => n + worldView.environment[kind].length, 0) + worldView.goals.length + worldView.paths.length : 0;

test('the environment changes the picture', { skip: worldItems === 0 || noWebgl }, async () => {
  if (!(await page.evaluate(() => window.robophiReplay.webgl()))) return;
  // Pixels that differ between the view with and without the environment and goals.
  const changed = await page.evaluate(async () => {
    const grab = () => {
      window.robophiReplay.seek(window.robophiReplay.frameTimes()[0]);
      const source = document.querySelector('#view canvas');
      const copy = document.createElement('canvas');
      copy.width = source.width;
      copy.height = source.height;
      const g = copy.getContext('2d');
      g.drawImage(source, 0, 0);
      return g.getImageData(0, 0, copy.width, copy.height).data;
    };
    const toggle = (on) => {
      for (const id of ['show-environment', 'show-goals']) {
        const box = document.getElementById(id);
        box.checked = on;
        box.dispatchEvent(new Event('change'));
      }
    };
    const frame = () => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)));
    toggle(true); await frame();
    const withWorld = grab();
    toggle(false); await frame();
    const without = grab();
    toggle(true); await frame();
    let count = 0;
    for (let i = 0; i < withWorld.length; i += 4) {
      const d = Math.abs(withWorld[i] - without[i]) + Math.abs(withWorld[i + 1] - without[i + 1]) +
        Math.abs(withWorld[i + 2] - without[i + 2]) + Math.abs(withWorld[i + 3] - without[i + 3]);
      if (d > 24) ++count;
    }
    return { count, total: withWorld.length / 4 };
  });
  console.log(`# environment pixels: ${changed.count} of ${changed.total}`);
  assert.ok(changed.count > 0.005 * changed.total, `only ${changed.count} of ${changed.total} pixels show the world`);
});

test('screenshot', { skip: !screenshot }, async () => {
  const middle = particles.t[Math.floor(particles.t.length * 0.8)];
  await page.evaluate((time) => window.robophiReplay.seek(time), middle);
  await page.waitForTimeout(300);
  fs.mkdirSync(path.dirname(path.resolve(screenshot)), { recursive: true });
  await page.screenshot({ path: screenshot });
  assert.ok(fs.statSync(screenshot).size > 0);
  console.log(`# screenshot: ${path.resolve(screenshot)}`);
  assert.deepEqual(consoleErrors, []);
});
