// A screenshot of any local HTML page (the sweep report, docs/sweep.md) in headless
// Chromium, the whole page's height at a width of 1200 px.
//
//   node tests/viewer/page_screenshot.mjs PAGE.html OUT.png [HEIGHT_CAP_PX]
import fs from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', '..', 'viewer', 'package.json'));
const { chromium } = require('playwright-core');

const [pagePath, out, cap = '2400'] = process.argv.slice(2);
if (!pagePath || !out) {
  console.error('usage: node tests/viewer/page_screenshot.mjs PAGE.html OUT.png [HEIGHT_CAP_PX]');
  process.exit(2);
}
const context = await chromium.launchPersistentContext(fs.mkdtempSync(path.join(os.tmpdir(), 'robophi-chromium-')), {
  executablePath: process.env.ROBOPHI_CHROMIUM || '/usr/bin/chromium',
  headless: true,
  viewport: { width: 1200, height: 800 },
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run', '--disable-background-networking'],
});
try {
  const page = context.pages()[0] || await context.newPage();
  await page.route(/^(https?|wss?):/, (route) => route.abort());
  await page.goto(pathToFileURL(path.resolve(pagePath)).href);
  const size = await page.evaluate(() => ({ width: document.documentElement.scrollWidth,
    height: document.documentElement.scrollHeight }));
  await page.screenshot({ path: out, clip: { x: 0, y: 0, width: 1200, height: Math.min(size.height, Number(cap)) } });
  console.log(JSON.stringify({ screenshot: path.resolve(out), pageWidth: size.width, pageHeight: size.height }));
} finally {
  await context.close();
}
