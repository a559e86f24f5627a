// The robots of a replay page as they look (docs/viewer.md "Robots as they look"),
// in headless Chromium: each run folder's page loads with no console error, draws
// its URDF visuals (meshes), and after "reset view" the robot's own pixels span
// a screen box of at least 20% of the view's area (or 60% of its height or width,
// for a robot of another shape than the view's), at t = 0 and at the last frame;
// every mesh file it parsed has at most 10 000 triangles (the page's budget).
//
//   node tests/viewer/robots.test.mjs OUT_DIR RUN_DIR[:q] ...
//
// A RUN_DIR followed by ":q" is a bare URDF run built at q = 0: its joint plot
// must start at q = 0 (the URDF's coordinates) within 1e-6 rad or m. Screenshots
// (t = 0 and the last frame) go to OUT_DIR/<run folder name>-t0.png, -end.png.
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { pathToFileURL } from 'node:url';

import { launchChromium } from './chromium.mjs';

const [outDir, ...runArgs] = process.argv.slice(2);
const runs = runArgs.map((a) => (a.endsWith(':q') ? { dir: a.slice(0, -2), q: true } : { dir: a, q: false }));
let context;

before(async () => {
  fs.mkdirSync(outDir, { recursive: true });
  context = await launchChromium(1400, 820);
});
after(async () => { if (context) await context.close(); });

for (const run of runs) {
  const name = path.basename(run.dir);
  test(`${name}: the robot is drawn as it looks`, async () => {
    const page = await context.newPage();
    const errors = [];
    page.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
    page.on('pageerror', (error) => errors.push(`page error: ${error.message}`));
    await page.route(/^(https?|wss?):/, (route) => { errors.push(`network: ${route.request().url()}`); return route.abort(); });
    await page.goto(pathToFileURL(path.join(run.dir, 'replay.html')).href);
    await page.waitForFunction(() => window.robophiReplay && window.robophiReplay.ready, null, { timeout: 120000 });
    const counts = await page.evaluate(() => window.robophiReplay.robotCounts());
    console.log(`# ${name}: ${JSON.stringify(counts)}`);
    assert.ok(counts.drawn > 0, `${name}: no visual drawn`);
    assert.ok(counts.meshes > 0, `${name}: no mesh drawn`);
    // Every mesh file as the page parsed it is within the triangle budget (docs/viewer.md).
    for (const [index, triangles] of Object.entries(counts.meshTriangles)) {
      assert.ok(triangles > 0 && triangles <= 10000, `${name}: mesh ${index} has ${triangles} triangles`);
    }
    const times = await page.evaluate(() => window.robophiReplay.frameTimes());
    for (const [label, t] of [['t0', times[0]], ['end', times[times.length - 1]]]) {
      await page.evaluate((at) => window.robophiReplay.seek(at), t);
      const box = await page.evaluate(() => window.robophiReplay.robotPixelBox());
      console.log(`# ${name} at t = ${t} s: robot box ${JSON.stringify(box)}`);
      // (Saved before the check, so that a failure has its picture.)
      await page.screenshot({ path: path.join(outDir, `${name}-${label}.png`) });
      // The box covers 20% of the view, or, for a robot much taller (or wider) than the
      // view's shape (an upright arm: 12% × 85%), spans 60% of the view along its long side.
      assert.ok(box && (box.area >= 0.2 || Math.max(box.width, box.height) >= 0.6),
        `${name} at t = ${t} s: the robot's box is ${JSON.stringify(box)} of the view`);
    }
    if (run.q) {
      const series = await page.evaluate(() => window.robophiReplay.plotSeries());
      const jointNames = series.filter((s) => s.includes('.'));
      assert.ok(jointNames.length > 0, `${name}: no joint plotted`);
      for (const joint of jointNames) {
        const values = await page.evaluate((j) => window.robophiReplay.plotValues(j), joint);
        assert.ok(Math.abs(values[0]) <= 1e-6, `${name}: ${joint} starts at q = ${values[0]}, not 0`);
      }
    }
    assert.deepEqual(errors, []);
    await page.close();
  });
}
