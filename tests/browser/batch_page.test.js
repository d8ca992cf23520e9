// A batch as a newcomer opens it (issue 48, item 5), in a real browser: orcs-batch runs four recorded jobs of the
// README's demo scenario, orcs-view opens the folder. The job table and a fitness histogram take the main area
// above the 3D view, which shows the fittest job at once; the header names the batch; the floor grid shows its
// lines running away from the camera (software GL dropped them whole: stripes); shadows can be switched on;
// clicking the robot's pelvis says which part was hit.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { mkdir, readFile, writeFile } from 'node:fs/promises';
import { spawn } from 'node:child_process';
import { repoRoot, binDir, tempDir, openViewer, frames, snapshotCanvas, diffSnapshots, until } from './helpers.js';

let tmp, server, page, close, folder;

function run(program, args) {
  const child = spawn(path.join(binDir, program), args, { cwd: repoRoot, stdio: ['ignore', 'ignore', 'pipe'] });
  let err = '';
  child.stderr.on('data', (d) => { err += d; });
  return new Promise((resolve) => child.once('exit', (code) => resolve({ code, err })));
}

before(async () => {
  tmp = await tempDir();
  folder = path.join(tmp.dir, 'rock');
  // The demo's scenario for 1.5 simulated seconds, not 4: the test looks at the page, not at the rocking.
  const scenario = JSON.parse(await readFile(path.join(repoRoot, 'scenarios/evolution/rock_oscillator.json'), 'utf8'));
  scenario.duration = 1.5;
  const scenarioFile = path.join(tmp.dir, 'rock.json');
  await writeFile(scenarioFile, JSON.stringify(scenario));
  const made = await run('orcs-batch', ['run', scenarioFile, '--jobs', '4',
    '--workers', '2', '--record', 'all', '--out', folder, '--quiet']);
  assert.equal(made.code, 0, made.err);
  ({ server, page, close } = await openViewer([folder], { tmp }));
});

after(async () => { await (close ? close() : tmp?.cleanup()); });

test('the batch opens with its table and histogram in the main area and its fittest job in the 3D view', async () => {
  const batch = await (await fetch(`${server.url}api/batch/${await page.evaluate(() => orcsView.item)}`)).json();
  const best = batch.jobs.reduce((a, b) => (b.fitness > a.fitness ? b : a));
  const shown = await until(() => page.evaluate(() => document.querySelector('#items li.current')?.dataset.id), 10_000, 'a job shown');
  assert.equal(shown, best.recording, `the fittest job (${best.job}, fitness ${best.fitness}) is shown`);
  assert.ok(Object.keys(await page.evaluate(() => orcsView.bodies)).length > 20, 'the robot in the 3D view');
  const layout = await page.evaluate(() => {
    const detail = document.getElementById('item-detail');
    return { inCentre: !!detail.closest('#center'), width: detail.getBoundingClientRect().width,
      rows: document.querySelectorAll('#batch-table tbody tr').length,
      histogram: document.querySelector('#fitness-histogram .u-title')?.textContent };
  });
  assert.equal(layout.inCentre, true, 'the table is above the 3D view, not in the side panel');
  assert.ok(layout.width > 500, `the table's area is ${layout.width} px wide`);
  assert.equal(layout.rows, 4);
  assert.equal(layout.histogram, 'Fitness of 4 jobs');
  assert.equal(await page.locator('#session-title').textContent(), 'rock', 'the header names the folder, not "orcs-view" twice');
});

test('the floor grid has lines along the view as well as across it (no stripes)', async () => {
  await page.click('[data-camera="front"]');
  await frames(page, 3);
  // Along a row near the bottom of the view (the floor in front of the robot), lines running away from the
  // camera cross it: count the runs of grid-line pixels, darker than the floor around them.
  const crossings = await page.evaluate(() => {
    const c = document.getElementById('canvas');
    const copy = document.createElement('canvas');
    copy.width = c.width; copy.height = c.height;
    const g = copy.getContext('2d');
    g.drawImage(c, 0, 0);
    const y = Math.floor(c.height * 0.95);
    const row = g.getImageData(0, y, c.width, 1).data;
    const lum = [];
    for (let x = 0; x < c.width; x++) lum.push(row[4 * x] + row[4 * x + 1] + row[4 * x + 2]);
    const floor = [...lum].sort((a, b) => a - b)[Math.floor(lum.length / 2)];
    let runs = 0, inLine = false;
    for (const l of lum) {
      const dark = l < floor - 30;
      if (dark && !inLine) runs++;
      inLine = dark;
    }
    return runs;
  });
  assert.ok(crossings >= 10, `${crossings} grid lines cross the bottom row of the floor`);
});

test('shadows start off in software GL and, switched on, darken the floor by the robot', async () => {
  assert.equal(await page.locator('#toggle-shadows').isChecked(), false);
  await frames(page, 2);
  await snapshotCanvas(page, 'no-shadow');
  await page.check('#toggle-shadows');
  await frames(page, 3);
  await snapshotCanvas(page, 'shadow');
  const d = await diffSnapshots(page, 'no-shadow', 'shadow');
  assert.ok(d.changed > 500, `${d.changed} pixels darkened by the shadow`);
  await page.uncheck('#toggle-shadows');
});

test('clicking the pelvis names the part hit, not only the invisible body that carries it', async () => {
  const at = await page.evaluate(() => orcsView.screenOf('Humanoid/Middle/InvisiblePart'));
  await page.mouse.click(at.x, at.y);
  await until(async () => /Middle\/InvisiblePart — its part /.test(await page.locator('#selection').textContent()), 5000,
    'the selection naming the part');
  assert.deepEqual(page.orcsProblems, []);
  if (!process.env.ORCS_SCREENSHOT_DIR) return;
  const dir = path.resolve(repoRoot, process.env.ORCS_SCREENSHOT_DIR);
  await mkdir(dir, { recursive: true });
  await page.check('#toggle-shadows');
  await frames(page, 3);
  await page.screenshot({ path: path.join(dir, 'viewer_batch.png') });
});
