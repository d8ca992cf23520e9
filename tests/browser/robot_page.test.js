// A robot run watched live in a real browser (docs/hardware.md, "Watching a run"): the real orcs-robot plays the
// waist bend on 21 emulated AX-12+ (a hidden 100 ms delay in them) with --view DIR, and orcs-view, started on DIR while the robot moves, follows it
// without a reload — the robot as measured in the 3D view with its simulated twin as the ghost, the waist's measured
// and commanded angles plotted (the twin's dashed) — until the run ends; "twin (simulated)" swaps the two.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, readFileSync } from 'node:fs';
import { mkdir, writeFile } from 'node:fs/promises';
import path from 'node:path';
import {
  repoRoot, tempDir, startServer, launchBrowser, openPage, until, fetchJson, startChild, stopChildren, frames,
  snapshotCanvas, diffSnapshots,
} from './helpers.js';

let tmp, robot, server, browser, page, folder;

before(async () => {
  tmp = await tempDir();
  // The browser first: on two loaded cores it can take longer to start than the robot's 10 s run, which must still
  // be under way when the page first shows it.
  browser = await launchBrowser();
  folder = path.join(tmp.dir, 'bend-on-robot');
  // The emulated servos are orcs's simulation with a hidden 100 ms delay, which the twin lacks: the two part visibly.
  const hidden = path.join(tmp.dir, 'hidden_delay.val');
  await writeFile(hidden, '#ORCS Values\n/Effects/TransportDelay/Enabled=T\n/Effects/TransportDelay/Delay=0.1\n');
  robot = startChild('orcs-robot', [
    '--map', path.join(repoRoot, 'scenarios/robots/aseries.joints.json'),
    '--play', path.join(repoRoot, 'scenarios/motions/waist_bend.csv'),
    // A browser starting on the same two cores delays a period now and then: that rule has its own test
    // (tests/hardware/robot/orcs_robot_test.cc); here the run must go on to be watched.
    '--emulate', '--emulate-val', hidden, '--yes', '--rate', '25', '--deadline-streak', '1000', '--view', folder,
  ]);
  // orcs-view opens the folder once the robot's first frames are there.
  const ended = () => robot.exitCode !== null || robot.signalCode !== null;  // an abort has a signal, no code
  await until(() => existsSync(path.join(folder, 'robot.orcsrec')) || ended(), 20_000, 'the first flush');
  assert.ok(!ended(), `orcs-robot ended early: ${robot.stderrText()}`);
  server = await startServer([folder]);
  page = await openPage(browser, server.url);
});

after(async () => {
  await browser?.close();
  await server?.stop();
  await stopChildren([robot]);
  await tmp?.cleanup();
});

const shown = () => page.evaluate(() => ({
  item: document.querySelector('#items li.current')?.dataset.id, frames: orcsView.frames, overlay: orcsView.overlayFrames, ghost: orcsView.ghostBodies,
  plots: orcsView.plots, progress: orcsView.progress?.state ?? null,
}));

test('the page follows the robot and its twin while the robot moves, and to the run\'s end', async () => {
  const items = (await fetchJson(`${server.url}api/session`)).items;
  const label = (id) => items.find((i) => i.id === id)?.label;
  const first = await until(async () => { const s = await shown(); return s.frames > 0 && s.overlay > 0 && s; }, 20_000,
    'the robot shown with its twin overlaid');
  assert.equal(label(first.item), 'robot', 'the robot as measured is the main run');
  assert.equal(label(await page.locator('#compare').inputValue()), 'twin', 'its twin is the overlay');
  assert.ok(first.ghost > 0, 'the twin is drawn as a ghost');
  assert.deepEqual(first.plots, ['/Sim/Humanoid/Waist/JointAngle', '/Sim/Humanoid/Waist/DesiredAngle']);
  assert.equal(first.progress, 'running', robot.stderrText());
  assert.match(await page.locator('#run-progress').textContent(), /robot running/);
  // Live: without a reload, more of the run arrives while the robot still moves (a flush every 0.5 s, a look every s).
  const grown = await until(async () => { const s = await shown(); return s.frames >= first.frames + 25 && s; }, 20_000,
    `the run grown in the page (first shown at ${first.frames} frames)`);
  assert.equal(grown.progress, 'running', 'grown while the robot was still moving');
  // The end: the run's every control period, in the page as on disk.
  const ended = await robot.exited;
  assert.equal(ended.code, 0, robot.stderrText());
  const last = await until(async () => { const s = await shown(); return s.progress === 'finished' && s; }, 20_000, 'the end');
  const progress = JSON.parse(readFileSync(path.join(folder, 'progress.json'), 'utf8'));
  await until(async () => (await shown()).frames === progress.periods, 10_000, 'every period shown');
  assert.equal(progress.periods, 252, 'a 10 s bend at 25 Hz, and the period that logs where it ended');
  assert.match(await page.locator('#run-progress').textContent(), /robot finished/);
  assert.ok(last.overlay > 0);
  // What it draws: the ghost is there (hiding it changes the picture) and the robot bends (the pose at 5 s differs
  // from the start's).
  await page.evaluate(() => orcsView.seek(5.0));
  await frames(page, 3);
  await snapshotCanvas(page, 'with-ghost');
  await page.click('#toggle-ghost');
  await frames(page, 3);
  await snapshotCanvas(page, 'without-ghost');
  await page.click('#toggle-ghost');
  const ghostDiff = await diffSnapshots(page, 'with-ghost', 'without-ghost');
  assert.ok(ghostDiff.changed > 500, `the twin's ghost is drawn: ${JSON.stringify(ghostDiff)}`);
  assert.equal(label(await page.locator('#compare').inputValue()), 'twin', 'still named as the overlay after the run grew');
  await page.evaluate(() => orcsView.seek(0));
  await frames(page, 3);
  await snapshotCanvas(page, 'start');
  await page.evaluate(() => orcsView.seek(5.0));
  await frames(page, 3);
  await snapshotCanvas(page, 'bent');
  assert.ok((await diffSnapshots(page, "start", "bent")).centre > 500, 'the robot bends');
  assert.deepEqual(page.orcsProblems, []);
  if (process.env.ORCS_SCREENSHOT_DIR) {
    const dir = path.resolve(repoRoot, process.env.ORCS_SCREENSHOT_DIR);
    await mkdir(dir, { recursive: true });
    await page.click('button[data-camera="left"]');
    await page.evaluate(() => orcsView.seek(3.0));
    await frames(page, 3);
    await page.screenshot({ path: path.join(dir, 'viewer_robot.png') });
  }
  // The other way round: the twin in the view, the robot its ghost.
  await page.click('#robot-show-twin');
  const swapped = await until(async () => {
    const s = await shown();
    return label(s.item) === 'twin' && label(await page.locator('#compare').inputValue()) === 'robot' && s;
  }, 10_000, 'the twin shown, the robot its overlay');
  assert.equal(swapped.frames, progress.periods);
});
