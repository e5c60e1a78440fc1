// SPDX-License-Identifier: MIT
// Debian's chromium, headless, driven by playwright-core (from the build tree's node_modules,
// DSM_WEB_MODULES). WebGL runs on SwiftShader (no GPU on the test machines).
import { createRequire } from 'node:module';

const require = createRequire((process.env.DSM_WEB_MODULES || '.') + '/');
const { chromium } = require('playwright-core');

export async function launch() {
  return chromium.launch({
    executablePath: process.env.DSM_CHROMIUM || '/usr/bin/chromium',
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
}

// Console errors and uncaught exceptions of `page`, collected as they happen.
export function collectErrors(page) {
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  return errors;
}

// Pixels of a PNG screenshot that differ from its most common colour (the background): decoded by
// the browser itself in a blank page.
export async function nonBackgroundPixels(browser, png) {
  const page = await browser.newPage();
  const count = await page.evaluate(async (b64) => {
    const image = new Image();
    image.src = 'data:image/png;base64,' + b64;
    await image.decode();
    const canvas = document.createElement('canvas');
    canvas.width = image.width;
    canvas.height = image.height;
    const g = canvas.getContext('2d');
    g.drawImage(image, 0, 0);
    const pixels = g.getImageData(0, 0, image.width, image.height).data;
    const histogram = new Map();
    for (let i = 0; i < pixels.length; i += 4) {
      const key = (pixels[i] << 16) | (pixels[i + 1] << 8) | pixels[i + 2];
      histogram.set(key, (histogram.get(key) || 0) + 1);
    }
    const background = Math.max(...histogram.values());
    return pixels.length / 4 - background;
  }, png.toString('base64'));
  await page.close();
  return count;
}

export function check(condition, message) {
  if (!condition) throw new Error(message);
}
