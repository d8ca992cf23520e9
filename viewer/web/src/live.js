// Live mode: one simulation in the server. The page long-polls frames and draws them; whoever holds the control
// token runs, pauses, steps and resets it, moves motors (the Motor Control Manager), edits values (Simulation
// Properties) and logs (the Logger) — the 2008 ORCS GUI's panels over docs/viewer-api.md's live routes.
import { getJson, post, setToken, getToken } from './api.js';
import { $, el, showError, fmt } from './util.js';

const HISTORY = 2000;  // frames kept for the plots
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function fileNames(answer) {
  const list = Array.isArray(answer) ? answer : (answer && (answer.files || answer.items)) || [];
  return list.map((f) => (typeof f === 'string' ? f : f && (f.name || f.file))).filter(Boolean);
}

export class Live {
  /** ctx: {world, plots, state, fillTree(), channelSearch()} */
  constructor(ctx) {
    this.ctx = ctx;
    this.header = null;
    this.channels = [];
    this.index = new Map();
    this.times = [];
    this.history = [];
    this.last = null;
    this.since = -1;
    this.plotDirty = false;
    this.lastPlot = 0;
    this.sliders = new Map();  // path -> {input, out, pending, busy, dragging}
    this.source = {
      label: 'live',
      times: this.times,
      channelIndex: (p) => this.channelIndex(p),
      values: async (i) => this.valuesNow(i),
      valuesNow: (i) => this.valuesNow(i),
    };
  }

  channelIndex(path) { return this.index.has(path) ? this.index.get(path) : -1; }

  valuesNow(i) {
    const out = new Float64Array(this.history.length);
    for (let k = 0; k < this.history.length; k++) out[k] = this.history[k][i];
    return out;
  }

  async start() {
    const { world, plots } = this.ctx;
    this.header = await getJson('/api/live/world');
    this.channels = Array.isArray(this.header.channels) ? this.header.channels : [];
    this.index = new Map(this.channels.map((c, i) => [c, i]));
    world.load(this.header);
    world.setContactsVisible($('toggle-contacts').checked);
    world.setJointsVisible($('toggle-joints').checked);
    world.setPreset('front');
    for (const id of ['timeline', 'compare-row']) $(id).hidden = true;
    for (const id of ['live-bar', 'live-motors', 'live-props']) $(id).hidden = false;
    await plots.setPrimary(this.source);
    this.ctx.fillTree();
    this.wire();
    this.setControlled(false);
    await this.refreshFiles().catch((e) => showError(e));
    await this.refreshProps().catch((e) => showError(e));
    const first = await this.fetchFrame();
    this.onFrame(first);
    this.buildSliders();
    this.loop();
  }

  async fetchFrame() {
    const headers = getToken() ? { 'X-Orcs-Token': getToken() } : {};
    return getJson(`/api/live/frame?since=${this.since}`, { headers });
  }

  /** The long poll: one request at a time, each answer awaited (the server waits up to 0.5 s for a new step). */
  async loop() {
    let failing = false;
    for (;;) {
      try {
        const frame = await this.fetchFrame();
        failing = false;
        this.onFrame(frame);
      } catch (err) {
        if (!failing) showError(err);
        failing = true;
        await sleep(1000);
      }
    }
  }

  /** A reset compiled the world anew (a size, a mass, a material changed): its bodies are drawn again. */
  async reloadWorld(revision) {
    this.worldRevision = revision;
    this.header = await getJson('/api/live/world');
    this.ctx.world.load(this.header);
    this.ctx.world.setContactsVisible($('toggle-contacts').checked);
    this.ctx.world.setJointsVisible($('toggle-joints').checked);
  }

  onFrame(f) {
    if (!f || typeof f !== 'object' || !Array.isArray(f.values)) return;
    if (this.worldRevision === undefined) this.worldRevision = f.world_revision;
    if (Number.isInteger(f.world_revision) && f.world_revision !== this.worldRevision) {
      this.reloadWorld(f.world_revision).then(() => this.onFrame(f)).catch((e) => showError(e));
      return;
    }
    const { world, state } = this.ctx;
    const v = f.values;
    this.last = f;
    this.since = Number.isInteger(f.serial) ? f.serial : this.since;  // the server's frame counter, not the step
    world.pose((i) => v[i]);
    if (world.contactGroup.visible) world.setContacts(Array.isArray(f.contacts) ? f.contacts : []);
    world.poses(state.bodies);
    state.time = f.time;
    state.frame = f.step;
    state.playing = !!f.running;
    if (this.times.length && f.time < this.times[this.times.length - 1]) { this.times.length = 0; this.history.length = 0; }
    if (!this.times.length || f.time > this.times[this.times.length - 1]) {
      this.times.push(f.time);
      this.history.push(Float32Array.from(v));
      if (this.times.length > HISTORY) { this.times.shift(); this.history.shift(); }
      this.plotDirty = true;
    }
    const stopped = f.message ? `   stopped: ${f.message}` : (f.status && f.status !== 'ok' ? `   ${f.status}` : '');
    const real = Number.isFinite(f.real_time) ? ` (real ${Number(f.real_time).toFixed(1)} s)` : '';
    // orcs-osp -gui: the OSP clients step and reset it; the page has no Run, Pause, Step or Reset then.
    document.body.classList.toggle('osp-driven', !!f.osp);
    const how = f.osp ? `driven over OSP at ${f.osp}` : `${f.running ? 'running' : 'paused'}${f.realtime ? ', real time' : ', as fast as possible'}`;
    $('live-time').textContent = `t = ${Number(f.time).toFixed(3)} s${real}   step ${f.step}   ${how}${stopped}`;
    if (f.message && f.message !== this.shownMessage) showError(`the simulation stopped: ${f.message}`);
    this.shownMessage = f.message || '';
    $('time-label').textContent = `t = ${Number(f.time).toFixed(3)} s`;
    if (document.activeElement !== $('live-realtime')) $('live-realtime').checked = !!f.realtime;
    this.showLogger(f.logger);
    $('live-run').classList.toggle('active', !!f.running);
    $('live-pause').classList.toggle('active', !f.running);
    this.ctx.plots.setTime(f.time);
    for (const [path, s] of this.sliders) {
      const i = this.channelIndex(path);
      if (i < 0 || s.dragging || s.busy || s.pending !== null) continue;
      s.input.value = String(v[i]);
      s.out.textContent = fmt(v[i], 1);
    }
  }

  /** Called before each draw: refreshes the plots at most 5 times a second. */
  beforeDraw() {
    const now = performance.now();
    if (this.plotDirty && now - this.lastPlot > 200) {
      this.plotDirty = false;
      this.lastPlot = now;
      this.ctx.plots.refreshLive();
    }
  }

  needToken() {
    if (getToken()) return true;
    showError('take control first (Motor Control Manager: "Take control")');
    return false;
  }

  async control(action, steps = 1) {
    if (!this.needToken()) return null;
    try {
      const body = { action, realtime: $('live-realtime').checked };
      if (action === 'step' && steps > 1) body.steps = steps;
      const answer = await post('/api/live/control', body);
      if (action === 'reset') this.since = -1;
      return answer;
    } catch (err) {
      showError(err);
      return null;
    }
  }

  /** n steps in one request: the server does them at once, whatever the page's round trips cost. */
  async stepMany(n) {
    return this.control('step', Math.max(1, Math.min(100000, Math.trunc(Number(n) || 1))));
  }

  toggle() { return this.control(this.last && this.last.running ? 'pause' : 'run'); }

  setControlled(on) {
    document.body.classList.toggle('has-token', on);
    for (const node of document.querySelectorAll('.needs-token')) node.disabled = !on;
    for (const s of this.sliders.values()) s.input.disabled = !on;
    for (const input of document.querySelectorAll('#props-table input, #object-table input')) input.disabled = !on;
    $('live-claim-state').textContent = on ? 'you control the simulation' : 'watching (take control to steer)';
    $('live-claim').disabled = on;
  }

  async claim() {
    try {
      // A JSON request, as the server requires: a page of another site cannot send one without asking first.
      const answer = await post('/api/live/claim', {});
      if (!answer || !answer.token) throw new Error('POST /api/live/claim: no token in the answer');
      setToken(answer.token);
      this.setControlled(true);
    } catch (err) {
      showError(err.status === 409 ? 'someone else controls this simulation (try again once they are silent for 10 s)' : err);
    }
  }

  wire() {
    $('live-claim').addEventListener('click', () => this.claim());
    $('live-run').addEventListener('click', () => this.control('run'));
    $('live-pause').addEventListener('click', () => this.control('pause'));
    $('live-step').addEventListener('click', () => this.control('step'));
    $('live-reset').addEventListener('click', () => this.control('reset'));
    $('live-realtime').addEventListener('change', () => this.control(this.last && this.last.running ? 'run' : 'pause'));
    $('pose-save').addEventListener('click', () => this.save($('pose-file').value, '.*DesiredAngle'));
    $('pose-load').addEventListener('click', () => this.load($('pose-files').value));
    $('object-initial').addEventListener('click', () => this.keepAsInitial());
    $('props-refresh').addEventListener('click', () => this.refreshProps().catch((e) => showError(e)));
    $('props-filter').addEventListener('keydown', (e) => { if (e.key === 'Enter') this.refreshProps().catch((err) => showError(err)); });
    $('props-save').addEventListener('click', () => this.save($('props-file').value, $('props-filter').value || '.*'));
    $('props-load').addEventListener('click', () => this.load($('props-files').value));
    $('logger-start').addEventListener('click', () => this.logger('start'));
    $('logger-stop').addEventListener('click', () => this.logger('stop'));
  }

  // --- the Motor Control Manager --------------------------------------------------------------------------
  buildSliders() {
    const container = $('motor-sliders');
    const v = this.last ? this.last.values : [];
    const at = (path, fallback) => {
      const i = this.channelIndex(path);
      return i >= 0 && Number.isFinite(v[i]) ? v[i] : fallback;
    };
    const groups = [];
    for (const agent of this.header.agents || []) {
      const rows = [];
      for (const motor of agent.motors || []) {
        const base = `/Sim/${agent.name}/${motor}/`;
        const path = base + 'DesiredAngle';
        const joint = (this.header.joints || []).find((j) => j.agent === agent.name && j.motor === motor) || {};
        let lo = at(base + 'MinAngle', Number.isFinite(joint.min_angle) ? joint.min_angle : -150);
        let hi = at(base + 'MaxAngle', Number.isFinite(joint.max_angle) ? joint.max_angle : 150);
        if (!(hi > lo)) [lo, hi] = [-150, 150];
        const value = at(path, 0);
        const input = el('input', { type: 'range', min: String(lo), max: String(hi), step: '0.1', value: String(value), dataset: { path }, title: path });
        const out = el('output', { class: 'mono' }, fmt(value, 1));
        const s = { input, out, pending: null, busy: false, dragging: false };
        input.disabled = !getToken();
        input.addEventListener('pointerdown', () => { s.dragging = true; });
        input.addEventListener('pointerup', () => { s.dragging = false; });
        input.addEventListener('input', () => { out.textContent = fmt(Number(input.value), 1); this.sendSlider(path, s, input.value); });
        input.addEventListener('change', () => { s.dragging = false; this.sendSlider(path, s, input.value); });
        this.sliders.set(path, s);
        rows.push(el('div', { class: 'slider-row' }, el('label', { title: path }, motor), input, out));
      }
      if (rows.length) groups.push(el('details', { open: true }, el('summary', {}, agent.name), ...rows));
    }
    container.replaceChildren(...(groups.length ? groups : [el('div', { class: 'muted' }, 'no motorised agents in this world')]));
  }

  /** Sends a slider's value, one request at a time, the newest value last. */
  async sendSlider(path, s, value) {
    if (!getToken()) return;
    s.pending = value;
    if (s.busy) return;
    s.busy = true;
    while (s.pending !== null) {
      const text = s.pending;
      s.pending = null;
      try {
        await post('/api/live/values', { path, value: String(text) });
      } catch (err) {
        showError(err.reason || err);  // the server's reason names the path already
      }
    }
    s.busy = false;
  }

  // --- value files ----------------------------------------------------------------------------------------
  async refreshFiles() {
    const names = fileNames(await getJson('/api/live/files'));
    const vals = names.filter((n) => n.endsWith('.val'));
    for (const id of ['pose-files', 'props-files']) {
      const sel = $(id), keep = sel.value;
      sel.replaceChildren(...(vals.length ? vals.map((n) => el('option', { value: n }, n)) : [el('option', { value: '' }, '(no value files)')]));
      if (vals.includes(keep)) sel.value = keep;
    }
  }

  async save(file, filter) {
    if (!this.needToken()) return;
    try {
      await post('/api/live/save', { file: String(file).trim(), filter });
      await this.refreshFiles();
    } catch (err) {
      showError(err);
    }
  }

  async load(file) {
    if (!this.needToken()) return;
    if (!file) { showError('no value file chosen'); return; }
    try {
      await post('/api/live/load', { file });
      await this.refreshProps();
    } catch (err) {
      showError(err);
    }
  }

  // --- Object Properties ----------------------------------------------------------------------------------
  /** Shows the values of body or object `name` (null: none), each editable as in Simulation Properties. */
  async showObject(name) {
    this.object = name || null;
    const isObject = !!name && !(this.header.agents || []).some((a) => name.startsWith(`${a.name}/`));
    $('object-name').textContent = name ? `${isObject ? 'object' : 'robot body'}: ${name}` : 'click a body or pick one from Bodies & joints';
    $('object-initial').hidden = !isObject;  // a robot starts where its agent is placed
    $('object-state').textContent = '';
    const body = $('object-table').querySelector('tbody');
    if (!name) { body.replaceChildren(); return; }
    const escaped = name.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
    const rows = await getJson(`/api/live/values?filter=${encodeURIComponent(`/Sim/${escaped}/[^/]+`)}`);
    body.replaceChildren(...(Array.isArray(rows) ? rows : []).map((row) => this.valueRow(row)));
  }

  /** Set as initial: the object's pose now is where the next reset and every later one start it. */
  async keepAsInitial() {
    if (!this.needToken() || !this.object) return;
    try {
      await post('/api/live/initial', { object: this.object });
      $('object-state').textContent = 'its pose now is its start from the next Reset on';
    } catch (err) {
      showError(err.reason || err);
    }
  }

  // --- Simulation Properties ------------------------------------------------------------------------------
  async refreshProps() {
    const filter = $('props-filter').value || '.*';
    const rows = await getJson(`/api/live/values?filter=${encodeURIComponent(filter)}`);
    const body = $('props-table').querySelector('tbody');
    body.replaceChildren(...(Array.isArray(rows) ? rows : []).map((row) => this.valueRow(row)));
  }

  /** A table row of one value: path, type and an input that sets it (Enter or leaving the cell). */
  valueRow(row) {
    const input = el('input', { value: String(row.value ?? ''), dataset: { path: row.path }, disabled: !getToken() });
    const tr = el('tr', {}, el('td', { class: 'path', title: row.path }, row.path), el('td', { class: 'muted' }, row.type || ''), el('td', {}, input));
    const commit = async () => {
      if (input.value === input.defaultValue) return;
      if (!this.needToken()) return;
      try {
        const answer = await post('/api/live/values', { path: row.path, value: input.value });
        const now = answer && answer.value !== undefined ? String(answer.value) : input.value;
        input.value = now;
        input.defaultValue = now;
        tr.classList.remove('bad');
        tr.title = '';
      } catch (err) {
        tr.classList.add('bad');
        tr.title = err.reason || err.message;
        input.value = input.defaultValue;  // back to the value in force, so a later blur does not send it again
        showError(err.reason || err);       // the server's reason names the path already
      }
    };
    input.addEventListener('keydown', (e) => { if (e.key === 'Enter') commit(); if (e.key === 'Escape') input.value = input.defaultValue; });
    input.addEventListener('blur', commit);
    return tr;
  }

  // --- the Logger -----------------------------------------------------------------------------------------
  /** The server's logger state (docs/viewer-api.md): what is written, how much of its bounds, why it stopped. */
  showLogger(l) {
    if (!l) return;
    const mib = (bytes) => `${(bytes / 1048576).toFixed(bytes < 1048576 ? 2 : 1)} MiB`;
    $('logger-bounds').textContent = `a log stops at ${mib(l.max_bytes)} or ${Math.round(l.max_seconds)} s, or when control lapses`;
    let text = 'stopped';
    if (l.file) text = `writing ${l.file}: ${mib(l.bytes)} of ${mib(l.max_bytes)}, ${Math.floor(l.seconds)} s of ${Math.round(l.max_seconds)} s`;
    else if (l.stopped) text = `stopped: ${l.stopped}`;
    if ($('logger-state').textContent !== text) $('logger-state').textContent = text;
    if (l.stopped && l.stopped !== this.shownLoggerStop) {
      this.shownLoggerStop = l.stopped;
      this.refreshFiles().catch(() => {});
    }
  }

  async logger(action) {
    if (!this.needToken()) return;
    try {
      const body = action === 'start' ? { action, filter: $('logger-filter').value, file: $('logger-file').value.trim() } : { action };
      const state = await post('/api/live/logger', body);
      if (state && state.logger) this.showLogger(state.logger);
      else $('logger-state').textContent = action === 'start' ? `writing ${$('logger-file').value.trim()}` : 'stopped';
      await this.refreshFiles();
    } catch (err) {
      showError(err);
    }
  }
}
