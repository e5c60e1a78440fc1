// SPDX-License-Identifier: MIT
// report.html of a synthetic run, opened offline in headless chromium: no console error, the 3D
// view is not blank (pixel check on a screenshot of its canvas), every plot has data.
//   node report_page.test.mjs DSM_BINARY WORK_DIR [SCREENSHOT.png]
import { execFileSync } from 'node:child_process';
import { mkdirSync, rmSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, collectErrors, nonBackgroundPixels, check } from './browser.mjs';

const [dsm, work, screenshot] = process.argv.slice(2);
rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
execFileSync(dsm, ['synth', '--scene', 'loop', '--frames', '120', '--width', '320', '--height', '240',
  '--defects', 'black:70-74', '--out', join(work, 'scene')]);
execFileSync(dsm, ['run', join(work, 'scene'), '--sequential', '--quiet', '--out', join(work, 'run')]);

const browser = await launch();
try {
  const context = await browser.newContext({ offline: true, viewport: { width: 1280, height: 1400 } });
  const page = await context.newPage();
  const errors = collectErrors(page);
  const requests = [];
  page.on('request', (r) => { if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) requests.push(r.url()); });
  await page.goto('file://' + join(work, 'run', 'report.html'));
  await page.waitForFunction(() => window.dsmReport && window.dsmReport.data);
  await page.waitForTimeout(1500);  // A few animation frames of the 3D view.

  const plots = await page.$$eval('figure canvas', (cs) => cs.map((c) => ({ id: c.id, points: Number(c.dataset.points) })));
  console.log('plots:', JSON.stringify(plots));
  check(plots.length === 4, `expected 4 plots, found ${plots.length}`);
  for (const p of plots) check(p.points > 0, `plot ${p.id} has no data`);
  const lost = await page.textContent('#lost');
  check(lost.includes('70'), `the lost episode is not listed: '${lost}'`);
  const summary = await page.textContent('#summary');
  check(summary.includes('frames tracked') && summary.includes('keyframes'), `summary: '${summary}'`);

  const canvas = await page.$('#map-canvas');
  const box = await canvas.boundingBox();
  const png = await canvas.screenshot();
  const drawn = await nonBackgroundPixels(browser, png);
  console.log(`3D view ${Math.round(box.width)}x${Math.round(box.height)}: ${drawn} pixels not background`);
  check(drawn > 0.005 * box.width * box.height, '3D view is blank');
  if (screenshot) writeFileSync(screenshot, await page.screenshot({ fullPage: false }));
  check(errors.length === 0, 'console errors: ' + errors.join(' | '));
  check(requests.length === 0, 'network requests: ' + requests.join(' '));
  console.log('report page: ok');
} finally {
  await browser.close();
}
