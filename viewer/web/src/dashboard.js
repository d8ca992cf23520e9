// orcs-view --broker ENDPOINT: the broker's dashboard (docs/viewer.md, "Watching a broker"). The server asks the
// broker for its status once a second; this page long-polls /api/broker/status for each new answer (push, no page
// reloads) and shows the totals, throughput and queue-depth charts over time, the workers (click one for its
// recent jobs), the batches with their progress, and each batch's latest failures. When orcs-view was also given
// the batches' folders, a finished job that was recorded links to its replay (GET /api/replays).
import uPlot from 'uplot';
import { getJson } from './api.js';
import { el, $, fmt, showError } from './util.js';

const AXIS = { stroke: '#aeb6c2', grid: { stroke: '#2c323b' }, ticks: { stroke: '#3a414b' } };
const HISTORY_POINTS = 3600;  // as the server keeps (viewer/broker_watch.h)
const REPLAYS_MS = 3000;      // how often the recorded jobs are asked for again

const seconds = (s) => {
  if (!(s >= 0)) return '—';
  if (s < 10) return `${s.toFixed(1)} s`;
  if (s < 60) return `${Math.round(s)} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${Math.round(s % 60)} s`;
  return `${Math.floor(s / 3600)} h ${Math.floor((s % 3600) / 60)} min`;
};

export class Dashboard {
  /** ctx: {state: window.orcsView, where the dashboard's figures go for tests; openRecording(rid, opts); hasFiles()} */
  constructor(ctx) {
    this.ctx = ctx;
    this.serial = 0;
    this.polling = false;
    this.points = [];           // [time, workers, busy, queued, running, done, failed, jobs_per_second]
    this.charts = null;
    this.selectedWorker = null;
    this.latest = null;
    this.replays = new Map();   // "batch\u0000job" → recording id
  }

  async show() {
    document.body.classList.add('dashboard-on');
    $('dashboard').hidden = false;
    if (this.polling) return;
    this.polling = true;
    try {
      const history = await getJson('/api/broker/history');
      this.points = Array.isArray(history.points) ? history.points : [];
    } catch (err) {
      showError(err);
    }
    this.poll();
  }

  hide() {
    document.body.classList.remove('dashboard-on');
    $('dashboard').hidden = true;
    this.polling = false;  // the poll under way ends the loop when it returns
  }

  async poll() {
    while (this.polling) {
      try {
        const snapshot = await getJson(`/api/broker/status?since=${this.serial}`);
        if (snapshot.serial > this.serial) {
          this.serial = snapshot.serial;
          await this.loadReplays();
          this.apply(snapshot);
        }
      } catch (err) {
        showError(err);
        await new Promise((resolve) => setTimeout(resolve, 1000));
      }
    }
  }

  /** The recorded jobs of the batch folders orcs-view was given, by broker batch and job id. */
  async loadReplays() {
    if (!this.ctx.hasFiles?.()) return;
    // Each answer rescans the batch folders: every few seconds is soon enough for a replay link.
    const now = performance.now();
    if (this.replaysAt !== undefined && now - this.replaysAt < REPLAYS_MS) return;
    this.replaysAt = now;
    const answer = await getJson('/api/replays');
    this.replays = new Map((answer.replays || []).map((r) => [`${r.batch}\u0000${r.job}`, r.recording]));
  }

  /** A "replay" button for a finished job that was recorded, or null. */
  replayButton(batchId, jobId) {
    const rid = batchId && jobId ? this.replays.get(`${batchId}\u0000${jobId}`) : undefined;
    if (!rid) return null;
    return el('button', {
      class: 'small replay', title: `open the recording of ${jobId}`, dataset: { recording: rid },
      onclick: () => this.ctx.openRecording(rid, { label: jobId }),
    }, 'replay');
  }

  apply(snapshot) {
    const status = snapshot.status;
    if (status) {
      this.points.push([snapshot.time, status.workers, status.busy_workers, status.queued, status.running, status.done,
        status.failed, status.jobs_per_second]);
      if (this.points.length > HISTORY_POINTS) this.points.shift();
    }
    this.latest = snapshot;
    this.render(snapshot);
    this.ctx.state.broker = status ? {
      serial: snapshot.serial, error: snapshot.error || '', workers: status.workers, busy: status.busy_workers,
      queued: status.queued, running: status.running, done: status.done, failed: status.failed,
      batches: status.batch_list.length, points: this.points.length, replays: this.replays.size,
    } : { serial: snapshot.serial, error: snapshot.error || 'no answer' };
  }

  render(snapshot) {
    $('dash-endpoint').textContent = snapshot.endpoint;
    const status = snapshot.status;
    const summary = $('dash-summary');
    if (!status) {
      summary.replaceChildren(el('span', { class: 'bad' }, snapshot.error || 'the broker does not answer'),
        el('span', { class: 'muted' }, ' — asking again every second'));
      return;
    }
    const figure = (name, value, hint) => el('span', { class: 'figure', dataset: { name }, title: hint },
      el('b', {}, String(value)), ' ', name);
    summary.replaceChildren(
      figure('workers', status.workers, 'registered workers'),
      figure('busy', status.busy_workers, 'workers holding a job'),
      figure('queued', status.queued, 'jobs waiting for a worker'),
      figure('running', status.running, 'jobs held by workers'),
      figure('done', status.done, 'jobs finished OK since the broker started'),
      figure('failed', status.failed, 'jobs finished with another status'),
      figure('jobs/s', fmt(status.jobs_per_second, 3), 'finished jobs per second over the last minute'),
      el('span', { class: 'muted' }, ` · up ${seconds(status.uptime_seconds)} · ${status.workers_lost} workers lost, ` +
        `${status.crashes} crashes · workers connect to ${status.worker_endpoint}`));
    if (status.workers === 0) {
      summary.append(el('div', { class: 'hint' },
        `No worker is connected: start one with orcs-worker --connect ${status.worker_endpoint}`));
    }
    this.drawCharts();
    this.renderWorkers(status);
    this.renderBatches(status);
    this.renderRecent(status);
  }

  drawCharts() {
    const columns = (i) => this.points.map((p) => p[i]);
    const data = [[columns(0), columns(7)], [columns(0), columns(3), columns(4), columns(1)]];
    if (!this.charts) {
      const width = Math.max(320, Math.floor($('dash-charts').getBoundingClientRect().width / 2) - 16);
      const make = (target, title, yLabel, series, d) => new uPlot({
        title, width, height: 170, scales: { x: { time: false } },
        axes: [{ ...AXIS, label: 'time since orcs-view started (s)' }, { ...AXIS, label: yLabel, size: 56 }],
        series: [{ label: 't (s)' }, ...series],
      }, d, target);
      this.charts = [
        make($('dash-throughput'), 'Throughput', 'jobs / s',
          [{ label: 'finished jobs/s (last minute)', stroke: '#2ed573', width: 2 }], data[0]),
        make($('dash-queue'), 'Queue depth', 'jobs · workers',
          [{ label: 'queued', stroke: '#ffa502', width: 2 }, { label: 'running', stroke: '#4ea1ff', width: 2 },
            { label: 'workers', stroke: '#aeb6c2', width: 1, dash: [4, 3] }], data[1]),
      ];
    } else {
      this.charts[0].setData(data[0]);
      this.charts[1].setData(data[1]);
    }
  }

  renderWorkers(status) {
    const rows = status.worker_list.map((w) => el('tr', {
      class: `openable${w.worker_id === this.selectedWorker ? ' current' : ''}`, dataset: { worker: w.worker_id },
      title: 'show its recent jobs',
      onclick: () => { this.selectedWorker = w.worker_id; this.renderWorkers(status); this.renderRecent(status); },
    },
    el('td', {}, w.worker_id), el('td', {}, w.host || '—'),
    el('td', {}, w.busy ? (w.current_job_id ? `${w.current_job_id}` : "(another key's job)") : 'idle'),
    el('td', { class: 'num' }, w.busy ? seconds(w.current_seconds) : '—'),
    el('td', { class: 'num' }, `${w.holding}/${w.credit}`), el('td', { class: 'num' }, w.jobs_done),
    el('td', { class: `num${w.crashes > 0 ? ' bad' : ''}` }, w.crashes),
    el('td', { class: 'num' }, `${seconds(w.last_heard_seconds)} ago`)));
    $('dash-workers').querySelector('tbody').replaceChildren(...rows);
  }

  renderBatches(status) {
    const rows = status.batch_list.map((b) => {
      const finished = b.done + b.failed;
      const total = b.expected > 0 ? b.expected : finished + b.queued + b.running;
      const share = total > 0 ? Math.min(1, finished / total) : 0;
      return el('tr', { dataset: { batch: b.batch_id } },
        el('td', { class: 'mono' }, b.hidden ? "(another key's batch)" : b.batch_id),
        el('td', {}, b.hidden ? '—' : b.client_id),
        el('td', {}, el('div', { class: 'progress', title: `${finished} of ${total}` },
          el('div', { class: 'progress-done', style: `width: ${(100 * share).toFixed(1)}%` }))),
        el('td', { class: 'num' }, b.queued), el('td', { class: 'num' }, b.running), el('td', { class: 'num' }, b.done),
        el('td', { class: `num${b.failed > 0 ? ' bad' : ''}` }, b.failed),
        el('td', { class: 'num' }, b.expected > 0 ? b.expected : '?'),
        el('td', { class: 'num' }, fmt(b.jobs_per_second, 3)),
        el('td', { class: 'num' }, b.seconds_left < 0 ? '?' : seconds(b.seconds_left)));
    });
    $('dash-batches').querySelector('tbody').replaceChildren(...rows);
    const failures = [];
    for (const b of status.batch_list) {
      for (const f of b.recent_failures || []) failures.push({ batch: b.batch_id, ...f });
    }
    $('dash-failures').replaceChildren(...(failures.length ? failures.map((f) => el('li', { class: 'failure' },
      el('span', { class: 'bad' }, f.status), ' ', el('span', { class: 'mono' }, f.job_id),
      f.worker_id ? ` on ${f.worker_id}` : '', `, ${seconds(f.seconds_ago)} ago: `, f.message || '(no message)', ' ',
      this.replayButton(f.batch, f.job_id)))
      : [el('li', { class: 'muted' }, 'no failures in the live batches')]));
  }

  renderRecent(status) {
    const worker = status.worker_list.find((w) => w.worker_id === this.selectedWorker);
    $('dash-recent-title').textContent = worker ? `Recent jobs of ${worker.worker_id}` : 'Recent jobs (click a worker)';
    $('dash-recent').replaceChildren(...(worker ? (worker.recent_jobs.length ? worker.recent_jobs.map((j) => el('li', {},
      el('span', { class: j.status === 'OK' ? 'good' : 'bad' }, j.status), ' ',
      el('span', { class: 'mono' }, j.job_id || "(another key's job)"), ` ${seconds(j.seconds)}, ${seconds(j.seconds_ago)} ago `,
      this.replayButton(j.batch_id, j.job_id)))
      : [el('li', { class: 'muted' }, 'no job finished yet')]) : []));
  }
}
