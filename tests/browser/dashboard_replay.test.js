// orcs-view --broker ENDPOINT DIR in a real browser (docs/viewer.md, "From a job to its replay"): the real
// orcs-broker, two orcs-worker processes and `orcs-batch submit --record 1,3 --out DIR` on 127.0.0.1; then orcs-view
// on the broker and the batch folder. A worker's recent jobs that were recorded get a replay button naming the
// recording (the folder's progress.json gives the broker's batch id), the others none; clicking it opens the
// recording.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFile } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { writeFile } from 'node:fs/promises';
import path from 'node:path';
import { promisify } from 'node:util';
import {
  binDir, repoRoot, tempDir, startServer, launchBrowser, openPage, until, fetchJson, startChild, stopChildren,
  startBroker,
} from './helpers.js';

const run = promisify(execFile);
let tmp, broker, workers = [], server, browser, page, out;
let results;    // results.jsonl's lines
let recorded;   // [{job, worker, path}] of the recorded jobs, from results.jsonl
let progress;   // DIR/progress.json at the end of the batch

before(async () => {
  tmp = await tempDir();
  broker = await startBroker();
  for (const id of ['w0', 'w1']) {
    workers.push(startChild('orcs-worker', ['--connect', broker.workers, '--heartbeat', '0.1', '--id', id]));
  }
  const scenario = path.join(tmp.dir, 'scenario.json');
  await writeFile(scenario, JSON.stringify({
    name: 'replay-test', duration: 1,
    controller: { type: 'oscillator', joints: ['Right/HipYaw', 'Left/HipYaw'] },
    genome: [10, 1, 0, 0, 10, 1, 3, 0],
    fitness: { terms: [{ type: 'distance', body: 'Middle/UpperBody', axis: 'z' }] },
  }));
  out = path.join(tmp.dir, 'batch');
  // The whole batch first: orcs-view is started on a folder that exists (and has its recordings).
  await run(path.join(binDir, 'orcs-batch'), ['submit', '--broker', broker.clients, scenario, '--jobs', '4',
    '--record', '1,3', '--out', out, '--heartbeat', '0.1', '--quiet'], { cwd: repoRoot, timeout: 60_000 });
  results = readFileSync(path.join(out, 'results.jsonl'), 'utf8').split('\n').filter((l) => l.trim())
    .map((l) => JSON.parse(l));
  recorded = results.filter((r) => r.recording).map((r) => ({ job: r.id, worker: r.worker, path: r.recording }));
  progress = JSON.parse(readFileSync(path.join(out, 'progress.json'), 'utf8'));
  server = await startServer(['--broker', broker.clients, out]);
  browser = await launchBrowser();
  page = await openPage(browser, server.url);
});

after(async () => {
  await browser?.close();
  await server?.stop();
  await stopChildren([...workers, broker?.child]);
  await tmp?.cleanup();
});

/** The session's recording id of a job's recording (its path in the folder, "recordings/JOB.orcsrec"). */
async function recordingIdOf(relative) {
  const session = await fetchJson(`${server.url}api/session`);
  const item = session.items.find((i) => i.kind === 'recording' && path.resolve(i.path) === path.resolve(out, relative));
  assert.ok(item, `no item for ${relative} in ${JSON.stringify(session.items)}`);
  return item.id;
}

test('the batch folder names its broker batch; /api/replays lists its two recorded jobs', async () => {
  assert.equal(recorded.length, 2, 'jobs 1 and 3 were recorded');
  assert.equal(progress.format, 'orcs-progress');
  assert.equal(progress.command, 'submit');
  assert.equal(progress.state, 'finished');
  assert.equal(typeof progress.broker_batch, 'string');
  assert.ok(progress.broker_batch.length > 0);
  const { replays } = await fetchJson(`${server.url}api/replays`);
  const expected = await Promise.all(recorded.map(async (r) => ({
    batch: progress.broker_batch, job: r.job, recording: await recordingIdOf(r.path),
  })));
  const key = (r) => r.job;
  assert.deepEqual([...replays].sort((a, b) => key(a).localeCompare(key(b))),
    expected.sort((a, b) => key(a).localeCompare(key(b))));
});

test("a worker's recorded job has a replay button; clicking it opens the recording", async () => {
  assert.equal(await page.evaluate(() => orcsView.item), 'broker');
  await until(async () => page.evaluate(() => orcsView.broker?.workers === 2 && orcsView.broker?.replays === 2),
    20_000, 'the dashboard with both workers and the two replays');
  const job = recorded[0];
  const rid = await recordingIdOf(job.path);
  // The broker's status has the job among that worker's recent jobs, under the folder's batch id.
  const { stdout } = await run(path.join(binDir, 'orcs-broker'), ['status', '--broker', broker.clients, '--json']);
  const worker = JSON.parse(stdout).worker_list.find((w) => w.worker_id === job.worker);
  assert.ok(worker, `worker ${job.worker} in the status`);
  assert.ok(worker.recent_jobs.some((j) => j.job_id === job.job && j.batch_id === progress.broker_batch),
    JSON.stringify(worker.recent_jobs));

  // Each worker's recent jobs: the two recorded jobs have a button naming their recording, the other two none.
  const recordedIds = new Map(await Promise.all(recorded.map(async (r) => [r.job, await recordingIdOf(r.path)])));
  const rows = [];
  for (const id of [...new Set(results.map((r) => r.worker))].sort()) {
    const ran = results.filter((r) => r.worker === id).map((r) => r.id).sort();
    await page.click(`#dash-workers tbody tr[data-worker="${id}"]`);
    const shown = await until(async () => {
      const now = await page.evaluate(() => ({
        title: document.getElementById('dash-recent-title').textContent,
        rows: [...document.querySelectorAll('#dash-recent li')].map((li) => ({
          job: li.querySelector('.mono')?.textContent ?? null,
          replays: [...li.querySelectorAll('button.replay')].map((b) => b.dataset.recording),
        })),
      }));
      return now.title === `Recent jobs of ${id}` && now.rows.length === ran.length && now.rows;
    }, 10_000, `the ${ran.length} recent jobs of ${id}`);
    assert.deepEqual(shown.map((r) => r.job).sort(), ran);
    rows.push(...shown);
  }
  assert.equal(rows.length, 4);
  for (const row of rows) {
    assert.deepEqual(row.replays, recordedIds.has(row.job) ? [recordedIds.get(row.job)] : [], `row of ${row.job}`);
  }
  assert.equal(rows.filter((r) => r.replays.length).length, 2);

  await page.click(`#dash-workers tbody tr[data-worker="${job.worker}"]`);
  await until(async () => (await page.locator('#dash-recent-title').textContent()) === `Recent jobs of ${job.worker}`,
    10_000, `the recent jobs of ${job.worker}`);
  const exactly = new RegExp(`^${job.job.replace(/[.*+?^${}()|[\]\\]/g, '\\$&')}$`);
  const button = page.locator('#dash-recent li', { has: page.locator('.mono', { hasText: exactly }) })
    .locator('button.replay');
  await button.click();
  const opened = await until(async () => {
    const v = await page.evaluate(() => ({ item: orcsView.item, ready: orcsView.ready, mode: orcsView.mode,
      bodies: Object.keys(orcsView.bodies || {}).length }));
    return v.item === rid && v.ready && v;
  }, 20_000, `orcsView.item === ${rid}`);
  assert.equal(opened.mode, 'files');
  assert.ok(opened.bodies > 20, 'the A-Series is drawn');
  assert.equal(await page.locator('#dashboard').isVisible(), false, 'the dashboard gave way to the recording');
});

test('no console errors after all of the above', () => {
  assert.deepEqual(page.orcsProblems, []);
});
