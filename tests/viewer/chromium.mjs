// Headless Debian Chromium through playwright-core (viewer/node_modules), WebGL on
// SwiftShader, with a fresh profile: shared by the viewer tests.
import fs from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', '..', 'viewer', 'package.json'));
const { chromium } = require('playwright-core');

/** A browser context of `width` × `height` CSS pixels at 1 device pixel each
 * (ROBOPHI_CHROMIUM, default /usr/bin/chromium). */
export function launchChromium(width = 1400, height = 820) {
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'robophi-chromium-'));
  return chromium.launchPersistentContext(userDataDir, {
    executablePath: process.env.ROBOPHI_CHROMIUM || '/usr/bin/chromium',
    headless: true,
    viewport: { width, height },
    deviceScaleFactor: 1,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
  });
}
