// The page's frame rate playing a 10 s A-Series recording in headless chromium (the browser tests' browser:
// Debian's chromium, WebGL 2 through SwiftShader), against the browser's own ceiling in the same run.
//
//   node tests/bench/viewer_fps.mjs [--runs 5] [--uncapped] [--compare]   (after scripts/build.sh and setup_web.sh)
//
// --uncapped starts the browser without its frame-rate limit and vsync, so frames come as fast as the page can
// draw them: the page's headroom above the display's 60 Hz, not what a user sees.
// --compare measures, in each run and in turn on fresh pages, the page as it opens, with shadows on, and with two
// views beside the main one (the Camera Manager's head camera and a follow view): what each costs, peers in one run.
//
// Each run opens a fresh page, plays from t = 0 at 1x, lets the page settle its drawing resolution for 2 s and
// counts the frames drawn over the next 3 s. Prints every run, then the median, and the load of the machine.
import path from 'node:path';
import { loadavg, availableParallelism } from 'node:os';
import { parseArgs } from 'node:util';
import {
  tempDir, makeRecording, startServer, launchBrowser, openPage,
} from '../browser/helpers.js';

const { values } = parseArgs({
  options: {
    runs: { type: 'string', default: '5' }, uncapped: { type: 'boolean', default: false },
    compare: { type: 'boolean', default: false },
  },
});
const runs = Math.max(1, Math.min(50, Number(values.runs) || 5));

/** requestAnimationFrame callbacks per second with nothing drawn: what the browser allows at most. */
function ceiling(page) {
  return page.evaluate(() => new Promise((resolve) => {
    let n = 0;
    const t0 = performance.now();
    const f = () => {
      n++;
      if (performance.now() - t0 < 2000) requestAnimationFrame(f); else resolve(n / ((performance.now() - t0) / 1000));
    };
    requestAnimationFrame(f);
  }));
}

async function playingRate(page) {
  await page.evaluate(() => { orcsView.seek(0); orcsView.play(); });
  await page.waitForTimeout(2000);
  const a = await page.evaluate(() => ({ drawn: orcsView.drawn, at: performance.now() }));
  await page.waitForTimeout(3000);
  const b = await page.evaluate(() => ({ drawn: orcsView.drawn, at: performance.now(), scale: orcsView.scale,
    buffer: `${document.getElementById('canvas').width}x${document.getElementById('canvas').height}` }));
  await page.evaluate(() => orcsView.pause());
  return { fps: (1000 * (b.drawn - a.drawn)) / (b.at - a.at), scale: b.scale, buffer: b.buffer };
}

const perSecond = (x) => (Number.isNaN(x) ? 'not measured' : `${x.toFixed(1)}/s`);
const median = (xs) => [...xs].sort((x, y) => x - y)[Math.floor(xs.length / 2)];

// The page set up as a configuration asks, before it plays.
const CONFIGURATIONS = {
  plain: async () => {},
  shadows: async (page) => page.evaluate(() => { document.getElementById('toggle-shadows').click(); }),
  'two views': async (page) => page.evaluate(() => {
    orcsView.addView({ kind: 'body', body: 'Humanoid/Middle/Head' });
    orcsView.addView({ kind: 'follow' });
  }),
};
const chosen = values.compare ? Object.keys(CONFIGURATIONS) : ['plain'];

const tmp = await tempDir();
const recording = await makeRecording(path.join(tmp.dir, 'stand.orcsrec'));
const server = await startServer([recording]);
const browser = await launchBrowser(values.uncapped ? ['--disable-frame-rate-limit', '--disable-gpu-vsync'] : []);
const fps = Object.fromEntries(chosen.map((c) => [c, []])), ceilings = [];
try {
  for (let k = 0; k < runs; k++) {
    for (const name of chosen) {
      const page = await openPage(browser, server.url);
      await CONFIGURATIONS[name](page);
      // Without the frame-rate limit an empty page has nothing to draw and no rate to measure.
      const c = values.uncapped ? NaN : await ceiling(page);
      const r = await playingRate(page);
      fps[name].push(r.fps);
      ceilings.push(c);
      console.log(`run ${k + 1}/${runs}, ${name}: ${r.fps.toFixed(1)} frames/s drawn (browser ceiling ${perSecond(c)}), ` +
        `drawing buffer ${r.buffer} (scale ${r.scale.toFixed(2)}), load ${loadavg()[0].toFixed(1)}`);
      await page.close();
    }
  }
} finally {
  await browser.close();
  await server.stop();
  await tmp.cleanup();
}
for (const name of chosen) {
  console.log(`median, ${name}: ${median(fps[name]).toFixed(1)} frames/s drawn, browser ceiling ` +
    `${perSecond(median(ceilings))} (${runs} runs, ${availableParallelism()} cores)`);
}
