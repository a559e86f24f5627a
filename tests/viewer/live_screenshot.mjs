// The live view's screenshot (docs/images/live-view.png): the pendulum held above
// its pivot by a ctrl-drag of the mouse in headless Chromium.
//
//   node tests/viewer/live_screenshot.mjs ROBOPHI_BINARY OUT.png
import { spawn } from 'node:child_process';
import fs from 'node:fs'; import os from 'node:os'; import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const require = createRequire(path.join(repo, 'viewer', 'package.json'));
const { chromium } = require('playwright-core');
const child = spawn(process.argv[2], ['run', path.join(repo, 'scenes', 'pendulum.json'), '--live', '--live-port', '0', '--live-wait', '60', '--duration', '100', '--out', fs.mkdtempSync(path.join(os.tmpdir(), 'robophi-live-')) + '/run', '-q']);
let err=''; const url = await new Promise((r) => child.stderr.on('data', (c) => { err += c; const m = /(http:\/\/\S+)/.exec(err); if (m) r(m[1]); }));
const ctx = await chromium.launchPersistentContext(fs.mkdtempSync(path.join(os.tmpdir(), 'c-')), { executablePath: process.env.ROBOPHI_CHROMIUM || '/usr/bin/chromium', headless: true, viewport: { width: 1100, height: 640 },
  args: ['--headless','--no-sandbox','--disable-gpu','--disable-quic','--no-first-run','--disable-background-networking','--disable-component-update','--disable-sync','--use-angle=swiftshader','--enable-unsafe-swiftshader','--ignore-gpu-blocklist'] });
const page = await ctx.newPage(); await page.goto(url);
await page.waitForFunction(() => window.robophiReplay && window.robophiReplay.live() && window.robophiReplay.live().frames() > 2, null, { timeout: 60000 });
const L = (e) => page.evaluate(`window.robophiReplay.live().${e}`);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
await page.evaluate(() => window.robophiReplay.setView([0.4, 0, 1.5], 4.5));
await sleep(700);
await L('pause()'); await sleep(200);
const [x, y] = await L('screenOf(3)');
const [px, py] = await L('screenOf(0)');
const tx = px + 120, ty = py - 170;
await page.keyboard.down('Control'); await page.mouse.move(x, y); await page.mouse.down();
for (let k = 1; k <= 12; ++k) { await page.mouse.move(x + (tx - x) * k / 12, y + (ty - y) * k / 12); await sleep(30); }
await L('resume()'); await sleep(1500);
await page.screenshot({ path: process.argv[3] });
await page.mouse.up(); await page.keyboard.up('Control');
await L('stop()'); await new Promise((r) => child.on('exit', r)); await ctx.close();
