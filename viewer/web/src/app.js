// orcs-view's page: loads the session, shows recordings (3D view, time line, plots), batch/evolve/gap items,
// live simulations, and the render mode; keeps window.orcsView (docs/viewer-api.md) for tests and scripts.
import { World } from './world.js';
import { ResolutionGovernor } from './resolution.js';
import { Plots, shortName } from './plots.js';
import { Items } from './items.js';
import { Live } from './live.js';
import { Dashboard } from './dashboard.js';
import { runRender } from './render.js';
import { getJson, getFloat64, getChannels } from './api.js';
import { $, el, showError, hideError, onError, floorIndex, matcher } from './util.js';

const PLAY_ICON = '<svg viewBox="0 0 16 16" width="14" height="14"><path d="M4 2v12l10-6z" fill="currentColor"/></svg>';
const PAUSE_ICON = '<svg viewBox="0 0 16 16" width="14" height="14"><rect x="3" y="2" width="3.5" height="12" fill="currentColor"/><rect x="9.5" y="2" width="3.5" height="12" fill="currentColor"/></svg>';
const params = new URLSearchParams(location.search);
const renderMode = params.get('render') === '1';

// ---------------------------------------------------------------------------------------------------------
// The state object tests read back.
const state = {
  ready: false,
  mode: null,
  item: null,
  progress: null,     // the followed run's progress.json and its item, or null
  time: 0,
  frame: 0,
  playing: false,
  speed: 1,
  loop: true,
  bodies: {},
  plots: [],
  fps: 0,
  drawn: 0,
  scale: 1,
  errors: [],
  seek: (t) => seek(t),
  play: () => play(),
  pause: () => pause(),
  step: (n = 1) => step(n),
  select: (name) => select(name),
  plot: (path) => plot(path),
  open: (id) => open(id),
  get views() { return world ? world.viewList() : []; },
  screenOf: (body) => world.screenOf(String(body)),
  addView: (spec) => addView(spec),
  removeView: (id) => removeView(id),
  /** The shown run's frames and its overlay's (0 when none): a robot run's grow while the robot moves. */
  get frames() { return rec ? rec.frames : 0; },
  get overlayFrames() { return overlay ? overlay.frames : 0; },
  get ghostBodies() { return world ? world.ghostBodies.length : 0; },
};
window.orcsView = state;
onError((text) => state.errors.push(text));
window.addEventListener('unhandledrejection', (e) => { e.preventDefault(); showError(e.reason); });
window.addEventListener('error', (e) => { e.preventDefault(); showError(e.message || 'script error'); });
$('banner-close').addEventListener('click', hideError);

// ---------------------------------------------------------------------------------------------------------
// A recording as the page holds it: header, times, pose channels, other channels on demand.
class Recording {
  static async load(rid, label) {
    const r = new Recording();
    r.id = rid;
    r.header = await getJson(`/api/recording/${encodeURIComponent(rid)}`);
    r.times = await getFloat64(`/api/recording/${encodeURIComponent(rid)}/times`);
    r.frames = r.times.length;
    if (!r.frames) throw new Error(`recording ${rid} has no frames`);
    r.duration = typeof r.header.duration === 'number' ? r.header.duration : r.times[r.frames - 1];
    r.channels = Array.isArray(r.header.channels) ? r.header.channels : [];
    r.index = new Map(r.channels.map((c, i) => [c, i]));
    r.label = label || r.header.file || rid;
    r.cache = new Map();
    const poseIds = [];
    for (const b of r.header.bodies || []) if (b.dynamic && Array.isArray(b.pose_channels)) poseIds.push(...b.pose_channels);
    if (poseIds.length) for (const [id, v] of await getChannels(rid, poseIds, r.frames)) r.cache.set(id, v);
    r.contactData = null;
    return r;
  }

  channelIndex(path) { return this.index.has(path) ? this.index.get(path) : -1; }

  async values(id) {
    if (id < 0) return null;
    if (!this.cache.has(id)) for (const [k, v] of await getChannels(this.id, [id], this.frames)) this.cache.set(k, v);
    return this.cache.get(id);
  }

  value(id, frame) {
    const v = this.cache.get(id);
    return v ? v[frame] : NaN;
  }

  async contacts() {
    if (!this.contactData) this.contactData = await getJson(`/api/recording/${encodeURIComponent(this.id)}/contacts`);
    return this.contactData;
  }

  contactsAt(frame) {
    const d = this.contactData;
    if (!d || !Array.isArray(d.offsets) || !Array.isArray(d.contacts)) return [];
    return d.contacts.slice(d.offsets[frame] ?? 0, d.offsets[frame + 1] ?? 0);
  }

  frameAt(t) { return floorIndex(this.times, t + 1e-9); }
}

// ---------------------------------------------------------------------------------------------------------
const canvas = $('canvas');
let world;
let plots;
let items;
let live = null;
let dashboard = null;
let session = null;
let rec = null;        // the shown recording
let overlay = null;    // the run overlaid in plots and drawn as a ghost
let simTime = 0;
let drawnFrame = -1;
let lastWall = null;
const renderTimes = [];
let selected = null;

function start() {
  if (renderMode) {
    document.body.classList.add('render-mode');
    const w = Math.max(16, Math.min(7680, parseInt(params.get('width') || '960', 10) || 960));
    const h = Math.max(16, Math.min(4320, parseInt(params.get('height') || '540', 10) || 540));
    world = new World(canvas, { fixedSize: [w, h] });
  } else {
    world = new World(canvas);
  }
  plots = new Plots($('plots'), {
    onChange: (paths) => { state.plots = paths.slice(); },
    onSeek: (t) => { if (state.mode === 'files') seek(t); },
  });
  items = new Items({
    open,
    openRecording: (rid, opts) => openRecording(rid, opts),
    onProgress: (progress) => { state.progress = progress; },
    refreshSession: () => refreshSession().catch((err) => showError(err)),
  });
  dashboard = new Dashboard({
    state,
    openRecording: (rid, opts) => { dashboard.hide(); items.markCurrent(null); return openRecording(rid, opts); },
    hasFiles: () => (session?.items || []).some((i) => i.kind !== 'broker' && i.kind !== 'live'),
  });
  wireUi();
  boot().catch((err) => showError(err));
  if (!renderMode) requestAnimationFrame(tick);
}

async function boot() {
  session = await getJson('/api/session');
  state.mode = session.mode === 'live' ? 'live' : 'files';
  document.body.classList.add(`mode-${state.mode}`);
  $('session-title').textContent = session.title || '';
  if (session.title) document.title = `orcs-view — ${session.title}`;
  items.setSession(session);
  fillCompare();
  if (state.mode === 'live') {
    live = new Live({ world, plots, state, fillTree, channelSearch });
    await live.start();
    state.item = 'live';
    items.markCurrent('live');
    state.ready = true;
    return;
  }
  const wanted = params.get('item');
  const first = wanted ? items.byId(wanted) : (session.items || []).find((i) => !i.parent) || (session.items || [])[0];
  if (wanted && !first) throw new Error(`no item ${wanted} in this session`);
  if (!first) { showError('this session has no items'); return; }
  await open(first.id);
  if (renderMode) {
    await runRender({ world, rec, params, seekFrame: (f) => applyFrame(f, true), state });
  }
}

// The items again: a run in progress has written recordings since the page loaded.
async function refreshSession() {
  const fresh = await getJson('/api/session');
  session.items = fresh.items;
  items.setSession(session);
  items.markCurrent(state.item);
  fillCompare();
}

function fillCompare() {
  const select = $('compare');
  const recs = (session.items || []).filter((i) => i.kind === 'recording');
  select.replaceChildren(el('option', { value: '' }, '— none —'),
    ...recs.map((i) => el('option', { value: i.id }, `${i.label || i.path || i.id}`)));
  // A refreshed list (a run in progress grew) keeps naming the run overlaid.
  if (overlay && [...select.options].some((o) => o.value === overlay.id)) select.value = overlay.id;
}

// ---------------------------------------------------------------------------------------------------------
// Items.
async function open(id) {
  const item = items.byId(id);
  if (!item) {
    // A recording id not listed in the session (a batch job's, a gap replay) opens as a recording.
    if (/^r\d+$/.test(String(id))) return openRecording(String(id));
    showError(`no item "${id}" in this session`);
    return false;
  }
  items.markCurrent(id);
  if (item.kind !== 'broker') dashboard.hide();
  try {
    switch (item.kind) {
      case 'broker': items.clearDetail(); await dashboard.show(); break;
      case 'recording': items.clearDetail(); return await openRecording(id, { label: item.label });
      case 'batch': await items.showBatch(id); break;
      case 'evolve': await items.showEvolve(id); break;
      case 'gap': await items.showGap(id); break;
      case 'robot': await items.showRobot(id); break;
      case 'live': return true;
      default: showError(`unknown item kind "${item.kind}"`); return false;
    }
  } catch (err) {
    showError(err);
    return false;
  }
  state.item = id;
  if (!state.ready) { state.ready = true; }
  return true;
}

/**
 * Shows a recording; opts.overlay names a run to overlay (a gap's measured run, a robot's twin); opts.plot lists
 * channels to plot when nothing is plotted; opts.follow: the same run again, grown (a robot run being written) —
 * the camera and the time stay, or move to the newest frame when the last one was shown.
 */
async function openRecording(rid, opts = {}) {
  const following = Boolean(opts.follow && rec && rec.id === rid);
  const atEnd = following && drawnFrame >= rec.frames - 1;
  const keptTime = simTime;
  const wasPlaying = following && state.playing;
  let next;
  try {
    next = await Recording.load(rid, opts.label);
  } catch (err) {
    showError(err);
    return false;
  }
  pause();
  rec = next;
  state.item = rid;
  if (items.byId(rid)) items.markCurrent(rid);
  world.load(rec.header);
  world.setContactsVisible($('toggle-contacts').checked);
  world.setJointsVisible($('toggle-joints').checked);
  world.setBodiesVisible($('toggle-bodies') ? $('toggle-bodies').checked : true);
  if ($('toggle-contacts').checked) await rec.contacts().catch((e) => showError(e));
  const slider = $('tl-slider');
  slider.max = String(rec.frames - 1);
  simTime = following ? (atEnd ? rec.times[rec.frames - 1] : keptTime) : rec.times[0];
  drawnFrame = -1;
  applyFrame(rec.frameAt(simTime), true);
  if (!following) world.setPreset(renderMode ? 'follow' : world.preset || 'front');
  fillTree();
  channelSearch();
  await plots.setPrimary(rec, true);
  if (!plots.paths.length && Array.isArray(opts.plot) && opts.plot.length) await plots.addAll(opts.plot);
  overlay = null;
  world.clearGhost();
  $('compare').value = '';
  if (opts.overlay) await setOverlay(opts.overlay, opts.overlayLabel);
  else plots.setOverlay(null);
  applyFrame(rec.frameAt(simTime), true);
  world.render();
  countRender();
  state.ready = true;
  if (wasPlaying && !atEnd) play();
  return true;
}

async function setOverlay(rid, label) {
  if (!rid) {
    overlay = null;
    world.clearGhost();
    await plots.setOverlay(null);
    return;
  }
  try {
    const item = items.byId(rid);
    overlay = await Recording.load(rid, label || (item && item.label) || rid);
  } catch (err) {
    showError(err);
    return;
  }
  const select = $('compare');
  if (![...select.options].some((o) => o.value === rid)) select.append(el('option', { value: rid }, overlay.label));
  select.value = rid;
  if ((overlay.header.bodies || []).some((b) => b.dynamic && Array.isArray(b.pose_channels))) {
    world.loadGhost(overlay.header);
    world.setGhostVisible($('toggle-ghost').checked);
  }
  await plots.setOverlay(overlay);
  applyFrame(drawnFrame < 0 ? 0 : drawnFrame, true);
}

// ---------------------------------------------------------------------------------------------------------
// The time line.
function applyFrame(frame, force = false) {
  if (!rec) return;
  frame = Math.max(0, Math.min(rec.frames - 1, frame));
  if (frame === drawnFrame && !force) return;
  drawnFrame = frame;
  world.pose((id) => rec.value(id, frame));
  if (world.contactGroup.visible) world.setContacts(rec.contactsAt(frame));
  const t = rec.times[frame];
  if (overlay && world.ghostBodies.length) {
    const f = overlay.frameAt(t);
    world.pose((id) => overlay.value(id, f), true);
  }
  world.poses(state.bodies);
  state.frame = frame;
  state.time = t;
  plots.setTime(t);
  $('tl-slider').value = String(frame);
  $('tl-time').textContent = `t = ${t.toFixed(3)} s / ${rec.duration.toFixed(3)} s   frame ${frame} / ${rec.frames - 1}`;
  $('time-label').textContent = `t = ${t.toFixed(3)} s`;
}

function seek(t) {
  if (state.mode === 'live') return;
  if (!rec) return;
  const x = Number(t);
  if (!Number.isFinite(x)) { showError(`seek: not a time: ${t}`); return; }
  simTime = Math.max(rec.times[0], Math.min(rec.times[rec.frames - 1], x));
  applyFrame(rec.frameAt(simTime));
}

function play() {
  if (state.mode === 'live') { live?.control('run'); return; }
  if (!rec) return;
  if (drawnFrame >= rec.frames - 1) simTime = rec.times[0];
  state.playing = true;
  lastWall = null;
  $('tl-play').innerHTML = PAUSE_ICON;
}

function pause() {
  if (state.mode === 'live') { live?.control('pause'); return; }
  state.playing = false;
  $('tl-play').innerHTML = PLAY_ICON;
}

function step(n = 1) {
  if (state.mode === 'live') { live?.stepMany(n); return; }
  if (!rec) return;
  pause();
  const f = Math.max(0, Math.min(rec.frames - 1, drawnFrame + Math.trunc(Number(n) || 0)));
  simTime = rec.times[f];
  applyFrame(f);
}

function setSpeed(v) {
  const x = Number(v);
  if (!(x > 0)) return;
  state.speed = x;
  const sel = $('tl-speed');
  if ([...sel.options].some((o) => Number(o.value) === x)) sel.value = String(x);
}

function countRender() {
  const now = performance.now();
  renderTimes.push(now);
  while (renderTimes.length && renderTimes[0] < now - 1000) renderTimes.shift();
  state.drawn++;
}

// While the picture moves (a recording playing, a live simulation running), the drawing resolution follows the
// browser's frame rate (resolution.js): software GL cannot fill a large canvas 60 times a second, and a slow
// draw also slows the live long poll. Standing still, the view is drawn at full resolution again.
const governor = new ResolutionGovernor();
function adaptResolution(now) {
  const moving = !renderMode && state.playing && (state.mode === 'files' || state.mode === 'live');
  world.setScale(governor.update(now, moving));
  state.scale = world.scale;
}

function tick(now) {
  if (state.playing && rec && state.mode === 'files') {
    if (lastWall !== null) {
      simTime += ((now - lastWall) / 1000) * state.speed;
      const end = rec.times[rec.frames - 1];
      if (simTime > end) {
        if (state.loop && end > rec.times[0]) simTime = rec.times[0] + ((simTime - rec.times[0]) % (end - rec.times[0]));
        else { simTime = end; pause(); }
      }
    }
    lastWall = now;
    applyFrame(rec.frameAt(simTime));
  }
  if (live) live.beforeDraw();
  world.follow();
  if (world.needsDraw || state.playing) {
    world.render();
    countRender();
  }
  while (renderTimes.length && renderTimes[0] < now - 1000) renderTimes.shift();
  state.fps = renderTimes.length;
  adaptResolution(now);
  requestAnimationFrame(tick);
}

// ---------------------------------------------------------------------------------------------------------
// Selection and plots.
function headerOf() { return live ? live.header : rec && rec.header; }
function channelList() { return live ? live.channels : rec ? rec.channels : []; }
function hasChannel(path) { return live ? live.channelIndex(path) >= 0 : rec ? rec.channelIndex(path) >= 0 : false; }

/** Resolves a body or joint name (exact, or the end of a path: "Right/Knee"). */
function resolve(name) {
  const header = headerOf();
  if (!header) return null;
  const bodies = header.bodies || [], joints = header.joints || [];
  const exactB = bodies.find((b) => b.name === name);
  if (exactB) return { kind: 'body', obj: exactB };
  const exactJ = joints.find((j) => j.name === name || (j.agent && j.motor && `${j.agent}/${j.motor}` === name));
  if (exactJ) return { kind: 'joint', obj: exactJ };
  const suffix = (n) => n === name || n.endsWith('/' + name);
  const j = joints.find((x) => suffix(x.name) || (x.motor && suffix(x.motor)));
  if (j) return { kind: 'joint', obj: j };
  const b = bodies.find((x) => suffix(x.name));
  if (b) return { kind: 'body', obj: b };
  return null;
}

function channelsFor(found) {
  const all = channelList();
  if (found.kind === 'body') {
    const prefix = `/Sim/${found.obj.name}/`;
    const pos = ['x', 'y', 'z'].map((a) => `${prefix}Position.${a}`).filter(hasChannel);
    if (pos.length) return pos;
    return all.filter((c) => c.startsWith(prefix)).slice(0, 6);
  }
  const j = found.obj;
  const prefix = j.agent && j.motor ? `/Sim/${j.agent}/${j.motor}/` : `/Sim/${j.name}/`;
  const out = ['JointAngle', 'DesiredAngle', 'MotorTorque'].map((leaf) => prefix + leaf).filter(hasChannel);
  if (!out.includes(prefix + 'JointAngle') && Number.isInteger(j.angle_channel) && all[j.angle_channel]) out.unshift(all[j.angle_channel]);
  if (out.length) return out;
  return all.filter((c) => c.startsWith(prefix)).slice(0, 6);
}

async function select(name, geom = '') {
  const found = resolve(String(name));
  if (!found) { showError(`nothing named "${name}" in this world`); return false; }
  selected = found.obj.name;
  world.highlight(found.kind === 'body' ? found.obj.name : null);
  markTree();
  const part = geom && !found.obj.name.endsWith(geom) ? ` — its part ${geom}` : '';
  $('selection').textContent = `${found.kind}: ${found.obj.name}${part}`;
  if (live) live.showObject(found.kind === 'body' ? found.obj.name : null).catch((err) => showError(err));
  plots.clear();
  for (const path of channelsFor(found)) await plots.add(path);
  if (live) plots.refreshLive();
  return true;
}

async function plot(path) {
  if (!hasChannel(String(path))) { showError(`no channel "${path}" in ${state.item}`); return false; }
  const ok = await plots.add(String(path));
  if (live) plots.refreshLive();
  return ok;
}

// The Camera Manager: views beside the main one (world.js addView).
function addView(spec) {
  const id = world.addView(spec);
  if (id === null) showError(`no view added: ${JSON.stringify(spec)} (at most 3 views, of a body or robot in this world)`);
  return id;
}

function removeView(id) { world.removeView(Number(id)); }

/** The choices of the "+ view" menu for the shown world: each robot's head camera and follow view, the presets, the selection. */
function fillViewChoices() {
  const header = headerOf();
  const menu = $('view-add');
  const option = (spec, text) => el('option', { value: JSON.stringify(spec) }, text);
  const choices = [el('option', { value: '' }, '+ view')];
  const names = new Set((header && header.bodies || []).map((b) => b.name));
  for (const agent of (header && header.agents) || []) {
    if (names.has(`${agent.name}/Middle/Head`)) choices.push(option({ kind: 'body', body: `${agent.name}/Middle/Head`, label: `head camera: ${agent.name}` }, `head camera: ${agent.name}`));
    choices.push(option({ kind: 'follow', agent: agent.name }, `follow ${agent.name}`));
  }
  for (const preset of ['front', 'left', 'top']) choices.push(option({ kind: 'preset', preset }, `fixed: ${preset}`));
  choices.push(el('option', { value: 'selected' }, 'camera on the selected body'));
  menu.replaceChildren(...choices);
}

function fillTree() {
  const header = headerOf();
  if (!header) return;
  fillViewChoices();
  const filter = matcher($('tree-filter').value || '') || (() => true);
  const entries = [];
  for (const b of header.bodies || []) {
    if ((b.geoms || []).every((g) => g.shape === 'plane')) continue;
    if (filter(b.name)) entries.push(el('li', { class: 'body', dataset: { name: b.name }, onclick: () => select(b.name) },
      el('span', { class: 'icon' }, b.dynamic ? '◆' : '◇'), b.name));
  }
  for (const j of header.joints || []) {
    if (filter(j.name)) entries.push(el('li', { class: 'joint', dataset: { name: j.name }, onclick: () => select(j.name) },
      el('span', { class: 'icon' }, j.motor ? '⚙' : '○'), j.name));
  }
  $('tree').replaceChildren(...entries);
  markTree();
}

function markTree() {
  for (const li of $('tree').children) {
    const on = li.dataset.name === selected;
    li.classList.toggle('current', on);
    if (on) li.scrollIntoView({ block: 'nearest' });
  }
}

function channelSearch() {
  const text = $('channel-search').value;
  const list = $('channel-results');
  if (!text.trim()) { list.replaceChildren(); return; }
  const test = matcher(text);
  if (!test) { list.replaceChildren(el('li', { class: 'muted' }, 'not a valid regular expression')); return; }
  const found = channelList().filter(test);
  const rows = found.slice(0, 200).map((c) => el('li', { title: `plot ${c}`, onclick: () => plot(c) }, shortName(c)));
  if (found.length > 200) rows.push(el('li', { class: 'muted' }, `… ${found.length - 200} more`));
  if (!found.length) rows.push(el('li', { class: 'muted' }, 'no channel matches'));
  list.replaceChildren(...rows);
}

// ---------------------------------------------------------------------------------------------------------
// The controls.
function wireUi() {
  // A "robots" toggle and the selection label, added here so index.html stays the static skeleton.
  const bodiesToggle = el('label', { class: 'toggle' }, el('input', { type: 'checkbox', id: 'toggle-bodies', checked: true }), ' bodies');
  $('toggle-contacts').parentElement.before(bodiesToggle);
  $('plot-tools').append(el('div', { id: 'selection', class: 'muted' }, 'click a body or pick one from the list'));

  for (const b of document.querySelectorAll('[data-camera]')) b.addEventListener('click', () => world.setPreset(b.dataset.camera));
  $('toggle-contacts').addEventListener('change', async (e) => {
    world.setContactsVisible(e.target.checked);
    if (e.target.checked && rec && !live) {
      try { await rec.contacts(); } catch (err) { showError(err); }
      applyFrame(drawnFrame, true);
    }
  });
  $('toggle-joints').addEventListener('change', (e) => world.setJointsVisible(e.target.checked));
  $('toggle-bodies').addEventListener('change', (e) => world.setBodiesVisible(e.target.checked));
  $('toggle-ghost').addEventListener('change', (e) => world.setGhostVisible(e.target.checked));
  $('toggle-shadows').checked = world.shadows;
  $('toggle-shadows').addEventListener('change', (e) => world.setShadows(e.target.checked));
  $('tl-play').addEventListener('click', () => (state.playing ? pause() : play()));
  $('tl-back').addEventListener('click', () => step(-1));
  $('tl-forward').addEventListener('click', () => step(1));
  $('tl-speed').addEventListener('change', (e) => setSpeed(e.target.value));
  $('tl-loop').addEventListener('change', (e) => { state.loop = e.target.checked; });
  $('tl-slider').addEventListener('input', (e) => {
    if (!rec) return;
    const f = Number(e.target.value);
    simTime = rec.times[f];
    applyFrame(f);
  });
  $('tree-filter').addEventListener('input', fillTree);
  $('view-add').addEventListener('change', (e) => {
    const choice = e.target.value;
    e.target.value = '';
    if (!choice) return;
    if (choice !== 'selected') addView(JSON.parse(choice));
    else if (selected && world.byName.has(selected)) addView({ kind: 'body', body: selected });
    else showError('select a body first (click it, or pick it from Bodies & joints)');
  });
  $('channel-search').addEventListener('input', channelSearch);
  $('plot-clear').addEventListener('click', () => plots.clear());
  $('compare').addEventListener('change', (e) => setOverlay(e.target.value));

  // Click (not drag) on a body selects it.
  let down = null;
  canvas.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  canvas.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    const name = world.pick(e.clientX, e.clientY);
    if (name) select(name, world.pickedGeom);
  });

  window.addEventListener('keydown', (e) => {
    const t = e.target;
    const typing = (t.tagName === 'INPUT' && !['checkbox', 'range', 'button'].includes(t.type)) || t.tagName === 'SELECT' || t.tagName === 'TEXTAREA';
    if (typing || e.ctrlKey || e.metaKey || e.altKey) return;
    const presets = { 1: 'front', 2: 'back', 3: 'left', 4: 'right', 5: 'top', 6: 'follow' };
    if (e.key in presets) { world.setPreset(presets[e.key]); e.preventDefault(); return; }
    if (e.key === ' ') {
      e.preventDefault();
      if (state.mode === 'live') live?.toggle(); else if (state.playing) pause(); else play();
    } else if (e.key === 'ArrowRight') { e.preventDefault(); step(1); }
    else if (e.key === 'ArrowLeft') { e.preventDefault(); if (state.mode !== 'live') step(-1); }
    else return;
    if (t.tagName === 'BUTTON' || t.type === 'range') t.blur();
  });
}

start();
