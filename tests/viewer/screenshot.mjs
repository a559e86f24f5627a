// A screenshot of a run's replay page in headless Chromium (docs/viewer.md "Screenshots").
//
//   node tests/viewer/screenshot.mjs RUN_DIR OUT.png [TIME_S | last] [VIEW]
//
// RUN_DIR must hold replay.html. The page is shown at TIME_S (default: the last
// frame) and the window (1400 × 820) saved as a PNG. VIEW, optional, is JSON
// {"target": [x, y, z], "distance": d, "elevation": e} (m, m, -): the camera
// looks at target from d along the home view direction, or one of elevation e
// (default: "reset view", the whole scene).
// Prints the page's worldCounts() so that a caller can check what was drawn.
import fs from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', '..', 'viewer', 'package.json'));
const { chromium } = require('playwright-core');

const [runDir, out, when = 'last', viewJson = ''] = process.argv.slice(2);
const width = 1400;
const height = 820;
if (!runDir || !out) {
  console.error('usage: node tests/viewer/screenshot.mjs RUN_DIR OUT.png [TIME_S | last] [VIEW]');
  process.exit(2);
}
const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'robophi-chromium-'));
const context = await chromium.launchPersistentContext(userDataDir, {
  executablePath: process.env.ROBOPHI_CHROMIUM || '/usr/bin/chromium',
  headless: true,
  viewport: { width: Number(width), height: Number(height) },
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
    '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
let failed = false;
try {
  const page = context.pages()[0] || await context.newPage();
  const errors = [];
  page.on('pageerror', (error) => errors.push(error.message));
  page.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
  await page.route(/^(https?|wss?):/, (route) => route.abort());
  await page.goto(pathToFileURL(path.resolve(runDir, 'replay.html')).href);
  await page.waitForFunction(() => window.robophiReplay && window.robophiReplay.ready, null, { timeout: 60000 });
  const shownAt = await page.evaluate((w) => {
    const times = window.robophiReplay.frameTimes();
    return window.robophiReplay.seek(w === 'last' ? times[times.length - 1] : Number(w));
  }, when);
  if (viewJson) {
    const view = JSON.parse(viewJson);
    await page.evaluate((v) => window.robophiReplay.setView(v.target, v.distance, v.elevation), view);
  }
  await page.waitForTimeout(500);
  fs.mkdirSync(path.dirname(path.resolve(out)), { recursive: true });
  await page.screenshot({ path: out });
  const counts = await page.evaluate(() => window.robophiReplay.worldCounts());
  const shown = await page.evaluate(() => window.robophiReplay.shownCounts());
  console.log(JSON.stringify({ screenshot: path.resolve(out), t: shownAt, world: counts, shown, errors }));
  failed = errors.length > 0;
} finally {
  await context.close();
}
process.exit(failed ? 1 : 0);
