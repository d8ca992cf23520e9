// Channel plots with uPlot: one chart per unit (m, deg, N·m, ...), time in s on x, a cursor line that follows
// the time line, and an optional second run overlaid (the original Value Plotter's offline overlay).
import uPlot from 'uplot';
import { el, unitOf, floorIndex } from './util.js';

const PALETTE = ['#4ea1ff', '#ff9f43', '#2ed573', '#ff6b81', '#a29bfe', '#feca57', '#48dbfb', '#ff9ff3'];
const AXIS = { stroke: '#aeb6c2', grid: { stroke: '#2c323b', width: 1 }, ticks: { stroke: '#3a414b', width: 1 } };

/** Short, readable channel name for legends. */
export function shortName(path) {
  return path.replace(/^\/Sim\//, '');
}

/** A run's name for legends: its label without the .orcsrec ending. */
function runName(source) {
  return String(source.label || '').replace(/\.orcsrec$/, '');
}

/** The longest common prefix of the paths that ends at a '/', or ''. */
function commonFolder(paths) {
  if (paths.length < 2) return paths.length ? paths[0].slice(0, paths[0].lastIndexOf('/') + 1) : '';
  let prefix = paths[0];
  for (const p of paths) while (!p.startsWith(prefix)) prefix = prefix.slice(0, -1);
  return prefix.slice(0, prefix.lastIndexOf('/') + 1);
}

/** Values of `values` (at `fromTimes`) resampled linearly at `toTimes`; null outside the range. */
function resample(fromTimes, values, toTimes) {
  const same = fromTimes.length === toTimes.length && fromTimes.length > 0 &&
    Math.abs(fromTimes[0] - toTimes[0]) < 1e-9 &&
    Math.abs(fromTimes[fromTimes.length - 1] - toTimes[toTimes.length - 1]) < 1e-9;
  if (same) return Array.from(values);
  const out = new Array(toTimes.length);
  const n = fromTimes.length;
  for (let i = 0; i < toTimes.length; i++) {
    const t = toTimes[i];
    if (!n || t < fromTimes[0] - 1e-9 || t > fromTimes[n - 1] + 1e-9) { out[i] = null; continue; }
    const k = floorIndex(fromTimes, t);
    if (k >= n - 1) { out[i] = values[n - 1]; continue; }
    const t0 = fromTimes[k], t1 = fromTimes[k + 1];
    const a = t1 > t0 ? (t - t0) / (t1 - t0) : 0;
    out[i] = values[k] * (1 - a) + values[k + 1] * a;
  }
  return out;
}

export class Plots {
  /**
   * container: where charts go. onChange(paths): the plotted paths changed. onSeek(t): a click in a chart.
   */
  constructor(container, { onChange = () => {}, onSeek = () => {} } = {}) {
    this.container = container;
    this.onChange = onChange;
    this.onSeek = onSeek;
    this.charts = new Map();  // unit -> {unit, paths, div, u, line}
    this.primary = null;      // {label, times, channelIndex(path), values(index)}
    this.overlay = null;
    this.time = 0;
    this.generation = 0;
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
  }

  get paths() {
    const all = [];
    for (const chart of this.charts.values()) all.push(...chart.paths);
    return all;
  }

  width() {
    return Math.max(200, Math.floor(this.container.getBoundingClientRect().width) - 4);
  }

  resize() {
    const w = this.width();
    for (const chart of this.charts.values()) if (chart.u && chart.u.width !== w) chart.u.setSize({ width: w, height: chart.u.height });
    this.placeCursor();
  }

  /** Sets the shown run (and drops every chart if `keep` is false). */
  setPrimary(source, keep = false) {
    this.primary = source;
    const paths = keep ? this.paths : [];
    this.clear(false);
    return this.addAll(paths);
  }

  async setOverlay(source) {
    this.overlay = source;
    await this.rebuildAll();
  }

  clear(notify = true) {
    for (const chart of this.charts.values()) { chart.u?.destroy(); chart.div.remove(); }
    this.charts.clear();
    this.generation++;
    if (notify) this.onChange(this.paths);
  }

  /** Plots a channel; returns false if the shown run has no such channel. */
  async add(path) {
    if (!this.primary || this.primary.channelIndex(path) < 0) return false;
    const unit = unitOf(path);
    let chart = this.charts.get(unit);
    if (!chart) {
      const div = el('div', { class: 'chart' });
      const title = el('div', { class: 'chart-title' },
        el('span', { class: 'chart-name' }, unit ? `[${unit}]` : '[—]'),
        el('button', { class: 'chart-close', title: 'remove this plot', onclick: () => this.removeUnit(unit) }, '×'));
      div.append(title);
      this.container.append(div);
      chart = { unit, paths: [], div, u: null, line: null };
      this.charts.set(unit, chart);
    }
    if (!chart.paths.includes(path)) chart.paths.push(path);
    this.onChange(this.paths);
    await this.rebuild(chart);
    return true;
  }

  async addAll(paths) {
    for (const p of paths) await this.add(p);
  }

  removeUnit(unit) {
    const chart = this.charts.get(unit);
    if (!chart) return;
    chart.u?.destroy();
    chart.div.remove();
    this.charts.delete(unit);
    this.onChange(this.paths);
  }

  async rebuildAll() {
    for (const chart of this.charts.values()) await this.rebuild(chart);
  }

  /** Fetches the chart's series and (re)creates its uPlot. */
  async rebuild(chart) {
    const generation = this.generation;
    const primary = this.primary, overlay = this.overlay;
    const times = primary.times;
    const data = [Array.from(times)];
    const series = [{ label: 't', value: (u, v) => (v == null ? '—' : v.toFixed(3) + ' s') }];
    const folder = commonFolder(chart.paths);
    chart.div.querySelector('.chart-name').textContent = `${shortName(folder) || ''} [${chart.unit || '—'}]`;
    const name = (path) => path.slice(folder.length) || shortName(path);
    for (let i = 0; i < chart.paths.length; i++) {
      const path = chart.paths[i];
      const color = PALETTE[i % PALETTE.length];
      const values = await primary.values(primary.channelIndex(path));
      data.push(Array.from(values || []));
      series.push({ label: overlay ? `${name(path)} · ${runName(primary)}` : name(path), stroke: color, width: 1.5, value: (u, v) => (v == null ? '—' : v.toFixed(4)) });
      if (overlay) {
        const oi = overlay.channelIndex(path);
        const ov = oi >= 0 ? await overlay.values(oi) : null;
        data.push(ov ? resample(overlay.times, ov, times) : new Array(times.length).fill(null));
        series.push({ label: `${name(path)} · ${runName(overlay)}`, stroke: color, width: 1.5, dash: [6, 4], value: (u, v) => (v == null ? '—' : v.toFixed(4)) });
      }
    }
    if (generation !== this.generation || !this.charts.has(chart.unit)) return;
    if (chart.u && chart.u.series.length === series.length && chart.signature === series.map((s) => s.label).join('|')) {
      chart.u.setData(data);
    } else {
      chart.u?.destroy();
      const opts = {
        width: this.width(),
        height: 190,
        scales: { x: { time: false } },
        axes: [
          { ...AXIS, label: 'time [s]', labelSize: 18, size: 34 },
          { ...AXIS, label: chart.unit ? `[${chart.unit}]` : 'value', labelSize: 18, size: 56 },
        ],
        series,
        cursor: { drag: { x: true, y: false } },
        legend: { live: true },
        hooks: { ready: [(u) => this.addCursorLine(chart, u)] },
      };
      chart.u = new uPlot(opts, data, chart.div);
      chart.signature = series.map((s) => s.label).join('|');
    }
    this.placeCursor();
  }

  /** Live data: replaces every chart's data without refetching (the source answers synchronously). */
  refreshLive() {
    if (!this.primary) return;
    for (const chart of this.charts.values()) {
      if (!chart.u) continue;
      const data = [Array.from(this.primary.times)];
      for (const path of chart.paths) data.push(Array.from(this.primary.valuesNow(this.primary.channelIndex(path))));
      chart.u.setData(data);
    }
    this.placeCursor();
  }

  addCursorLine(chart, u) {
    chart.line = el('div', { class: 'cursor-line' });
    u.over.append(chart.line);
    u.over.addEventListener('click', () => {
      if (u.select && u.select.width > 2) return;
      const left = u.cursor.left;
      if (left == null || left < 0) return;
      this.onSeek(u.posToVal(left, 'x'));
    });
  }

  setTime(t) {
    this.time = t;
    this.placeCursor();
  }

  placeCursor() {
    for (const chart of this.charts.values()) {
      if (!chart.u || !chart.line) continue;
      const x = chart.u.valToPos(this.time, 'x');
      const w = chart.u.over.clientWidth || chart.u.bbox.width;
      chart.line.style.display = Number.isFinite(x) && x >= 0 && x <= w ? 'block' : 'none';
      chart.line.style.transform = `translateX(${Math.round(x)}px)`;
    }
  }
}
