// orcs-view following a run in progress, in a real browser (docs/viewer.md, "Runs in progress"): the real
// orcs-broker with no worker at first, `orcs-batch evolve --broker` writing its folder, and orcs-view started on
// that folder while it holds only progress.json. The page shows the run at generation 0 of 6 with nothing done;
// then an orcs-worker connects, runs three generations and is killed: without a reload, the page shows the curve
// grown to three points and the run still going. A second worker finishes the run, and the page follows it to
// its end: the progress line says finished, the curve has generations 0 to 6, and the winner's recording joins
// the item list and opens.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, readFileSync, readdirSync } from 'node:fs';
import { mkdir, writeFile } from 'node:fs/promises';
import path from 'node:path';
import {
  repoRoot, tempDir, startServer, launchBrowser, openPage, until, fetchJson, startChild, stopChildren, startBroker,
} from './helpers.js';

let tmp, broker, evolve, worker, firstWorker, server, browser, page, out, evolveId, filesAtStart;
const GENERATIONS = 6;

// The tiny walk of tests/integration/orcs_evolve_test.cc: a two-neuron oscillator, 10 genes, 0.5 s under two
// randomised parameter sets; cmaes with five genomes (its least) per generation.
const scenario = {
  name: 'progress-test',
  genome: [0.01, 1.0978, 0.0698, -0.0698, 1.0978, 0.05, -0.05, 0.05, 0.0, 0.0],
  duration: 0.5,
  controller: {
    type: 'network', transfer: 'tanh', inputs: [],
    neurons: [
      { name: 'osc1', bias: null }, { name: 'osc2', bias: 0 },
      { name: 'hip_rock', bias: 0, transfer: 'linear' }, { name: 'ankle_rock', bias: 0, transfer: 'linear' },
      { name: 'hip_swing', bias: 0, transfer: 'linear' }, { name: 'ankle_swing', bias: 0, transfer: 'linear' },
      { name: 'knee_bend', bias: 0, transfer: 'linear' },
    ],
    synapses: [
      { from: 'osc1', to: 'osc1', weight: null }, { from: 'osc2', to: 'osc1', weight: null },
      { from: 'osc1', to: 'osc2', weight: null }, { from: 'osc2', to: 'osc2', weight: null },
      { from: 'osc1', to: 'hip_rock', weight: null }, { from: 'osc1', to: 'ankle_rock', weight: null },
      { from: 'osc2', to: 'hip_swing', weight: null }, { from: 'osc2', to: 'ankle_swing', weight: null },
      { from: 'osc1', to: 'knee_bend', weight: null },
    ],
    outputs: [
      { neuron: 'hip_rock', value: 'Right/HipPitch/DesiredAngle' }, { neuron: 'hip_rock', value: 'Left/HipPitch/DesiredAngle' },
      { neuron: 'ankle_rock', value: 'Right/AnklePitch/DesiredAngle' }, { neuron: 'ankle_rock', value: 'Left/AnklePitch/DesiredAngle' },
      { neuron: 'hip_swing', value: 'Right/HipYaw/DesiredAngle' }, { neuron: 'hip_swing', value: 'Left/HipYaw/DesiredAngle' },
      { neuron: 'ankle_swing', value: 'Right/AnkleYaw/DesiredAngle' }, { neuron: 'ankle_swing', value: 'Left/AnkleYaw/DesiredAngle' },
      { neuron: 'knee_bend', value: 'Right/Knee/DesiredAngle' }, { neuron: 'knee_bend', value: 'Left/Knee/DesiredAngle' },
    ],
  },
  fitness: {
    terms: [
      { type: 'distance', name: 'forward', body: 'Middle/UpperBody', axis: 'z', weight: 10 },
      { type: 'upright_time', body: 'Middle/Head', min_height: 0.25, weight: 0.1 },
    ],
    aggregate: 'mean',
  },
  randomisation: { sets: 2, default_motor_model: true },
  evolution: {
    bounds: [[-0.05, 0.05], [0.8, 1.5], [-0.5, 0.5], [-0.5, 0.5], [0.8, 1.5],
      [-0.15, 0.15], [-0.15, 0.15], [-0.15, 0.15], [-0.15, 0.15], [-0.15, 0.15]],
    algorithm: 'cmaes', population: 5, generations: 2, seed: 1, validate: 2,
  },
};

/** Throws with its stderr when orcs-batch has ended other than by finishing well. */
function checkEvolve() {
  if ((evolve.exitCode !== null && evolve.exitCode !== 0) || evolve.signalCode !== null) {
    throw new Error(`orcs-batch evolve ended (${evolve.exitCode ?? evolve.signalCode}): ${evolve.stderrText()}`);
  }
}

/** What the page shows of the followed run. */
const shown = () => page.evaluate(() => {
  const line = document.getElementById('run-progress');
  const count = document.querySelector('#item-detail > div.muted');
  return {
    item: orcsView.item,
    progress: orcsView.progress,
    lineState: line ? line.dataset.state ?? null : null,
    lineClass: line ? line.className : null,
    lineText: line ? line.textContent : null,
    // The evolve item's "N generations" under its title: the length of the data the curve was drawn from.
    generations: count ? count.textContent : null,
    plot: !!document.querySelector('#fitness-plot .uplot'),
    detail: document.getElementById('item-detail').textContent,
  };
});

before(async () => {
  tmp = await tempDir();
  const file = path.join(tmp.dir, 'walk.json');
  await writeFile(file, JSON.stringify(scenario));
  out = path.join(tmp.dir, 'evolve');
  broker = await startBroker();
  evolve = startChild('orcs-batch', ['evolve', file, '--broker', broker.clients, '--heartbeat', '0.1', '--out', out,
    '--generations', String(GENERATIONS), '--population', '5', '--validate', '0', '--time-limit', '30', '--no-plot']);
  // orcs-view refuses a folder with nothing viewable: start it once the run has said it runs.
  await until(() => { checkEvolve(); return existsSync(path.join(out, 'progress.json')); }, 20_000, 'DIR/progress.json');
  filesAtStart = readdirSync(out).sort();
  server = await startServer([out]);
  browser = await launchBrowser();
  page = await openPage(browser, server.url);
  const session = await fetchJson(`${server.url}api/session`);
  evolveId = session.items.find((i) => i.kind === 'evolve')?.id;
});

after(async () => {
  await browser?.close();
  await server?.stop();
  await stopChildren([evolve, firstWorker, worker, broker?.child]);
  await tmp?.cleanup();
});

test(`with no worker the page shows the evolve run as running at generation 0/${GENERATIONS}`, async () => {
  assert.ok(!filesAtStart.includes('fitness.csv'), `orcs-view was started on ${filesAtStart.join(', ')}`);
  assert.ok(evolveId, 'the folder with only progress.json is an evolve item');
  assert.equal(JSON.parse(readFileSync(path.join(out, 'progress.json'), 'utf8')).command, 'evolve');
  // The run writes generation 0's figures once it has started it (within a second of its first write).
  const s = await until(async () => {
    checkEvolve();
    const now = await shown();
    return now.progress && typeof now.progress.generation === 'number' && now;
  }, 15_000, 'orcsView.progress with the generation');
  assert.equal(s.item, evolveId);
  assert.equal(s.progress.item, evolveId);
  assert.equal(s.progress.command, 'evolve');
  assert.equal(s.progress.state, 'running');
  assert.equal(s.progress.generation, 0);
  assert.equal(s.progress.generations, GENERATIONS);
  assert.equal(s.progress.done, 0);
  assert.equal(s.progress.total, 5);
  assert.equal(s.lineState, 'running');
  assert.match(s.lineClass, /\brun-progress\b/);
  assert.match(s.lineClass, /\bstate-running\b/);
  assert.match(s.lineText, /evolve running/);
  assert.match(s.lineText, new RegExp(`generation 0/${GENERATIONS}`));
  assert.match(s.lineText, /0\/5 jobs/);
  assert.equal(s.generations, '0 generations', 'no generation in fitness.csv yet');
  assert.ok(s.plot, 'the (empty) fitness curve is drawn');
  assert.doesNotMatch(s.detail, /null|undefined|NaN/, 'what is not there yet is left out, not written');
  assert.equal(await page.locator('#run-progress[data-state=running]').isVisible(), true);
  // Nothing moves without a worker: the page keeps asking, the run stays at generation 0.
  assert.equal(evolve.exitCode, null);
});

test('the curve grows while the run goes on, without a reload', async () => {
  await page.evaluate(() => { window.__sameDocument = true; });
  firstWorker = startChild('orcs-worker', ['--connect', broker.workers, '--heartbeat', '0.1', '--id', 'w-first']);
  // Three generations in fitness.csv (a header and three rows), then the worker dies: the run waits, mid-way.
  const csv = path.join(out, 'fitness.csv');
  await until(() => {
    checkEvolve();
    return existsSync(csv) && readFileSync(csv, 'utf8').trim().split('\n').length >= 4;
  }, 60_000, 'three generations in fitness.csv');
  firstWorker.kill('SIGKILL');
  await firstWorker.exited;
  const s = await until(async () => {
    checkEvolve();
    const now = await shown();
    const count = parseInt(now.generations, 10);
    return now.progress?.state === 'running' && count >= 3 && now.progress.last_generation === count - 1 && now;
  }, 20_000, 'the page showing three generations or more of a running run');
  assert.ok(parseInt(s.generations, 10) < GENERATIONS + 1, 'the run is not over');
  assert.equal(s.lineState, 'running');
  assert.match(s.lineText, new RegExp(`generation ${s.progress.generation}/${GENERATIONS}`));
  assert.ok(s.plot);
  assert.doesNotMatch(s.detail, /null|undefined|NaN/);
  assert.equal(await page.evaluate(() => window.__sameDocument), true, 'the page was not reloaded');
  assert.equal(evolve.exitCode, null);
});

test('screenshot: the run in progress (ORCS_SCREENSHOT_DIR)', async (t) => {
  if (!process.env.ORCS_SCREENSHOT_DIR) { t.skip('ORCS_SCREENSHOT_DIR not set'); return; }
  const dir = path.resolve(repoRoot, process.env.ORCS_SCREENSHOT_DIR);
  await mkdir(dir, { recursive: true });
  await page.screenshot({ path: path.join(dir, 'progress.png') });
});

test('once a worker connects again, the page follows the run to its end without a reload', async () => {
  worker = startChild('orcs-worker', ['--connect', broker.workers, '--heartbeat', '0.1', '--id', 'w0']);
  const s = await until(async () => {
    checkEvolve();
    if (worker.exitCode !== null) throw new Error(`orcs-worker ended (${worker.exitCode}): ${worker.stderrText()}`);
    const now = await shown();
    return now.progress?.state === 'finished' && now;
  }, 60_000, 'orcsView.progress.state === "finished"');
  assert.deepEqual(await evolve.exited, { code: 0, signal: null }, evolve.stderrText());
  assert.equal(await page.evaluate(() => window.__sameDocument), true, 'the page was not reloaded');
  assert.equal(s.item, evolveId);
  assert.equal(s.progress.item, evolveId);
  assert.equal(s.lineState, 'finished');
  assert.match(s.lineClass, /\bstate-finished\b/);
  assert.match(s.lineText, /evolve finished/);
  // Ended, the line counts generations, not the last generation's jobs (which read as the run's: "12/12 jobs").
  assert.match(s.lineText, new RegExp(`generations 0–${GENERATIONS} of 0–${GENERATIONS}`));
  assert.doesNotMatch(s.lineText, /jobs/);
  assert.doesNotMatch(s.detail, /null|undefined|NaN/);
  // The curve: drawn again from generations 0 to 6 (fitness.csv as the server reads it).
  assert.equal(s.generations, `${GENERATIONS + 1} generations`);
  assert.ok(s.plot);
  const evo = await fetchJson(`${server.url}api/evolve/${evolveId}`);
  assert.deepEqual(evo.generations.map((g) => g.generation), [...Array(GENERATIONS + 1).keys()]);
  assert.equal(evo.progress.state, 'finished');
  assert.ok(evo.recording, 'the winner is recorded');
  assert.equal(await page.locator('#item-detail button', { hasText: 'Open the winner' }).isEnabled(), true);
});

test('the winner joins the item list and opens', async () => {
  const winner = await until(async () => page.evaluate(() => {
    const li = [...document.querySelectorAll('#items li[data-kind=recording]')]
      .find((l) => l.querySelector('.label')?.textContent === 'winner');
    return li ? li.dataset.id : null;
  }), 10_000, 'the winner in the side list');
  const evo = await fetchJson(`${server.url}api/evolve/${evolveId}`);
  assert.equal(winner, evo.recording);
  assert.equal(await page.locator('#items li[data-kind=batch]', { hasText: 'winner and validation' }).count(), 1);
  await page.click(`#items li[data-id="${winner}"]`);
  const opened = await until(async () => {
    const v = await page.evaluate(() => ({ item: orcsView.item, ready: orcsView.ready, mode: orcsView.mode,
      progress: orcsView.progress, bodies: Object.keys(orcsView.bodies || {}).length }));
    return v.item === winner && v.ready && v;
  }, 20_000, 'the winner opened');
  assert.equal(opened.mode, 'files');
  assert.equal(opened.progress, null, 'no run followed while a recording is shown');
  assert.ok(opened.bodies > 20, 'the A-Series is drawn');
  assert.equal(await page.locator('#items li.current').getAttribute('data-id'), winner);
});

test('no console errors after all of the above', () => {
  assert.deepEqual(page.orcsProblems, []);
});
