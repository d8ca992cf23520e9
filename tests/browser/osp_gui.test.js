// orcs-osp -gui, the original ClientSimulator's -gui, in a real browser: orcs-osp hands its world to orcs-view,
// whose live simulation the OSP clients step. The shipped example client (scripts/osp_example_client.py) swings a
// robot's shoulder while the page watches: the page's frames follow the client's steps, the arm moves in the 3D
// view, the run bar says who drives, the page offers no Run, Step or Reset (the server refuses them), and the
// client's reset at its end takes the page back to step 0.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { spawn } from 'node:child_process';
import { mkdir } from 'node:fs/promises';
import { repoRoot, openViewer, fetchJson, until } from './helpers.js';

let server, page, close;

before(async () => {
  ({ server, page, close } = await openViewer(['-gui', '-port', '0', '-odcp_port', '0', '--view-port', '0'], { program: 'orcs-osp' }));
});

after(async () => { await close?.(); });

/** The example client for `steps` steps on the gateway: resolves to {code, out}. */
function exampleClient(steps) {
  const child = spawn('python3', [path.join(repoRoot, 'scripts/osp_example_client.py'), '--host', server.osp.host,
    '--port', String(server.osp.port), '--joint', 'Right/ShoulderYaw', '--steps', String(steps)], { stdio: ['ignore', 'pipe', 'pipe'] });
  let out = '';
  child.stdout.on('data', (d) => { out += d; });
  child.stderr.on('data', (d) => { out += d; });
  return new Promise((resolve) => child.once('exit', (code) => resolve({ code, out })));
}

test('an OSP client drives the simulation the page shows; the page watches and cannot step it', async () => {
  assert.ok(server.osp, `orcs-view printed its OSP address: ${server.stderr()}`);
  const bar = page.locator('#live-time');
  await until(async () => new RegExp(`driven over OSP at ${server.osp.host}:${server.osp.port}`).test(await bar.textContent()),
    10_000, 'the run bar naming the OSP server');
  for (const id of ['live-run', 'live-step', 'live-reset']) assert.equal(await page.locator(`#${id}`).isVisible(), false, `#${id} hidden`);
  const arm = 'Humanoid/Right/UpperArm';
  const before = await page.evaluate((b) => orcsView.bodies[b].quaternion.slice(), arm);
  assert.equal(await page.evaluate(() => orcsView.frame), 0);

  // 1200 steps (about 3 s on an idle machine): with 300 a loaded machine's page sampled too seldom, and the client had
  // finished and reset the world before the page saw the arm turned.
  const client = exampleClient(1200);
  // The arm swings to and fro (a period of 150 steps): sampled while the client steps, the page shows the steps
  // advancing and the arm turned by more than 5° at some frame. (A loaded machine samples seldom: the condition
  // collects what it saw rather than asking for both at one sample.)
  let most = 0, latest = 0;
  await until(() => page.evaluate((b) => [orcsView.frame, orcsView.bodies[b].quaternion.slice()], arm).then(([frame, q]) => {
    const turned = 2 * Math.acos(Math.min(1, Math.abs(before.reduce((s, x, i) => s + x * q[i], 0)))) * 180 / Math.PI;
    most = Math.max(most, turned);
    latest = Math.max(latest, frame);
    return latest >= 30 && most > 5;
  }), 30_000, 'the page following the client\'s steps and the arm turning by over 5°');
  if (process.env.ORCS_SCREENSHOT_DIR) {
    const dir = path.resolve(repoRoot, process.env.ORCS_SCREENSHOT_DIR);
    await mkdir(dir, { recursive: true });
    await page.click('[data-camera="follow"]');
    await page.screenshot({ path: path.join(dir, 'viewer_osp.png') });
  }
  const { code, out } = await client;
  assert.equal(code, 0, out);
  assert.match(out, /steps: 1200/);
  await until(() => page.evaluate(() => orcsView.frame === 0 && orcsView.time === 0), 10_000, 'the client\'s reset shown');

  const { token } = await fetchJson(`${server.url}api/live/claim`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: '{}' });
  const refused = await fetch(`${server.url}api/live/control`, {
    method: 'POST', headers: { 'Content-Type': 'application/json', 'X-Orcs-Token': token }, body: JSON.stringify({ action: 'run' }),
  });
  assert.equal(refused.status, 400);
  assert.match(await refused.text(), /OSP clients step and reset this simulation/);
  assert.deepEqual(page.orcsProblems, []);
});
