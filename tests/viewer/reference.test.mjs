// The robots' replays against reference images (docs/viewer.md "Reference images"),
// in headless Chromium: each run folder's page, after "reset view", at its first
// frame and at its last, scaled down to kWidth pixels wide, is compared with
// REFERENCE_DIR/<name>-t0.png and <name>-end.png.
//
//   node tests/viewer/reference.test.mjs OUT_DIR REFERENCE_DIR NAME=RUN_DIR ...
//
// Tolerance: per pixel the largest difference of its R, G, B, A (0-255); the image
// passes when their mean is at most kMeanTolerance of 255 and at most
// kDifferingTolerance of the pixels differ by more than kPixelThreshold. Scaling down
// averages away the antialiasing noise of a renderer (swiftshader) of another version.
// A failing image's diff (red: pixels past the threshold) and the image itself go
// to OUT_DIR/<name>-<t0|end>-diff.png and -actual.png.
// The comparison must fail for a wrong robot: each image is also compared with the
// robot hidden (robots unchecked) and the t = 0 image with the end's reference
// (every run's robot moves); both must be past the tolerance.
//
// ROBOPHI_RECORD_REFERENCE=1 writes the images to REFERENCE_DIR instead (re-record:
// tests/viewer/run_reference_test.sh with it set, then look at them and commit).
// PNGs are decoded by Chromium itself (an <img> drawn into a canvas).
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { pathToFileURL } from 'node:url';

import { launchChromium } from './chromium.mjs';

const kWidth = 240;  // px, the images' width (the view's shape sets the height)
const kPixelThreshold = 40;  // of 255: a pixel differs past this
const kMeanTolerance = 0.01;  // the mean difference, a fraction of 255
const kDifferingTolerance = 0.01;  // the fraction of pixels that differ

const [outDir, referenceDir, ...runArgs] = process.argv.slice(2);
const runs = runArgs.map((a) => { const at = a.indexOf('='); return { name: a.slice(0, at), dir: a.slice(at + 1) }; });
const record = process.env.ROBOPHI_RECORD_REFERENCE === '1';
let context;

before(async () => {
  fs.mkdirSync(outDir, { recursive: true });
  context = await launchChromium(1400, 820);
});
after(async () => { if (context) await context.close(); });

// Runs in the page: decodes two PNG data: URLs and measures their difference.
async function compareInPage({ actual, expected, threshold }) {
  const load = (url) => new Promise((resolve, reject) => {
    const image = new Image();
    image.onload = () => resolve(image);
    image.onerror = () => reject(new Error('cannot decode a PNG'));
    image.src = url;
  });
  const [a, b] = await Promise.all([load(actual), load(expected)]);
  if (a.width !== b.width || a.height !== b.height) {
    return { sizes: [[a.width, a.height], [b.width, b.height]] };
  }
  const pixelsOf = (image) => {
    const canvas = document.createElement('canvas');
    canvas.width = image.width;
    canvas.height = image.height;
    const context = canvas.getContext('2d');
    context.drawImage(image, 0, 0);
    return context.getImageData(0, 0, image.width, image.height).data;
  };
  const pa = pixelsOf(a);
  const pb = pixelsOf(b);
  const diffCanvas = document.createElement('canvas');
  diffCanvas.width = a.width;
  diffCanvas.height = a.height;
  const diffContext = diffCanvas.getContext('2d');
  const diff = diffContext.createImageData(a.width, a.height);
  const n = a.width * a.height;
  let sum = 0;
  let differing = 0;
  for (let i = 0; i < n; ++i) {
    let d = 0;
    for (let c = 0; c < 4; ++c) d = Math.max(d, Math.abs(pa[4 * i + c] - pb[4 * i + c]));
    sum += d;
    const past = d > threshold;
    if (past) ++differing;
    // The diff image: the reference faded, red where a pixel differs past the threshold.
    const grey = 255 - Math.round(0.25 * (255 - (pb[4 * i] + pb[4 * i + 1] + pb[4 * i + 2]) / 3) * pb[4 * i + 3] / 255);
    diff.data[4 * i] = past ? 255 : grey;
    diff.data[4 * i + 1] = past ? 0 : grey;
    diff.data[4 * i + 2] = past ? 0 : grey;
    diff.data[4 * i + 3] = 255;
  }
  diffContext.putImageData(diff, 0, 0);
  return { mean: sum / (255 * n), differing: differing / n, diff: diffCanvas.toDataURL('image/png') };
}

const dataUrlOf = (file) => `data:image/png;base64,${fs.readFileSync(file).toString('base64')}`;
const writeDataUrl = (file, url) => fs.writeFileSync(file, Buffer.from(url.slice(url.indexOf(',') + 1), 'base64'));
const within = (m) => m.mean !== undefined && m.mean <= kMeanTolerance && m.differing <= kDifferingTolerance;
const show = (m) => (m.sizes ? `sizes ${JSON.stringify(m.sizes)}`
  : `mean ${m.mean.toFixed(4)} (tolerance ${kMeanTolerance}), differing ${m.differing.toFixed(4)} (tolerance ${kDifferingTolerance})`);

for (const run of runs) {
  test(`${run.name}: the replay looks as its reference images`, async () => {
    const page = await context.newPage();
    const errors = [];
    page.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
    page.on('pageerror', (error) => errors.push(`page error: ${error.message}`));
    await page.route(/^(https?|wss?):/, (route) => { errors.push(`network: ${route.request().url()}`); return route.abort(); });
    await page.goto(pathToFileURL(path.join(run.dir, 'replay.html')).href);
    await page.waitForFunction(() => window.robophiReplay && window.robophiReplay.ready, null, { timeout: 120000 });
    const counts = await page.evaluate(() => window.robophiReplay.robotCounts());
    assert.ok(counts.meshes > 0, `${run.name}: no mesh drawn (${JSON.stringify(counts)})`);
    const times = await page.evaluate(() => window.robophiReplay.frameTimes());
    const moments = [['t0', times[0]], ['end', times[times.length - 1]]];
    const images = {};
    for (const [label, t] of moments) {
      await page.evaluate((at) => window.robophiReplay.seek(at), t);
      images[label] = await page.evaluate((w) => window.robophiReplay.viewImage(w), kWidth);
      assert.ok(images[label], `${run.name}: no WebGL view`);
    }
    // The robot hidden (the "robots" box unchecked): must not pass for it.
    const hidden = {};
    await page.evaluate(() => { const box = document.getElementById('show-robots'); box.checked = false; box.dispatchEvent(new Event('change')); });
    for (const [label, t] of moments) {
      await page.evaluate((at) => window.robophiReplay.seek(at), t);
      hidden[label] = await page.evaluate((w) => window.robophiReplay.viewImage(w), kWidth);
    }
    if (record) {
      fs.mkdirSync(referenceDir, { recursive: true });
      for (const [label] of moments) writeDataUrl(path.join(referenceDir, `${run.name}-${label}.png`), images[label]);
      console.log(`# ${run.name}: recorded ${referenceDir}/${run.name}-{t0,end}.png`);
    }
    const compare = (actual, expected) => page.evaluate(compareInPage, { actual, expected, threshold: kPixelThreshold });
    const failures = [];
    for (const [label, t] of moments) {
      const reference = path.join(referenceDir, `${run.name}-${label}.png`);
      assert.ok(fs.existsSync(reference), `${reference} missing (ROBOPHI_RECORD_REFERENCE=1 records it)`);
      const expected = dataUrlOf(reference);
      const m = await compare(images[label], expected);
      console.log(`# ${run.name} at t = ${t} s: ${show(m)}`);
      if (!within(m)) {
        writeDataUrl(path.join(outDir, `${run.name}-${label}-actual.png`), images[label]);
        if (m.diff) writeDataUrl(path.join(outDir, `${run.name}-${label}-diff.png`), m.diff);
        failures.push(`${run.name} at t = ${t} s: ${show(m)}; see ${outDir}/${run.name}-${label}-diff.png`);
      }
      // A wrong robot fails: hidden (and below, the other moment's).
      const withoutRobot = await compare(hidden[label], expected);
      console.log(`# ${run.name} at t = ${t} s, robot hidden: ${show(withoutRobot)}`);
      assert.ok(!within(withoutRobot), `${run.name} at t = ${t} s: the image without the robot passes (${show(withoutRobot)})`);
    }
    const other = await compare(images.t0, dataUrlOf(path.join(referenceDir, `${run.name}-end.png`)));
    console.log(`# ${run.name}: t0 against the end reference: ${show(other)}`);
    assert.ok(!within(other), `${run.name}: t0 passes for the end image (${show(other)})`);
    assert.deepEqual(failures, []);
    assert.deepEqual(errors, []);
    await page.close();
  });
}
