// orcs-view --live against a web page of another site, in a real browser (docs/security.md, "The browser"):
// chromium resolves evil.example to 127.0.0.1 (--host-resolver-rules), which is what DNS rebinding achieves, so a
// page "of evil.example" is same-origin with the server as far as the browser knows. The server refuses it; the
// page of the server's own address still takes control and shows the Logger's bounds.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { tempDir, startServer, launchBrowser, openPage, fetchJson, until } from './helpers.js';

let tmp, server, browser;
let port;

before(async () => {
  tmp = await tempDir();
  server = await startServer(['--live', '--files', tmp.dir]);
  port = new URL(server.url).port;
  browser = await launchBrowser(['--host-resolver-rules=MAP evil.example 127.0.0.1']);
});

after(async () => {
  await browser?.close();
  await server?.stop();
  await tmp?.cleanup();
});

test('a page reached as evil.example (DNS rebinding) gets 403 and no token', async () => {
  const page = await browser.newPage();
  const answer = await page.goto(`http://evil.example:${port}/`);
  assert.equal(answer.status(), 403, 'the page itself is refused');
  assert.match(await answer.text(), /is not this server/);
  // From that page, a same-origin request as far as the browser knows: it may read the answer, which is a refusal.
  const claim = await page.evaluate(async () => {
    const r = await fetch('/api/live/claim', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: '{}' });
    return { status: r.status, body: await r.text() };
  });
  assert.equal(claim.status, 403);
  assert.doesNotMatch(claim.body, /token/);
  // A cross-site request to the real address: sent (no-cors), refused by its Origin, and not even handed to the
  // page as an opaque answer (Cross-Origin-Resource-Policy: same-origin makes the fetch fail).
  const sent = await page.evaluate(async (p) => {
    const outcomes = [];
    for (const [route, body] of [['claim', '{}'], ['control', '{"action":"run"}']]) {
      try {
        await fetch(`http://127.0.0.1:${p}/api/live/${route}`, { method: 'POST', mode: 'no-cors', body });
        outcomes.push('opaque');
      } catch (err) {
        outcomes.push('blocked');
      }
    }
    return outcomes;
  }, port);
  assert.deepEqual(sent, ['blocked', 'blocked']);
  const frame = await fetchJson(`${server.url}api/live/frame?since=-1`);
  assert.equal(frame.running, false, 'nothing ran');
  await page.close();
});

test('the server\'s own page still takes control (nobody else claimed it) and shows the Logger\'s bounds', async () => {
  const page = await openPage(browser, server.url);
  await page.click('#live-claim');
  await until(async () => /you control/.test(await page.locator('#live-claim-state').textContent()), 20_000,
    'control taken: the foreign claim did not lock the page out');
  assert.match(await page.locator('#logger-bounds').textContent(), /64\.0 MiB or 600 s/);
  await page.fill('#logger-filter', '.*Knee/JointAngle');
  await page.fill('#logger-file', 'k.csv');
  await page.click('#logger-start');
  await until(async () => /writing k\.csv: .* of 64\.0 MiB, \d+ s of 600 s/.test(await page.locator('#logger-state').textContent()),
    20_000, 'the logger shows how much of its bounds it used');
  await page.click('#logger-stop');
  await until(async () => /^stopped$/.test(await page.locator('#logger-state').textContent()), 20_000, 'stopped');
  assert.deepEqual(page.orcsProblems, []);
  await page.close();
});
