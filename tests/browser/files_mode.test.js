// orcs-view in files mode, in a real browser: two recordings made here with orcs-sim (the A-Series standing,
// and the waist bend of scenarios/motions), served by the real orcs-view, drawn by the page.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { mkdir } from 'node:fs/promises';
import { availableParallelism, loadavg } from 'node:os';
import {
  repoRoot, tempDir, makeRecording, startServer, launchBrowser, openPage, frames, snapshotCanvas, diffSnapshots,
  fetchArray, fetchJson, until,
} from './helpers.js';

let tmp, server, browser, page;

before(async () => {
  tmp = await tempDir();
  const stand = path.join(tmp.dir, 'stand.orcsrec');
  const bend = path.join(tmp.dir, 'waist_bend.orcsrec');
  const two = path.join(tmp.dir, 'two_robots.orcsrec');
  await Promise.all([
    makeRecording(stand),
    makeRecording(two, ['-env', path.join(repoRoot, 'scenarios/environments/two_robots.xml'), '--duration', '0.5']),
    makeRecording(bend, ['-play', 'Humanoid', path.join(repoRoot, 'scenarios/motions/waist_bend.csv')]),
  ]);
  server = await startServer([stand, bend, two]);
  browser = await launchBrowser();
  page = await openPage(browser, server.url);
});

after(async () => {
  await browser?.close();
  await server?.stop();
  await tmp?.cleanup();
});

function headName(header) {
  const names = header.bodies.map((b) => b.name);
  return names.find((n) => n === 'Humanoid/Head') || names.find((n) => /^Humanoid\/(.*\/)?Head$/.test(n));
}

test('the page loads a recording with no console errors', async () => {
  const state = await page.evaluate(() => ({ ...window.orcsView }));
  assert.equal(state.mode, 'files');
  assert.equal(state.item, 'r0');
  assert.equal(state.ready, true);
  assert.deepEqual(state.errors, []);
  assert.ok(Object.keys(state.bodies).length > 20, 'the A-Series bodies are in orcsView.bodies');
  assert.equal(await page.locator('#banner').isVisible(), false);
  assert.deepEqual(page.orcsProblems, []);
});

test('the robot is drawn: hiding the bodies changes the robot region, not the bare floor', async () => {
  await page.evaluate(() => window.orcsView.seek(0));
  await page.click('[data-camera="front"]');
  await frames(page, 3);
  await snapshotCanvas(page, 'shown');
  await page.uncheck('#toggle-bodies');
  await frames(page, 3);
  await snapshotCanvas(page, 'hidden');
  await page.check('#toggle-bodies');
  await frames(page, 2);
  const { changed, centre: changedNearCentre, corner: changedInCorner } = await diffSnapshots(page, 'shown', 'hidden');
  // The front preset centres the robot: its pixels are there, the bare floor in the bottom-left corner stays.
  assert.ok(changed > 2000, `only ${changed} pixels show the robot`);
  assert.ok(changedNearCentre > 0.8 * changed, `${changedNearCentre} of ${changed} changed pixels near the centre`);
  assert.equal(changedInCorner, 0, 'the bare floor in the corner does not change');
});

test('scrubbing to t = 5 s draws the head at its recorded position', async () => {
  const header = await fetchJson(`${server.url}api/recording/r0`);
  const times = await fetchArray(`${server.url}api/recording/r0/times`, Float64Array);
  assert.equal(times.length, header.frames);
  const head = headName(header);
  assert.ok(head, 'the recording has a head body');
  const body = header.bodies.find((b) => b.name === head);
  const ids = body.pose_channels;
  const values = await fetchArray(`${server.url}api/recording/r0/channels?ids=${ids.join(',')}`, Float32Array);
  let k = 0;
  for (let i = 1; i < times.length; i++) if (Math.abs(times[i] - 5) < Math.abs(times[k] - 5)) k = i;
  assert.ok(Math.abs(times[k] - 5) < 0.011, `a frame at 5 s (nearest: ${times[k]})`);
  const n = times.length;
  const expect = (c, f) => values[c * n + f];

  // The scrub slider (frames) in the UI.
  await page.locator('#tl-slider').fill(String(k));
  await frames(page, 2);
  let state = await page.evaluate((name) => ({ frame: orcsView.frame, time: orcsView.time, head: orcsView.bodies[name] }), head);
  assert.equal(state.frame, k);
  assert.ok(Math.abs(state.time - 5) < 0.011, `time shown ${state.time}`);
  for (let a = 0; a < 3; a++) assert.ok(Math.abs(state.head.position[a] - expect(a, k)) < 1e-5, `position[${a}]: ${state.head.position[a]} vs ${expect(a, k)}`);
  for (let a = 0; a < 4; a++) assert.ok(Math.abs(state.head.quaternion[a] - expect(3 + a, k)) < 1e-5, `quaternion[${a}]`);
  assert.match(await page.locator('#tl-time').textContent(), /t = 5\.00\d s/);

  // And orcsView.seek(5) from a script, from elsewhere in the run.
  await page.evaluate(() => orcsView.seek(1));
  await page.evaluate(() => orcsView.seek(5));
  state = await page.evaluate((name) => ({ frame: orcsView.frame, head: orcsView.bodies[name] }), head);
  for (let a = 0; a < 3; a++) assert.ok(Math.abs(state.head.position[a] - expect(a, state.frame)) < 1e-5);
  assert.ok(Math.abs(times[state.frame] - 5) < 0.011);
});

test('clicking a joint in the list plots its angle', async () => {
  await page.locator('#tree li[data-name$="Right/Knee"]').first().click();
  await page.locator('#plots .uplot canvas').first().waitFor({ state: 'visible' });
  const plots = await page.evaluate(() => orcsView.plots);
  assert.ok(plots.includes('/Sim/Humanoid/Right/Knee/JointAngle'), `plots: ${plots}`);
  assert.ok(plots.includes('/Sim/Humanoid/Right/Knee/DesiredAngle'));
  assert.match(await page.locator('#plots').textContent(), /\[deg\]/);
});

test('clicking the robot in the 3D view selects a body and plots its position', async () => {
  await page.evaluate(() => { orcsView.seek(0); });
  await page.click('[data-camera="front"]');
  await frames(page, 2);
  // The front preset looks at the robot's centre: the middle of the view is on the robot.
  const box = await page.locator('#canvas').boundingBox();
  await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
  const plots = await until(async () => {
    const p = await page.evaluate(() => orcsView.plots);
    return p.length === 3 && p;
  }, 20_000, 'the picked body\'s plots');
  const body = /^\/Sim\/(.+)\/Position\.x$/.exec(plots[0]);
  assert.ok(body, `plots: ${plots}`);
  assert.ok(body[1].startsWith('Humanoid/'), `picked ${body[1]}`);
  assert.match(await page.locator('#selection').textContent(), new RegExp(`body: ${body[1]}`));
  assert.equal(await page.locator('#tree li.current').getAttribute('data-name'), body[1]);
});

test('orcsView.select on a body plots its position; a channel search adds any channel', async () => {
  const header = await fetchJson(`${server.url}api/recording/r0`);
  const head = headName(header);
  assert.equal(await page.evaluate((n) => orcsView.select(n), head), true);
  let plots = await page.evaluate(() => orcsView.plots);
  assert.deepEqual(plots, ['x', 'y', 'z'].map((a) => `/Sim/${head}/Position.${a}`));
  await page.fill('#channel-search', '/Left\\/Knee\\/JointAngle$/');
  await page.locator('#channel-results li', { hasText: 'Left/Knee/JointAngle' }).first().click();
  plots = await until(async () => {
    const p = await page.evaluate(() => orcsView.plots);
    return p.includes('/Sim/Humanoid/Left/Knee/JointAngle') && p;
  }, 20_000, 'the searched channel in the plots');
  assert.equal(plots.length, 4);
  // The chart is made once the channel's data has arrived: awaited, since a loaded machine takes its time.
  await until(async () => (await page.locator('#plots .uplot').count()) === 2, 20_000, 'one chart in m, one in deg');
});

test('a second run overlays the plots, the legend names both runs', async () => {
  await page.evaluate(() => orcsView.select('Waist'));
  await page.selectOption('#compare', 'r1');
  const legend = await until(async () => {
    const text = await page.locator('#plots .u-legend').first().textContent();
    return /waist_bend/.test(text) && text;
  }, 10_000, 'the overlaid run in the legend');
  assert.match(legend, /stand/);
  assert.match(legend, /waist_bend/);
  await page.selectOption('#compare', '');
});

test('play, pause, step and the frame rate', async () => {
  // What the browser manages with nothing to draw (paused, the page draws only on change): the ceiling.
  const ceiling = await page.evaluate(() => new Promise((resolve) => {
    let n = 0;
    const t0 = performance.now();
    const f = () => { n++; if (performance.now() - t0 < 1000) requestAnimationFrame(f); else resolve(n); };
    requestAnimationFrame(f);
  }));
  // Playing: frames drawn over 3 s, after 2 s in which the page settles its drawing resolution.
  await page.evaluate(() => { orcsView.seek(0); orcsView.play(); });
  await page.waitForTimeout(2000);
  const start = await page.evaluate(() => ({ drawn: orcsView.drawn, at: performance.now() }));
  await page.waitForTimeout(3000);
  const playing = await page.evaluate(() => {
    const c = document.getElementById('canvas');
    return { drawn: orcsView.drawn, at: performance.now(), time: orcsView.time, playing: orcsView.playing,
      buffer: `${c.width}x${c.height}`, css: `${c.clientWidth}x${c.clientHeight}` };
  });
  playing.fps = Math.round((10 * 1000 * (playing.drawn - start.drawn)) / (playing.at - start.at)) / 10;
  console.log(`fps: ${playing.fps} (a 10 s A-Series recording at 1x, frames drawn from 2 s to 5 s of playing; drawing ` +
    `buffer ${playing.buffer} for a ${playing.css} view; requestAnimationFrame alone: ${ceiling}/s)`);
  assert.equal(playing.playing, true);
  assert.ok(playing.time > 1, `simulated time advanced to ${playing.time}`);
  // A broken render loop draws next to nothing. 20 fps is the bar on a machine with cores to spare. SwiftShader
  // draws on the CPU, so on an oversubscribed machine (load above the core count) the bar falls in proportion,
  // and where the browser itself cannot animate at 40/s it is a third of what it can; never below 3.
  const cores = availableParallelism(), load = loadavg()[0];
  let bar = ceiling >= 40 ? 20 : ceiling / 3;
  if (load > cores) bar = Math.min(bar, (20 * cores) / load);
  bar = Math.max(3, bar);
  console.log(`fps bar: ${bar.toFixed(1)} (load ${load.toFixed(1)} on ${cores} cores)`);
  assert.ok(playing.fps > bar, `fps ${playing.fps} (bar ${bar.toFixed(1)}): the render loop is broken`);
  await page.keyboard.press('Space');
  const paused = await page.evaluate(() => ({ playing: orcsView.playing, time: orcsView.time, frame: orcsView.frame }));
  assert.equal(paused.playing, false);
  await frames(page, 3);
  assert.equal(await page.evaluate(() => orcsView.time), paused.time, 'paused: the clock stands');
  await page.keyboard.press('ArrowRight');
  assert.equal(await page.evaluate(() => orcsView.frame), paused.frame + 1);
  await page.evaluate(() => orcsView.step(-2));
  assert.equal(await page.evaluate(() => orcsView.frame), paused.frame - 1);
  await page.selectOption('#tl-speed', '0.25');
  assert.equal(await page.evaluate(() => orcsView.speed), 0.25);
  await page.selectOption('#tl-speed', '1');
});

test('a bad item is shown in the banner and in orcsView.errors, not on the console', async () => {
  const before = await page.evaluate(() => orcsView.errors.length);
  const problems = page.orcsProblems.length;
  await page.evaluate(() => orcsView.open('r99'));
  await page.locator('#banner').waitFor({ state: 'visible' });
  const errors = await page.evaluate(() => orcsView.errors);
  assert.equal(errors.length, before + 1);
  assert.match(errors.at(-1), /r99/);
  assert.equal(await page.evaluate(() => orcsView.item), 'r0', 'the shown run stays');
  await page.click('#banner-close');
  // Chromium logs the 404 answer itself as a failed resource; the page adds nothing to the console.
  const added = page.orcsProblems.splice(problems);
  assert.ok(added.every((p) => /status of 404/.test(p)), added.join('\n'));
});

test('several robots: every agent of the world is drawn where it stands', async () => {
  assert.equal(await page.evaluate(() => orcsView.open('r2')), true);
  const bodies = await until(async () => {
    const b = await page.evaluate(() => orcsView.bodies);
    return b['Partner/Middle/Head'] && b;
  }, 20_000, 'the second robot drawn');
  const x = (name) => bodies[name].position[0];
  assert.ok(Math.abs(x('Humanoid/Middle/Head') - 0.2) < 0.05, `Humanoid at x = 0.2, found ${x('Humanoid/Middle/Head')}`);
  assert.ok(Math.abs(x('Partner/Middle/Head') + 0.2) < 0.05, `Partner at x = -0.2, found ${x('Partner/Middle/Head')}`);
  assert.ok(bodies.Ball, 'the ball between them');
  assert.equal(await page.evaluate(() => orcsView.open('r1')), true);
});

test('screenshot: a body selected and a plot shown (ORCS_SCREENSHOT_DIR)', async (t) => {
  await page.evaluate(async () => {
    await orcsView.open('r1');
    orcsView.seek(4.2);
    await orcsView.select('Waist');
  });
  await page.selectOption('#compare', 'r0');
  await page.fill('#channel-search', '');
  await page.click('[data-camera="follow"]');
  await page.evaluate(() => {
    const names = Object.keys(orcsView.bodies);
    return orcsView.select(names.find((n) => /UpperBody$/.test(n)) || names.find((n) => /Head$/.test(n)));
  });
  await page.evaluate(() => orcsView.plot('/Sim/Humanoid/Waist/JointAngle'));
  await frames(page, 3);
  assert.equal(await page.evaluate(() => orcsView.item), 'r1');
  if (!process.env.ORCS_SCREENSHOT_DIR) { t.skip('ORCS_SCREENSHOT_DIR not set'); return; }
  const dir = path.resolve(repoRoot, process.env.ORCS_SCREENSHOT_DIR);
  await mkdir(dir, { recursive: true });
  await page.screenshot({ path: path.join(dir, 'viewer.png') });
});

test('no console errors after all of the above', () => {
  assert.deepEqual(page.orcsProblems, []);
});
