// A gap report as orcs-view shows it, in a real browser. The folder is laid out as orcs-gap writes one
// (report.json with its verdict, replays/<run>.orcsrec, <run>.given.orcsrec, <run>.measured.orcsrec: docs/gap.md),
// its recordings made here with orcs-sim: a diagnosis itself takes minutes, and the page is what is tested. The
// report takes the main area above the 3D view, naming the missing effect; the first run opens at once with its
// measured run overlaid (the plots' overlay and the ghost); "model as given" opens the replay before the fit.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { mkdir, writeFile } from 'node:fs/promises';
import { repoRoot, tempDir, makeRecording, openViewer, frames, until } from './helpers.js';

let tmp, server, page, close;

before(async () => {
  tmp = await tempDir();
  const folder = path.join(tmp.dir, 'waist-gap');
  const replays = path.join(folder, 'replays');
  await mkdir(replays, { recursive: true });
  await writeFile(path.join(folder, 'report.json'), JSON.stringify({ verdict: { effect: 'LuGre' } }));
  const bend = ['-play', 'Humanoid', path.join(repoRoot, 'scenarios/motions/waist_bend.csv'), '--duration', '1.5'];
  await Promise.all([
    makeRecording(path.join(replays, 'waist_bend.orcsrec'), bend),
    makeRecording(path.join(replays, 'waist_bend.given.orcsrec'), [...bend, '-ival', path.join(repoRoot, 'scenarios/values/servo_ax12.val')]),
    makeRecording(path.join(replays, 'waist_bend.measured.orcsrec'), ['--duration', '1.5']),
  ]);
  ({ server, page, close } = await openViewer([folder], { tmp }));
});

after(async () => { await (close ? close() : tmp?.cleanup()); });

test('the report names its effect above the 3D view, which opens its first run with the measured run overlaid', async () => {
  const detail = page.locator('#item-detail');
  await until(async () => /missing effect: LuGre/.test(await detail.textContent()), 10_000, 'the verdict shown');
  assert.equal(await page.evaluate(() => !!document.getElementById('item-detail').closest('#center')), true);
  const shown = await until(() => page.evaluate(() => document.querySelector('#items li.current')?.dataset.id), 10_000, 'a run shown');
  const items = (await (await fetch(`${server.url}api/session`)).json()).items;
  const label = (id) => items.find((i) => i.id === id)?.label;
  assert.equal(label(shown), 'waist_bend', 'the replay under the fitted model');
  const overlaid = await until(() => page.locator('#compare').inputValue(), 10_000, 'an overlay');
  assert.equal(label(overlaid), 'waist_bend.measured', 'the measured run overlaid');
  assert.equal(await page.locator('#session-title').textContent(), 'waist-gap');
  await page.click('#gap-runs button', { hasText: 'model as given' });
  const given = await until(() => page.evaluate((before) => {
    const id = document.querySelector('#items li.current')?.dataset.id;
    return id !== before && id;
  }, shown), 10_000, 'the given replay shown');
  assert.equal(label(given), 'waist_bend.given');
  assert.equal(label(await until(() => page.locator('#compare').inputValue(), 10_000, 'the overlay again')),
    'waist_bend.measured', 'the measured run overlaid on the given replay too');
  await frames(page, 3);
  assert.deepEqual(page.orcsProblems, []);
  if (!process.env.ORCS_SCREENSHOT_DIR) return;
  const dir = path.resolve(repoRoot, process.env.ORCS_SCREENSHOT_DIR);
  await mkdir(dir, { recursive: true });
  await page.evaluate(() => orcsView.seek(1.2));
  await frames(page, 3);
  await page.screenshot({ path: path.join(dir, 'viewer_gap.png') });
});
