// The session's items (GET /api/session) as a side panel, and what an item shows when opened: a batch's job
// table (sortable), an evolve run's fitness curve and winner, a gap report's runs (simulated + measured). A run
// still in progress (its progress.json says "running") is followed: its progress line and its table or curve are
// asked for again every second until it ends (docs/viewer.md, "Runs in progress").
import uPlot from 'uplot';
import { getJson } from './api.js';
import { el, $, fmt, put, showError } from './util.js';

/** "8 s", "3 min 20 s", "2 h 5 min". */
function duration(s) {
  if (!(s >= 0)) return '—';
  if (s < 60) return `${Math.round(s)} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${Math.round(s % 60)} s`;
  return `${Math.floor(s / 3600)} h ${Math.floor((s % 3600) / 60)} min`;
}

const FOLLOW_MS = 1000;       // how often a running item is asked for again
const STALE_SECONDS = 120;    // no news for this long: the command may have stopped

/**
 * The run an item opens with: a batch's fittest job with a recording, an evolve run's winner, a gap report's first
 * run (its replay with the measured run overlaid). {rid, opts} or null.
 */
function bestRun(kind, id, answer) {
  if (kind === 'batch') {
    const jobs = (Array.isArray(answer.jobs) ? answer.jobs : []).filter((j) => j.recording);
    if (!jobs.length) return null;
    const score = (j) => (typeof j.fitness === 'number' && Number.isFinite(j.fitness) ? j.fitness : -Infinity);
    const best = jobs.reduce((a, b) => (score(b) > score(a) ? b : a));
    return { rid: best.recording, opts: { label: `${answer.name || id} · ${best.job} (best)` } };
  }
  if (kind === 'evolve' && answer.recording) return { rid: answer.recording, opts: { label: `${answer.name || id} · winner` } };
  if (kind === 'robot') return robotRun(id, answer, 'robot');
  if (kind === 'gap') {
    const run = (Array.isArray(answer.runs) ? answer.runs : []).find((r) => r.simulated);
    if (!run) return null;
    return { rid: run.simulated, opts: { label: `${run.name} (simulated)`, overlay: run.measured || null, overlayLabel: `${run.name} (measured)` } };
  }
  return null;
}

/**
 * A robot run (orcs-robot --view) to open: `main` 'robot' shows the robot as measured with its twin as the ghost,
 * 'twin' the other way round; the first joint's measured and commanded angles are plotted (the twin's dashed).
 */
function robotRun(id, answer, main) {
  const name = answer.name || id;
  const other = main === 'robot' ? 'twin' : 'robot';
  const rid = answer[main];
  if (!rid) return null;
  const role = { robot: 'robot (measured)', twin: 'twin (simulated)' };
  const run = answer.run || {};
  const joint = Array.isArray(run.joints) && run.joints.length ? run.joints[0] : null;
  const plot = joint && run.agent ? [`/Sim/${run.agent}/${joint}/JointAngle`, `/Sim/${run.agent}/${joint}/DesiredAngle`] : [];
  return { rid, opts: { label: `${name} · ${role[main]}`, overlay: answer[other] || null, overlayLabel: `${name} · ${role[other]}`, plot } };
}

/** Equal-width bins over `values` (finite numbers): {centres, counts, width}; null for fewer than two values. */
function histogram(values) {
  if (values.length < 2) return null;
  const lo = Math.min(...values), hi = Math.max(...values);
  const bins = Math.max(5, Math.min(20, Math.ceil(Math.sqrt(values.length))));
  const width = hi > lo ? (hi - lo) / bins : 1;
  const counts = new Array(bins).fill(0);
  for (const v of values) counts[Math.min(bins - 1, Math.floor((v - lo) / width))]++;
  return { centres: counts.map((_, i) => lo + (i + 0.5) * width), counts, width };
}

// Tick steps for axes that count (generations, jobs): no 0.2 of a generation.
const WHOLE_STEPS = [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000];

const KIND_ICON = { recording: '▶', batch: '▦', evolve: '↗', gap: '≈', robot: '⚙', live: '●', broker: '⛁' };

export class Items {
  /** ctx: {open(id), openRecording(rid, opts), onProgress(progress or null), refreshSession()} */
  constructor(ctx) {
    this.ctx = ctx;
    this.items = [];
    this.current = null;        // the batch, evolve or gap item shown
    this.fitnessPlot = null;
    this.batchSort = { key: null, dir: -1 };
    this.followTimer = null;
    this.shownBody = '';        // the answer (without its progress) now drawn: redraw only when it changed
    this.robotMain = 'robot';   // a robot run: which side the 3D view shows, 'robot' or 'twin' (the other the ghost)
  }

  setSession(session) {
    this.items = Array.isArray(session.items) ? session.items : [];
    const list = $('items');
    list.replaceChildren(...this.items.map((item) => el('li', {
      class: item.parent ? 'item child' : 'item', dataset: { id: item.id, kind: item.kind }, title: item.path || item.label || item.id,
      onclick: () => this.ctx.open(item.id),
    }, el('span', { class: 'icon' }, KIND_ICON[item.kind] || '•'), el('span', { class: 'label' }, item.label || item.path || item.id),
    el('span', { class: 'muted id' }, item.id))));
  }

  byId(id) { return this.items.find((i) => i.id === id) || null; }

  markCurrent(id) {
    for (const li of $('items').children) li.classList.toggle('current', li.dataset.id === id);
  }

  detail() { return $('item-detail'); }

  clearDetail() {
    if (this.fitnessPlot) { this.fitnessPlot.destroy(); this.fitnessPlot = null; }
    this.detail().hidden = true;
    clearTimeout(this.followTimer);
    this.followTimer = null;
    this.current = null;
    this.shownBody = '';
    this.detail().replaceChildren();
    this.ctx.onProgress?.(null);
  }

  showBatch(id) { return this.show(id, 'batch', (answer) => this.renderBatch(id, answer)); }
  showEvolve(id) { return this.show(id, 'evolve', (answer) => this.renderEvolve(id, answer)); }
  showGap(id) { return this.show(id, 'gap', (answer) => this.renderGap(id, answer)); }
  showRobot(id) { return this.show(id, 'robot', (answer) => this.renderRobot(id, answer)); }

  /** Asks for the item, draws it, and while its run is in progress asks again every second. `follow`: a
   * repeated ask, which is dropped when another item was opened meanwhile. */
  async show(id, kind, render, follow = false) {
    const answer = await getJson(`/api/${kind}/${encodeURIComponent(id)}`);
    if (follow && this.current !== id) return;
    const same = this.current === id;
    const { progress = null, ...body } = answer;
    const bodyText = JSON.stringify(body);
    if (!same || bodyText !== this.shownBody) {
      const scroll = same ? this.detail().querySelector('.table-wrap')?.scrollTop : 0;
      if (!same) this.clearDetail();
      else this.detail().replaceChildren();
      if (this.fitnessPlot) { this.fitnessPlot.destroy(); this.fitnessPlot = null; }
      this.current = id;
      this.shownBody = bodyText;
      this.detail().hidden = false;
      this.detail().append(el('div', { id: 'run-progress' }));
      render(answer);
      // Opened anew: the 3D view shows the item's best run at once rather than staying empty. A robot run that grew
      // is opened again where the reader is (following its newest frame when they were at the end).
      const best = same ? (kind === 'robot' ? robotRun(id, answer, this.robotMain) : null) : bestRun(kind, id, answer);
      if (!same) this.robotMain = 'robot';
      if (best) await this.ctx.openRecording(best.rid, { ...best.opts, follow: same });
      const table = this.detail().querySelector('.table-wrap');
      if (table && scroll) table.scrollTop = scroll;  // a growing table keeps the reader's place
      if (same) this.ctx.refreshSession?.();  // recordings may have appeared: list them
    }
    this.renderProgress(kind, progress);
    this.ctx.onProgress?.(progress ? { item: id, ...progress } : null);
    clearTimeout(this.followTimer);
    if (progress && progress.state === 'running') {
      this.followTimer = setTimeout(() => {
        if (this.current !== id) return;
        this.show(id, kind, render, true).catch((err) => showError(err));
      }, FOLLOW_MS);
    }
  }

  /** The line above a run in progress (or one that ended early): what it does now. */
  renderProgress(kind, p) {
    const box = $('run-progress');
    if (!box) return;
    if (!p) { box.replaceChildren(); box.className = ''; return; }
    const parts = [];
    // An evolve run's counts are its generation's, not the run's: said so, and left out once it has ended.
    const generationJobs = kind === 'evolve' && typeof p.generation === 'number';
    const ended = generationJobs && p.state !== 'running' && typeof p.generations === 'number';
    if (p.label && !ended) parts.push(p.label);
    if (ended) {
      parts.push(`generations 0–${p.last_generation ?? p.generation} of 0–${p.generations}`);
    } else if (typeof p.done === 'number' && typeof p.total === 'number') {
      parts.push(`${p.done}/${p.total} jobs${generationJobs ? ' in this generation' : ''} (ok ${p.ok ?? p.done}, failed ${p.failed ?? 0})`);
      if (p.jobs_per_second > 0) parts.push(`${fmt(p.jobs_per_second, 3)} jobs/s`);
      if (p.eta_seconds >= 0 && p.state === 'running') parts.push(`ETA ${duration(p.eta_seconds)}`);
    }
    if (kind === 'evolve' && typeof p.best_so_far === 'number' && p.state === 'running') {
      parts.push(`best ${fmt(p.best_so_far, 4)}, median ${fmt(p.median_so_far, 4)} in this generation so far`);
    }
    if (kind === 'robot') {
      parts.push(`t = ${fmt(p.time_s ?? 0, 3)} s${typeof p.duration_s === 'number' ? ` of ${fmt(p.duration_s, 3)} s` : ''}, ${p.periods ?? 0} control periods`);
      if (p.stop) parts.push(p.stop);
    }
    if (kind === 'gap') {
      if (typeof p.replays === 'number') parts.push(`${p.replays} replays`);
      parts.push(`${p.fits_done ?? 0} fits done`);
      if (Array.isArray(p.fitting) && p.fitting.length) parts.push(`fitting ${p.fitting.join(', ')}`);
      if (p.best) parts.push(`best so far ${p.best.effect} (score ${fmt(p.best.score, 4)} deg²)`);
    }
    const age = typeof p.updated_unix === 'number' ? Date.now() / 1000 - p.updated_unix : 0;
    const words = {
      running: age > STALE_SECONDS ? `no news for ${duration(age)}: the command (pid ${p.pid}) may have stopped`
        : `${p.command} running`,
      finished: `${p.command} finished`,
      interrupted: `${p.command} interrupted: continue it with --resume`,
      failed: `${p.command} ended with an error (see its output)`,
    };
    box.className = `run-progress state-${p.state}${age > STALE_SECONDS && p.state === 'running' ? ' stale' : ''}`;
    box.dataset.state = p.state;
    const done = typeof p.total === 'number' && p.total > 0 ? Math.min(1, p.done / p.total) : null;
    box.replaceChildren();
    put(box, el('b', {}, words[p.state] || p.state),
      done !== null && p.state === 'running' ? el('div', { class: 'progress', title: `${p.done} of ${p.total}` },
        el('div', { class: 'progress-done', style: `width: ${(100 * done).toFixed(1)}%` })) : null,
      el('span', { class: 'muted' }, parts.join(' · ')));
  }

  renderBatch(id, batch) {
    const columns = Array.isArray(batch.columns) && batch.columns.length ? batch.columns : ['job', 'status', 'fitness', 'seed'];
    const jobs = Array.isArray(batch.jobs) ? batch.jobs.slice() : [];
    const sort = this.batchSort;
    const cell = (job, col) => {
      if (col in job) return job[col];
      if (job.terms && col in job.terms) return job.terms[col];
      return null;
    };
    const tbody = el('tbody');
    const renderRows = () => {
      const rows = jobs.slice();
      if (sort.key) {
        rows.sort((a, b) => {
          const x = cell(a, sort.key), y = cell(b, sort.key);
          if (x === y) return 0;
          if (x === null || x === undefined) return 1;
          if (y === null || y === undefined) return -1;
          return (typeof x === 'number' && typeof y === 'number' ? x - y : String(x).localeCompare(String(y))) * sort.dir;
        });
      }
      tbody.replaceChildren(...rows.map((job) => el('tr', {
        class: job.recording ? 'openable' : '',
        title: job.message || (job.recording ? `open the recording ${job.recording}` : 'no recording'),
        dataset: { recording: job.recording || '' },
        onclick: () => { if (job.recording) this.ctx.openRecording(job.recording, { label: `${batch.name || id} · ${job.job}` }); },
      }, columns.map((col) => {
        const v = cell(job, col);
        return el('td', { class: typeof v === 'number' ? 'num' : (col === 'status' ? `status status-${v}` : '') }, typeof v === 'number' ? fmt(v) : (v ?? '—'));
      }))));
    };
    const headRow = el('tr', {}, columns.map((col) => el('th', {
      class: `sortable${sort.key === col ? (sort.dir > 0 ? ' asc' : ' desc') : ''}`, title: `sort by ${col}`,
      onclick: (e) => {
        sort.dir = sort.key === col ? -sort.dir : (col === 'fitness' ? -1 : 1);
        sort.key = col;
        for (const th of headRow.children) th.classList.remove('asc', 'desc');
        e.currentTarget.classList.add(sort.dir > 0 ? 'asc' : 'desc');
        renderRows();
      },
    }, col)));
    renderRows();
    const histogramDiv = el('div', { class: 'chart', id: 'fitness-histogram' });
    put(this.detail(),
      el('h2', {}, `Batch: ${batch.name || id}`),
      el('div', { class: 'muted' }, `${jobs.length} jobs; click a row with a recording to open it; click a column to sort`),
      el('div', { class: 'item-panes' },
        el('div', { class: 'table-wrap' }, el('table', { class: 'grid', id: 'batch-table' }, el('thead', {}, headRow), tbody)),
        histogramDiv));
    this.drawHistogram(histogramDiv, jobs.map((j) => j.fitness).filter((f) => typeof f === 'number' && Number.isFinite(f)));
  }

  /** The batch's fitness histogram: how many jobs in each of 5–20 equal bins. */
  drawHistogram(div, fitness) {
    const h = histogram(fitness);
    if (!h) { div.append(el('div', { class: 'muted' }, 'a histogram needs two jobs with a fitness')); return; }
    const axis = { stroke: '#aeb6c2', grid: { stroke: '#2c323b' }, ticks: { stroke: '#3a414b' } };
    this.fitnessPlot = new uPlot({
      title: `Fitness of ${fitness.length} jobs`,
      width: 280, height: 190,
      scales: { x: { time: false, range: [h.centres[0] - h.width, h.centres[h.centres.length - 1] + h.width] }, y: { range: [0, Math.max(...h.counts) + 1] } },
      axes: [{ ...axis, label: 'fitness' }, { ...axis, label: 'jobs', size: 40, incrs: WHOLE_STEPS }],
      series: [{ label: 'fitness' }, { label: 'jobs', fill: 'rgba(78, 161, 255, 0.55)', stroke: '#4ea1ff', paths: uPlot.paths.bars({ size: [0.92, 100] }), points: { show: false } }],
    }, [h.centres, h.counts], div);
  }

  renderEvolve(id, evo) {
    const gens = Array.isArray(evo.generations) ? evo.generations : [];
    const plotDiv = el('div', { class: 'chart', id: 'fitness-plot' });
    const winner = el('button', {
      disabled: !evo.recording,
      onclick: () => evo.recording && this.ctx.openRecording(evo.recording, { label: `${evo.name || id} · winner` }),
    }, evo.recording ? 'Open the winner' : 'no winner recording');
    put(this.detail(), el('h2', {}, `Evolution: ${evo.name || id}`),
      el('div', { class: 'muted' }, `${gens.length} generations`), plotDiv,
      el('div', { class: 'row' }, winner),
      Array.isArray(evo.best_genome) ? el('div', { class: 'muted mono genome' }, `best genome: [${evo.best_genome.map((g) => fmt(g, 3)).join(', ')}]`) : null);
    const axis = { stroke: '#aeb6c2', grid: { stroke: '#2c323b' }, ticks: { stroke: '#3a414b' } };
    const width = Math.max(220, Math.floor(this.detail().getBoundingClientRect().width) - 8);
    this.fitnessPlot = new uPlot({
      title: 'Fitness (higher is better)',
      width, height: 200,
      scales: { x: { time: false } },
      axes: [{ ...axis, label: 'generation', incrs: WHOLE_STEPS }, { ...axis, label: 'fitness', size: 52 }],
      series: [{ label: 'generation' },
        { label: 'best', stroke: '#2ed573', width: 2 },
        { label: 'median', stroke: '#4ea1ff', width: 1.5 },
        { label: 'worst', stroke: '#ff6b81', width: 1, dash: [4, 3], points: { show: false }, show: gens.some((g) => g.worst !== undefined) }],
    }, [gens.map((g, i) => g.generation ?? i), gens.map((g) => g.best ?? null), gens.map((g) => g.median ?? null), gens.map((g) => g.worst ?? null)], plotDiv);
  }

  renderRobot(id, answer) {
    const run = answer.run || {};
    const open = (main) => {
      const chosen = robotRun(id, answer, main);
      if (!chosen) return;
      this.robotMain = main;
      this.ctx.openRecording(chosen.rid, chosen.opts);
    };
    put(this.detail(), el('h2', {}, `Robot: ${answer.name || id}`),
      el('div', {}, 'played: ', el('b', {}, run.played || '?'), ` on ${(run.joints || []).length} ${run.servo || 'servos'}`,
        ` at ${run.rate_hz ?? '?'} Hz (${run.port || '?'})`),
      el('div', { class: 'muted' }, 'the robot as measured and its simulated twin, fed the same commands; the other one is the ghost, dashed in the plots'),
      el('div', { id: 'robot-sides' },
        el('button', { class: 'small', id: 'robot-show-robot', disabled: !answer.robot, onclick: () => open('robot') }, 'robot (measured)'),
        ' ',
        el('button', { class: 'small', id: 'robot-show-twin', disabled: !answer.twin, onclick: () => open('twin') }, 'twin (simulated)')));
  }

  renderGap(id, gap) {
    const runs = Array.isArray(gap.runs) ? gap.runs : [];
    put(this.detail(), el('h2', {}, `Gap: ${gap.name || id}`),
      gap.missing_effect ? el('div', {}, 'missing effect: ', el('b', {}, gap.missing_effect)) : null,
      el('div', { class: 'muted' }, 'open a run: its simulated replay, the measured run overlaid and drawn as a ghost'),
      el('ul', { class: 'list', id: 'gap-runs' }, runs.map((run) => el('li', {
        class: run.simulated ? 'item openable' : 'item', dataset: { simulated: run.simulated || '', measured: run.measured || '' },
        onclick: () => run.simulated && this.ctx.openRecording(run.simulated, {
          label: `${run.name} (simulated)`, overlay: run.measured || null, overlayLabel: `${run.name} (measured)`,
        }),
      }, el('span', { class: 'label' }, run.name || run.simulated), run.measured ? el('span', { class: 'muted' }, ' + measured') : null,
      run.given ? el('button', {
        class: 'small', title: 'the replay under the model as given, before the fit, with the measured run',
        onclick: (e) => {
          e.stopPropagation();
          this.ctx.openRecording(run.given, {
            label: `${run.name} (model as given)`, overlay: run.measured || null, overlayLabel: `${run.name} (measured)`,
          });
        },
      }, 'model as given') : null))));
  }
}
