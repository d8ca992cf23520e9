// Shared by the browser tests: the real orcs-view and orcs-sim binaries (ORCS_BIN_DIR, default build/bin of
// the repository), Debian's chromium through playwright-core (WebGL2 via SwiftShader), and small page helpers.
import { spawn, execFile } from 'node:child_process';
import { mkdtemp, rm } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';
import { promisify } from 'node:util';
import { chromium } from 'playwright-core';

export const repoRoot = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
export const binDir = path.resolve(repoRoot, process.env.ORCS_BIN_DIR || 'build/bin');
export const chromiumPath = process.env.ORCS_CHROMIUM || '/usr/bin/chromium';
const run = promisify(execFile);

/** A scratch folder, removed by the returned cleanup. */
export async function tempDir() {
  const dir = await mkdtemp(path.join(tmpdir(), 'orcs-browser-'));
  return { dir, cleanup: () => rm(dir, { recursive: true, force: true }) };
}

/** Makes a recording with orcs-sim --record (the A-Series standing 10 s unless args say otherwise). */
export async function makeRecording(file, args = []) {
  await run(path.join(binDir, 'orcs-sim'), ['--record', file, ...args], { cwd: repoRoot, timeout: 60_000 });
  return file;
}

/**
 * Starts orcs-view on a free loopback port (--port 0) and waits for its "serving http://..." line. The page is
 * this checkout's viewer/web (its files.txt), or ORCS_WEB_DIR when set. `program` may be another program that
 * becomes orcs-view (orcs-osp -gui: give it its own port options). Returns {url, osp, stop()}: `osp` is the
 * OSP server's {host, port} when orcs-view printed one (--osp), else null.
 */
export function startServer(args, { program = 'orcs-view' } = {}) {
  const own = program === 'orcs-view'
    ? ['--port', '0', '--web-dir', path.resolve(repoRoot, process.env.ORCS_WEB_DIR || 'viewer/web')] : [];
  const child = spawn(path.join(binDir, program), [...args, ...own], {
    cwd: repoRoot, stdio: ['ignore', 'pipe', 'pipe'],
  });
  let osp = null;
  let stderr = '';
  child.stderr.on('data', (d) => { stderr += d; });
  const exited = new Promise((resolve) => child.once('exit', (code, signal) => resolve({ code, signal })));
  const url = new Promise((resolve, reject) => {
    const timer = setTimeout(() => {
      child.kill('SIGKILL');
      reject(new Error(`orcs-view ${args.join(' ')} printed no address in 30 s: ${stderr.trim()}`));
    }, 30_000);
    child.once('error', (err) => { clearTimeout(timer); reject(err); });
    const lines = createInterface({ input: child.stdout });
    lines.on('line', (line) => {
      const o = / osp=([^\s:]+):(\d+)$/.exec(line);
      if (o) osp = { host: o[1], port: Number(o[2]) };
      const m = /serving (http:\/\/[^\s/]+)/.exec(line);
      if (m) { clearTimeout(timer); resolve(m[1] + '/'); }
    });
    exited.then(({ code, signal }) => {
      clearTimeout(timer);
      reject(new Error(`orcs-view ${args.join(' ')} exited (${code ?? signal}) before serving: ${stderr.trim()}`));
    });
  });
  return url.then((u) => ({
    url: u,
    osp,
    stderr: () => stderr,
    stop: async () => {
      if (child.exitCode === null && child.signalCode === null) child.kill('SIGTERM');
      const timer = setTimeout(() => child.kill('SIGKILL'), 5000);
      await exited;
      clearTimeout(timer);
    },
  }));
}

/**
 * Starts a program of the build's bin dir; its stderr is kept (child.stderrText()) for error messages and
 * child.exited resolves to {code, signal}. Killed by stopChildren().
 */
export function startChild(program, args) {
  const child = spawn(path.join(binDir, program), args, { cwd: repoRoot, stdio: ['ignore', 'pipe', 'pipe'] });
  let stderr = '';
  child.stderr.on('data', (d) => { stderr = (stderr + d).slice(-20_000); });
  child.stderrText = () => stderr.trim();
  child.exited = new Promise((resolve) => child.once('exit', (code, signal) => resolve({ code, signal })));
  child.once('error', () => {});
  return child;
}

/** Kills (SIGKILL) whichever of the children still run, and waits for them. */
export async function stopChildren(children) {
  const alive = children.filter((c) => c && c.exitCode === null && c.signalCode === null);
  for (const child of alive) child.kill('SIGKILL');
  await Promise.all(alive.map((c) => c.exited));
}

/** A real orcs-broker on loopback ephemeral ports: {child, clients, workers} (its two endpoints). */
export async function startBroker(heartbeat = '0.1') {
  const child = startChild('orcs-broker', ['--client-port', '0', '--worker-port', '0', '--heartbeat', heartbeat]);
  const line = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`orcs-broker printed no endpoints in 10 s: ${child.stderrText()}`)), 10_000);
    createInterface({ input: child.stdout }).once('line', (l) => { clearTimeout(timer); resolve(l); });
  });
  const m = /clients=(\S+) workers=(\S+)/.exec(line);
  if (!m) throw new Error(`orcs-broker's endpoints line: ${line}`);
  return { child, clients: m[1], workers: m[2] };
}

export function haveBinaries(...names) {
  return names.every((n) => existsSync(path.join(binDir, n)));
}

export async function launchBrowser(extraArgs = []) {
  return chromium.launch({
    executablePath: chromiumPath,
    // Software compositing: the page's WebGL still runs on SwiftShader, but the browser does not composite the
    // whole window through it every frame (measured: a blank page's requestAnimationFrame 37 → 61 per second
    // on a busy 2-core machine).
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-sandbox', '--disable-gpu-compositing',
      ...extraArgs],
  });
}

/** A page that collects console errors and uncaught exceptions into page.orcsProblems. */
export async function openPage(browser, url, viewport = { width: 1400, height: 850 }) {
  const page = await browser.newPage({ viewport });
  const problems = [];
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  page.orcsProblems = problems;
  await page.goto(url);
  await page.waitForFunction(() => window.orcsView && window.orcsView.ready === true, null, { timeout: 30_000 });
  return page;
}

/**
 * orcs-view on `args` (startServer), a headless browser and the page, ready: {server, browser, page, close()}.
 * close() ends all three and removes `tmp` (a tempDir()) when given.
 */
export async function openViewer(args, { program, tmp } = {}) {
  const server = await startServer(args, program ? { program } : {});
  const browser = await launchBrowser();
  const page = await openPage(browser, server.url);
  return {
    server, browser, page,
    close: async () => {
      await browser.close();
      await server.stop();
      await tmp?.cleanup();
    },
  };
}

/** Waits for n animation frames in the page (the view has drawn what was set before). */
export function frames(page, n = 2) {
  return page.evaluate((k) => new Promise((resolve) => {
    const next = (left) => (left ? requestAnimationFrame(() => next(left - 1)) : resolve());
    next(k);
  }), n);
}

/** Keeps a copy of the WebGL canvas' pixels (its drawing buffer is preserved) in the page under `name`. */
export function snapshotCanvas(page, name) {
  return page.evaluate((key) => {
    const c = document.getElementById('canvas');
    const copy = document.createElement('canvas');
    copy.width = c.width;
    copy.height = c.height;
    const g = copy.getContext('2d', { willReadFrequently: true });
    g.drawImage(c, 0, 0);
    (window.__testSnapshots ||= {})[key] = g.getImageData(0, 0, c.width, c.height);
  }, name);
}

/**
 * Compares two snapshots pixel by pixel (summed |ΔR|+|ΔG|+|ΔB| > 24 counts as changed): how many changed in
 * all, near the centre (the middle half across, two thirds down), in the bottom-left eighth, and in the columns
 * between fractions `columns` = [from, to] of the width (`inColumns`, of `columnPixels`).
 */
export function diffSnapshots(page, a, b, columns = [0, 1]) {
  return page.evaluate(([ka, kb, [from, to]]) => {
    const A = window.__testSnapshots[ka], B = window.__testSnapshots[kb];
    const { width, height } = A;
    let changed = 0, centre = 0, corner = 0, inColumns = 0;
    const x0 = Math.floor(from * width), x1 = Math.floor(to * width);
    for (let y = 0; y < height; y++) {
      for (let x = 0; x < width; x++) {
        const i = 4 * (y * width + x);
        const d = Math.abs(A.data[i] - B.data[i]) + Math.abs(A.data[i + 1] - B.data[i + 1]) + Math.abs(A.data[i + 2] - B.data[i + 2]);
        if (d <= 24) continue;
        changed++;
        if (Math.abs(x - width / 2) < width / 4 && Math.abs(y - height / 2) < height / 3) centre++;
        if (x < width / 8 && y > (height * 7) / 8) corner++;
        if (x >= x0 && x < x1) inColumns++;
      }
    }
    return { width, height, changed, centre, corner, inColumns, columnPixels: (x1 - x0) * height };
  }, [a, b, columns]);
}

/** Float64 or Float32 array from a route of the server. */
export async function fetchArray(url, Type) {
  const res = await fetch(url);
  if (!res.ok) throw new Error(`${url}: ${res.status} ${await res.text()}`);
  return new Type(await res.arrayBuffer());
}

export async function fetchJson(url, options) {
  const res = await fetch(url, options);
  if (!res.ok) throw new Error(`${url}: ${res.status} ${await res.text()}`);
  return res.json();
}

/** Polls fn until it returns a truthy value (or throws after timeoutMs). */
export async function until(fn, timeoutMs = 10_000, what = 'condition') {
  const end = Date.now() + timeoutMs;
  let last;
  for (;;) {
    last = await fn();
    if (last) return last;
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 100));
  }
}
