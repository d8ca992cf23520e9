// orcs-view --broker in a real browser (issue 21, item 2): the real orcs-broker, two orcs-worker processes and
// `orcs-batch submit` on 127.0.0.1. The dashboard shows the numbers `orcs-broker status --json` gives — workers,
// busy workers, the batch's counts — while the batch runs, updates itself without a reload (its long poll), and
// shows one worker fewer after one is killed.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn, execFile } from 'node:child_process';
import { mkdir, writeFile } from 'node:fs/promises';
import path from 'node:path';
import { createInterface } from 'node:readline';
import { promisify } from 'node:util';
import { repoRoot, binDir, tempDir, startServer, launchBrowser, openPage, until } from './helpers.js';

const run = promisify(execFile);
let tmp, broker, endpoints, workers = [], submit, server, browser, page;

/** A child process, killed at the end. */
function start(program, args) {
  const child = spawn(path.join(binDir, program), args, { cwd: repoRoot, stdio: ['ignore', 'pipe', 'pipe'] });
  child.stderr.on('data', () => {});
  return child;
}

async function startBroker() {
  const child = start('orcs-broker', ['--client-port', '0', '--worker-port', '0', '--heartbeat', '0.1']);
  const line = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error('orcs-broker printed no endpoints in 10 s')), 10_000);
    createInterface({ input: child.stdout }).once('line', (l) => { clearTimeout(timer); resolve(l); });
  });
  const m = /clients=(\S+) workers=(\S+)/.exec(line);
  assert.ok(m, `endpoints line: ${line}`);
  return { child, clients: m[1], workers: m[2] };
}

async function statusJson() {
  const { stdout } = await run(path.join(binDir, 'orcs-broker'), ['status', '--broker', endpoints.clients, '--json']);
  return JSON.parse(stdout);
}

const shown = () => page.evaluate(() => ({
  broker: orcsView.broker,
  summary: Object.fromEntries([...document.querySelectorAll('#dash-summary .figure')].map((f) => [f.dataset.name, f.querySelector('b').textContent])),
  workerRows: [...document.querySelectorAll('#dash-workers tbody tr')].map((r) => r.dataset.worker),
  batchRows: [...document.querySelectorAll('#dash-batches tbody tr')].map((r) => [...r.children].map((c) => c.textContent)),
}));

before(async () => {
  tmp = await tempDir();
  const b = await startBroker();
  broker = b.child;
  endpoints = b;
  for (const id of ['w0', 'w1']) workers.push(start('orcs-worker', ['--connect', endpoints.workers, '--heartbeat', '0.1', '--id', id]));
  server = await startServer(['--broker', endpoints.clients]);
  browser = await launchBrowser();
  page = await openPage(browser, server.url);
});

after(async () => {
  await browser?.close();
  await server?.stop();
  for (const child of [submit, ...workers, broker]) if (child && child.exitCode === null) child.kill('SIGKILL');
  await tmp?.cleanup();
});

test('the dashboard is the first item and shows both workers', async () => {
  assert.equal(await page.evaluate(() => orcsView.item), 'broker');
  await until(async () => (await shown()).broker?.workers === 2, 20_000, 'two workers on the dashboard');
  const status = await statusJson();
  assert.equal(status.workers, 2);
  assert.deepEqual((await shown()).workerRows.sort(), ['w0', 'w1']);
});

test('during a batch it shows what orcs-broker status shows, updated without a reload', async () => {
  const scenario = path.join(tmp.dir, 'scenario.json');
  await writeFile(scenario, JSON.stringify({
    name: 'dashboard-test', duration: 10,
    controller: { type: 'oscillator', joints: ['Right/HipYaw', 'Left/HipYaw'] },
    genome: [10, 1, 0, 0, 10, 1, 3, 0],
    fitness: { terms: [{ type: 'distance', body: 'Middle/UpperBody', axis: 'z' }] },
  }));
  submit = start('orcs-batch', ['submit', '--broker', endpoints.clients, scenario, '--jobs', '16', '--out',
    path.join(tmp.dir, 'out'), '--heartbeat', '0.1', '--quiet']);
  const serialBefore = await page.evaluate(() => orcsView.broker.serial);
  // Wait until the page and the broker agree on a moment with both workers busy and some jobs done.
  let agreed = null;
  await until(async () => {
    const status = await statusJson();
    const page_ = await shown();
    const batch = status.batch_list[0];
    if (!batch || status.busy_workers !== 2 || batch.done === 0) return false;
    if (page_.broker.busy !== 2 || page_.broker.batches !== 1) return false;
    // The page polls once a second: compare the slow-moving figures, and the batch's total.
    agreed = { status, page_ };
    return page_.summary.workers === String(status.workers) && page_.summary.busy === String(status.busy_workers);
  }, 60_000, 'the dashboard showing the running batch');
  const { status, page_ } = agreed;
  assert.ok(page_.broker.serial > serialBefore, 'new answers arrived by the long poll');
  assert.equal(page_.batchRows.length, 1);
  const [id, , , queued, running, done, failed, of] = page_.batchRows[0];
  assert.equal(id, status.batch_list[0].batch_id);
  assert.equal(of, '16');
  assert.equal(Number(queued) + Number(running) + Number(done) + Number(failed), 16, 'every job counted once');
});

test('after a worker is killed it shows one worker', async () => {
  workers[0].kill('SIGKILL');
  await until(async () => (await shown()).broker?.workers === 1, 20_000, 'one worker on the dashboard');
  const status = await statusJson();
  assert.equal(status.workers, 1);
  const page_ = await shown();
  assert.deepEqual(page_.workerRows, ['w1']);
  assert.equal(page_.summary.workers, '1');
  assert.ok(status.workers_lost >= 1);
});

test('screenshot: the dashboard during a batch (ORCS_SCREENSHOT_DIR)', async (t) => {
  await until(async () => (await shown()).broker?.points >= 5, 20_000, 'a few points in the charts');
  await page.click('#dash-workers tbody tr');
  if (!process.env.ORCS_SCREENSHOT_DIR) { t.skip('ORCS_SCREENSHOT_DIR not set'); return; }
  const dir = path.resolve(repoRoot, process.env.ORCS_SCREENSHOT_DIR);
  await mkdir(dir, { recursive: true });
  await page.screenshot({ path: path.join(dir, 'dashboard.png') });
});

test('no console errors after all of the above', () => {
  assert.deepEqual(page.orcsProblems, []);
});
