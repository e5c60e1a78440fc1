// SPDX-License-Identifier: MIT
// dsm run --view: a browser connected during a run sees the map's point count grow.
//   node live_view.test.mjs DSM_BINARY WORK_DIR
import { execFileSync, spawn } from 'node:child_process';
import { mkdirSync, rmSync } from 'node:fs';
import { join } from 'node:path';
import { launch, collectErrors, check } from './browser.mjs';

const [dsm, work] = process.argv.slice(2);
rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
execFileSync(dsm, ['synth', '--scene', 'loop', '--frames', '160', '--width', '320', '--height', '240',
  '--out', join(work, 'scene')]);
// The browser first: launched after the address was printed, it took longer than the run on a
// loaded machine, which had closed its server by then (net::ERR_CONNECTION_REFUSED).
const browser = await launch();
// Sequential: every keyframe mapped before the next frame, so the map grows frame by frame however
// loaded the machine is (a realtime run on a busy machine drops most frames).
// --view-wait: the first frame waits for the page, which so sees the whole run (a page that took
// most of the run to load on a loaded machine saw only its last two point counts).
const run = spawn(dsm, ['run', join(work, 'scene'), '--sequential', '--quiet', '--view', '--port', '0',
  '--view-wait', '300', '--out', join(work, 'run')], { stdio: ['ignore', 'pipe', 'inherit'] });
const exited = new Promise((resolve) => run.on('exit', (code) => resolve(code)));
let output = '';
const url = await new Promise((resolve, reject) => {
  run.stdout.on('data', (chunk) => {
    output += chunk;
    const m = output.match(/view: (http:\/\/127\.0\.0\.1:\d+\/)/);
    if (m) resolve(m[1]);
  });
  run.on('exit', () => reject(new Error('dsm exited before printing the address: ' + output)));
});
console.log('live viewer at', url);

try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  const errors = collectErrors(page);
  await page.goto(url);
  const seen = [];  // Point counts the page showed, in order.
  let done = false;
  exited.then(() => { done = true; });
  while (!done) {
    const points = await page.evaluate(() => window.dsmReport?.data?.summary?.map_points ?? null);
    if (points !== null && points !== seen[seen.length - 1]) seen.push(points);
    await new Promise((r) => setTimeout(r, 200));
  }
  const code = await exited;
  const updates = Number(await page.getAttribute('#live-status', 'data-updates'));
  const errorsDuringRun = errors.filter((e) => !e.includes('WebSocket'));  // Reconnects after the run ended.
  console.log(`point counts seen: ${seen.join(' ')}; ${updates} updates; dsm exit ${code}`);
  check(code === 0, `dsm exited with ${code}`);
  check(seen.length >= 3, `expected the point count to change at least twice, saw ${seen.join(' ')}`);
  check(seen[seen.length - 1] > seen[0], 'the point count did not grow');
  check(updates >= 5, `only ${updates} updates reached the page`);
  check(errorsDuringRun.length === 0, 'console errors: ' + errorsDuringRun.join(' | '));
  console.log('live view: ok');
} finally {
  await browser.close();
  run.kill();
}
