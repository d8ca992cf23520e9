// The session's items (GET /api/session) as a side panel, and what an item shows when opened: a batch's job
// table (sortable), an evolve run's fitness curve and winner, a gap report's runs (simulated + measured).
import uPlot from 'uplot';
import { getJson } from './api.js';
import { el, $, fmt } from './util.js';

const KIND_ICON = { recording: '▶', batch: '▦', evolve: '↗', gap: '≈', live: '●', broker: '⛁' };

export class Items {
  /** ctx: {openRecording(rid, opts), showError(msg), onOpened(item)} */
  constructor(ctx) {
    this.ctx = ctx;
    this.items = [];
    this.current = null;
    this.fitnessPlot = null;
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
    this.detail().replaceChildren();
  }

  async showBatch(id) {
    const batch = await getJson(`/api/batch/${encodeURIComponent(id)}`);
    this.clearDetail();
    const columns = Array.isArray(batch.columns) && batch.columns.length ? batch.columns : ['job', 'status', 'fitness', 'seed'];
    const jobs = Array.isArray(batch.jobs) ? batch.jobs.slice() : [];
    let sortKey = null, sortDir = -1;
    const cell = (job, col) => {
      if (col in job) return job[col];
      if (job.terms && col in job.terms) return job.terms[col];
      return null;
    };
    const tbody = el('tbody');
    const renderRows = () => {
      const rows = jobs.slice();
      if (sortKey) {
        rows.sort((a, b) => {
          const x = cell(a, sortKey), y = cell(b, sortKey);
          if (x === y) return 0;
          if (x === null || x === undefined) return 1;
          if (y === null || y === undefined) return -1;
          return (typeof x === 'number' && typeof y === 'number' ? x - y : String(x).localeCompare(String(y))) * sortDir;
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
      class: 'sortable', title: `sort by ${col}`,
      onclick: (e) => {
        sortDir = sortKey === col ? -sortDir : (col === 'fitness' ? -1 : 1);
        sortKey = col;
        for (const th of headRow.children) th.classList.remove('asc', 'desc');
        e.currentTarget.classList.add(sortDir > 0 ? 'asc' : 'desc');
        renderRows();
      },
    }, col)));
    renderRows();
    this.detail().append(
      el('h2', {}, `Batch: ${batch.name || id}`),
      el('div', { class: 'muted' }, `${jobs.length} jobs; click a row with a recording to open it; click a column to sort`),
      el('div', { class: 'table-wrap' }, el('table', { class: 'grid', id: 'batch-table' }, el('thead', {}, headRow), tbody)));
  }

  async showEvolve(id) {
    const evo = await getJson(`/api/evolve/${encodeURIComponent(id)}`);
    this.clearDetail();
    const gens = Array.isArray(evo.generations) ? evo.generations : [];
    const plotDiv = el('div', { class: 'chart', id: 'fitness-plot' });
    const winner = el('button', {
      disabled: !evo.recording,
      onclick: () => evo.recording && this.ctx.openRecording(evo.recording, { label: `${evo.name || id} · winner` }),
    }, evo.recording ? 'Open the winner' : 'no winner recording');
    this.detail().append(el('h2', {}, `Evolution: ${evo.name || id}`),
      el('div', { class: 'muted' }, `${gens.length} generations`), plotDiv,
      el('div', { class: 'row' }, winner),
      Array.isArray(evo.best_genome) ? el('div', { class: 'muted mono genome' }, `best genome: [${evo.best_genome.map((g) => fmt(g, 3)).join(', ')}]`) : null);
    const axis = { stroke: '#aeb6c2', grid: { stroke: '#2c323b' }, ticks: { stroke: '#3a414b' } };
    const width = Math.max(220, Math.floor(this.detail().getBoundingClientRect().width) - 8);
    this.fitnessPlot = new uPlot({
      width, height: 180,
      scales: { x: { time: false } },
      axes: [{ ...axis, label: 'generation' }, { ...axis, label: 'fitness', size: 52 }],
      series: [{ label: 'generation' },
        { label: 'best', stroke: '#2ed573', width: 2 },
        { label: 'median', stroke: '#4ea1ff', width: 1.5 },
        { label: 'worst', stroke: '#ff6b81', width: 1, dash: [4, 3], points: { show: false }, show: gens.some((g) => g.worst !== undefined) }],
    }, [gens.map((g, i) => g.generation ?? i), gens.map((g) => g.best ?? null), gens.map((g) => g.median ?? null), gens.map((g) => g.worst ?? null)], plotDiv);
  }

  async showGap(id) {
    const gap = await getJson(`/api/gap/${encodeURIComponent(id)}`);
    this.clearDetail();
    const runs = Array.isArray(gap.runs) ? gap.runs : [];
    this.detail().append(el('h2', {}, `Gap: ${gap.name || id}`),
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
