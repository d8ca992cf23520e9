// The original's textures in orcs-view (issue 22, item 3): an object's `texture` travels from the XML through the
// recording to the page, which draws the original's built-in textures as simple patterns. Two recordings of the
// same wall, one textured, are drawn from the same camera: the textured face has a pattern (many grey levels),
// the plain one a flat colour.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { writeFile } from 'node:fs/promises';
import { tempDir, makeRecording, startServer, launchBrowser, openPage, frames, snapshotCanvas, fetchJson } from './helpers.js';

let tmp, server, browser, page;

// A white wall 0.6 m wide and high, facing the front camera, alone on the floor.
function wall(texture) {
  return `<?xml version="1.0"?>
<ORCS version="1.0" defaultRobot="false">
  <Environment>
    <object type="box" name="Wall" position="(0, 0.3, 0)" dimension="(0.6, 0.6, 0.05)" color="white"${
      texture ? ` texture="${texture}"` : ''}/>
  </Environment>
</ORCS>
`;
}

before(async () => {
  tmp = await tempDir();
  const recordings = [];
  for (const [name, texture] of [['plain', ''], ['board', 'AccelBoard'], ['other', 'Wood']]) {
    const env = path.join(tmp.dir, `${name}.xml`);
    await writeFile(env, wall(texture));
    recordings.push(makeRecording(path.join(tmp.dir, `${name}.orcsrec`), ['-env', env, '--duration', '0.05']));
  }
  server = await startServer(await Promise.all(recordings));
  browser = await launchBrowser();
  page = await openPage(browser, server.url);
});

after(async () => {
  await browser?.close();
  await server?.stop();
  await tmp?.cleanup();
});

// Grey levels in the middle tenth of the canvas (inside the wall from the front camera): how many distinct values
// and their standard deviation.
async function centreTexture(item) {
  assert.equal(await page.evaluate((id) => window.orcsView.open(id), item), true);
  await page.waitForFunction((id) => window.orcsView.item === id && window.orcsView.ready, item);
  await page.click('[data-camera="front"]');
  await frames(page, 3);
  await snapshotCanvas(page, item);
  return page.evaluate((key) => {
    const { width, height, data } = window.__testSnapshots[key];
    const levels = new Set();
    let sum = 0, squares = 0, n = 0;
    for (let y = Math.floor(height * 0.45); y < height * 0.55; y++) {
      for (let x = Math.floor(width * 0.45); x < width * 0.55; x++) {
        const i = 4 * (y * width + x);
        const grey = (data[i] + data[i + 1] + data[i + 2]) / 3;
        levels.add(Math.round(grey));
        sum += grey;
        squares += grey * grey;
        n++;
      }
    }
    const mean = sum / n;
    return { levels: levels.size, deviation: Math.sqrt(Math.max(0, squares / n - mean * mean)), mean };
  }, item);
}

test('the recording carries the texture name of the XML object', async () => {
  const header = await fetchJson(`${server.url}api/recording/r1`);
  const body = header.bodies.find((b) => b.name === 'Wall');
  assert.ok(body, 'the wall is in the recording');
  assert.equal(body.geoms[0].texture, 'AccelBoard');
  const plain = await fetchJson(`${server.url}api/recording/r0`);
  assert.equal(plain.bodies.find((b) => b.name === 'Wall').geoms[0].texture, undefined, 'no texture: no field');
});

test('a textured wall shows its pattern, a plain one a flat colour', async () => {
  const plain = await centreTexture('r0');
  const board = await centreTexture('r1');
  const other = await centreTexture('r2');
  assert.ok(plain.mean > 60, `the plain wall is in view (mean grey ${plain.mean.toFixed(1)})`);
  assert.ok(plain.deviation < 2, `the plain wall is flat (σ ${plain.deviation.toFixed(2)})`);
  assert.ok(board.deviation > 15, `AccelBoard shows a pattern (σ ${board.deviation.toFixed(2)})`);
  assert.ok(other.deviation > 15, `an unknown texture name shows the checker (σ ${other.deviation.toFixed(2)})`);
  assert.ok(board.levels > 3 && other.levels > 1, `${board.levels} and ${other.levels} grey levels`);
  assert.deepEqual(page.orcsProblems, []);
  assert.deepEqual(await page.evaluate(() => window.orcsView.errors), []);
});
