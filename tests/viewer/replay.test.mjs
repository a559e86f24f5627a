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
  for (const line of lines.slice(1)) {
    const values = line.split(',').map(Number);
    t.push(values[0]);
    const frame = [];
    for (let v = 1; v < values.length; v += 3) frame.push([values[v], values[v + 1], values[v + 2]]);
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
        assert.ok(Math.abs(p[d] - expected) <= 1e-6,
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
