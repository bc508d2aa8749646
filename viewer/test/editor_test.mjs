// End-to-end test of `laplacian_deform --serve` in real Chromium (headless, SwiftShader): starts the
// C++ server on a free port, opens the editor, paints a region of interest and a handle with the
// mouse, drags the handle (translate, then Ctrl-drag to rotate), switches the representation, and
// checks that the mesh moved, the handle reached its target, one factorisation served every drag,
// and malformed requests get 400; that the page shows its round trip, the drag replies are binary
// and not compressed, two drags sent back to back end at the second one (the first never applied
// after it), a drag released while its selection is still preprocessed ends at the release,
// API calls without the token or from another origin are refused, and a second server
// on a taken port fails naming the port. Writes a screenshot (editor.png) to --out.
//   usage: node viewer/test/editor_test.mjs --server PATH/laplacian_deform [--out DIR] [--chromium PATH]
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { CHROMIUM_ARGS } from '../render.mjs';

const arg = (name, fallback) => { const i = process.argv.indexOf(name); return i > 0 ? process.argv[i + 1] : fallback; };
const tool = arg('--server', null);
const executablePath = arg('--chromium', '/usr/bin/chromium');
const out = path.resolve(arg('--out', fs.mkdtempSync(path.join(os.tmpdir(), 'editor-test-'))));
if(!tool) { console.error('usage: node test/editor_test.mjs --server PATH/laplacian_deform [--out DIR] [--chromium PATH]'); process.exit(2); }
fs.mkdirSync(out, { recursive: true });

/** Starts the server on a free port; resolves with { child, url } once it prints its address. */
function startEditorServer() {
  const child = spawn(tool, ['--serve', '--port', '0', '--output', path.join(out, 'saved')], { stdio: ['ignore', 'pipe', 'pipe'] });
  return new Promise((resolve, reject) => {
    let text = '';
    const timer = setTimeout(() => reject(new Error(`the server printed no address in 60 s: ${text}`)), 60000);
    child.stdout.on('data', (chunk) => {
      text += chunk;
      const m = /editor at (http:\/\/127\.0\.0\.1:(\d+)\/)#token=([0-9a-f]{32})/.exec(text);
      if(m) { clearTimeout(timer); resolve({ child, origin: m[1], port: Number(m[2]), token: m[3], url: `${m[1]}#token=${m[3]}` }); }
    });
    child.stderr.on('data', (chunk) => { text += chunk; });
    child.on('exit', (code) => { clearTimeout(timer); reject(new Error(`the server exited (${code}): ${text}`)); });
  });
}

const server = await startEditorServer();
const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'laplacian-editor-chromium-'));
const context = await chromium.launchPersistentContext(userDataDir, {
  executablePath, headless: true, args: CHROMIUM_ARGS, viewport: { width: 1100, height: 760 } });
after(async () => {
  await context.close();
  fs.rmSync(userDataDir, { recursive: true, force: true });
  server.child.kill();
});

test('paint, drag, rotate, switch policy in the editor page', { timeout: 300000 }, async () => {
  const page = context.pages()[0] || await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  const dragResponses = [];
  page.on('response', async (r) => {
    if(r.url().endsWith('/api/drag'))
      dragResponses.push({ status: r.status(), headers: await r.allHeaders(), request: await r.request().allHeaders() });
  });
  await page.goto(server.url);
  await page.waitForFunction(() => window.editor && window.editor.ready, null, { timeout: 120000 });
  const rest = await page.evaluate(() => window.editor.positions());
  const n = rest.length / 3;
  assert.ok(n > 100, `the default mesh has ${n} vertices`);

  // the vertex under the middle of the view: the ROI around it, then it as the handle
  const box = await page.locator('#panels').boundingBox();
  // (the cactus's right arm if it is there, else the middle of the view)
  let cx, cy, center = null;
  for(const [fx, fy] of [[0.8, 0.55], [0.5, 0.5]]) {
    [cx, cy] = [box.x + fx * box.width, box.y + fy * box.height];
    center = await page.evaluate(([x, y]) => window.editor.vertexAt(x, y), [cx, cy]);
    if(center !== null) break;
  }
  assert.notEqual(center, null, 'a vertex under the pointer');
  const setBrush = (k) => page.$eval('#brush', (el, k) => { el.value = String(k); el.dispatchEvent(new Event('input')); }, k);
  await page.click('#mode-roi');
  await setBrush(8);
  await page.mouse.click(cx, cy);
  await page.click('#mode-handle');
  await setBrush(1);
  await page.mouse.click(cx, cy);
  const counts = await page.evaluate(() => {
    const s = window.editor.state.status;
    return { roi: s.filter((x) => x === 1).length, handles: s.filter((x) => x === 2).length };
  });
  assert.ok(counts.roi > 20 && counts.handles >= 4, `painted ROI ${counts.roi}, handles ${counts.handles}`);
  assert.match(await page.textContent('#counts'), /ROI \d+, handles \d+/);

  // translate: drag the handle up by 90 pixels
  await page.click('#mode-drag');
  const h = await page.evaluate((v) => window.editor.screenOf(v), center);
  await page.mouse.move(h.x, h.y);
  await page.mouse.down();
  await page.mouse.move(h.x - 40, h.y - 110, { steps: 12 });
  // without a GPU (this test's Chromium runs with --disable-gpu: SwiftShader), lighter frames: no
  // multisampling, half the resolution while the button is down, the full one after the release
  const drawing = await page.evaluate(() => ({ renderer: window.editor.renderer(), scale: window.editor.renderScale(),
                                               antialias: window.editor.antialias() }));
  assert.equal(drawing.renderer, 'cpu', 'Chromium with --disable-gpu draws WebGL in software');
  assert.equal(drawing.scale, 0.5, 'half the resolution during the drag');
  assert.equal(drawing.antialias, false, 'no multisampling in software');
  await page.mouse.up();
  await page.evaluate(() => window.editor.idle());
  assert.equal(await page.evaluate(() => window.editor.renderScale()), 1, 'the full resolution after the release');
  const moved = await page.evaluate(() => ({
    positions: window.editor.positions(), updates: window.editor.state.updates, handleError: window.editor.handleError(),
    reply: window.editor.state.lastReply && { handle_error: window.editor.state.lastReply.handle_error,
                                              factorizations: window.editor.state.lastReply.factorizations } }));
  assert.ok(moved.updates >= 1, `${moved.updates} updates`);
  const displacement = (v) => Math.hypot(moved.positions[3 * v] - rest[3 * v], moved.positions[3 * v + 1] - rest[3 * v + 1],
                                         moved.positions[3 * v + 2] - rest[3 * v + 2]);
  let diag = 0;
  for(let k = 0; k < 3; ++k) {
    let lo = Infinity, hi = -Infinity;
    for(let v = 0; v < n; ++v) { lo = Math.min(lo, rest[3 * v + k]); hi = Math.max(hi, rest[3 * v + k]); }
    diag += (hi - lo) ** 2;
  }
  diag = Math.sqrt(diag);
  assert.ok(displacement(center) > 0.02 * diag, `the handle moved by ${displacement(center)} (diagonal ${diag})`);
  let movedCount = 0;
  for(let v = 0; v < n; ++v) movedCount += displacement(v) > 1e-6 * diag;
  assert.ok(movedCount > counts.handles, `${movedCount} vertices moved`);
  assert.ok(moved.handleError < 1e-5 * diag, `the handle is ${moved.handleError} from its target`);
  assert.ok(moved.reply.handle_error < 1e-9 * diag, `server: handle error ${moved.reply.handle_error}`);
  assert.equal(moved.reply.factorizations, 1, 'one factorisation for every drag');
  assert.match(await page.textContent('#timing'), /^round trip [\d.]+ ms, update [\d.]+ ms .* server [\d.]+ ms, factorizations 1/);
  const trip = await page.evaluate(() => window.editor.state.lastRoundTrip);
  assert.ok(trip.ms > 0 && trip.ms >= trip.serverMs, `round trip ${trip.ms} ms, server ${trip.serverMs} ms`);
  // the drag replies: binary frames of the moving vertices only, never compressed
  assert.ok(dragResponses.length >= 1);
  for(const r of dragResponses.filter((x) => x.status === 200)) {
    assert.match(r.request['accept-encoding'] || '', /br|gzip/, 'the browser accepts compressed replies');
    assert.equal(r.headers['content-encoding'], undefined, `drag reply encoded ${r.headers['content-encoding']}`);
    assert.equal(r.headers['content-type'], 'application/octet-stream');
  }
  const moving = await page.evaluate(() => window.editor.state.moving.length);
  assert.equal(moving, counts.roi + counts.handles);
  assert.ok(trip.bytes < 4 + 2048 + 12 * moving, `a drag reply of ${trip.bytes} bytes for ${moving} moving vertices`);
  await page.screenshot({ path: path.join(out, 'editor.png') });

  // rotate: Ctrl-drag; the handle follows its rotated target, still one factorisation
  await page.keyboard.down('Control');
  await page.mouse.move(h.x, h.y);
  await page.mouse.down();
  await page.mouse.move(h.x + 60, h.y, { steps: 8 });
  await page.mouse.up();
  await page.keyboard.up('Control');
  await page.evaluate(() => window.editor.idle());
  const rotated = await page.evaluate(() => ({ updates: window.editor.state.updates, handleError: window.editor.handleError(),
                                               factorizations: window.editor.state.lastReply.factorizations,
                                               angle: JSON.parse(JSON.stringify(window.editor.state.transform.elements)) }));
  assert.ok(rotated.updates > moved.updates);
  assert.ok(Math.abs(rotated.angle[1]) > 0.05 || Math.abs(rotated.angle[2]) > 0.05 || Math.abs(rotated.angle[6]) > 0.05,
            'the transform has a rotation');
  assert.ok(rotated.handleError < 1e-5 * diag, `after rotating the handle is ${rotated.handleError} from its target`);
  assert.equal(rotated.factorizations, 1);

  // the same drag with the vertex-based representation: another shape, handle still on target
  const before = await page.evaluate(() => window.editor.positions());
  await page.selectOption('#representation', 'vertex');
  await page.waitForFunction((u) => window.editor.state.updates > u, rotated.updates);
  const vertexBased = await page.evaluate(() => ({ positions: window.editor.positions(), handleError: window.editor.handleError() }));
  assert.ok(vertexBased.positions.some((x, i) => Math.abs(x - before[i]) > 1e-6 * diag), 'the representation changes the shape');
  assert.ok(vertexBased.handleError < 1e-5 * diag);

  // two drags sent back to back: one is in flight, the other waits; the page ends at the second
  // one's result and never applies the first after it; a third replacing the pending one is sent
  // instead of it (only the latest pending drag is sent)
  const coalesced = await page.evaluate(async () => {
    const e = window.editor, s = e.state;
    await e.idle();
    const sentBefore = s.seq, appliedBefore = s.applied.length;
    const m = (x) => [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, 0.5 * x, 0, 1];
    e.drag(m(0.05));
    e.drag(m(0.10));
    e.drag(m(0.15));
    await e.idle();
    return { sent: s.seq - sentBefore, applied: s.applied.slice(appliedBefore), last: s.seq,
             handleError: e.handleError(), transform: Array.from(s.transform.elements) };
  });
  assert.equal(coalesced.sent, 2, `drags sent: ${coalesced.sent} (the second was replaced by the third)`);
  assert.equal(coalesced.applied[coalesced.applied.length - 1], coalesced.last, `applied ${coalesced.applied}`);
  assert.ok(coalesced.applied.every((x, i, a) => i === 0 || a[i - 1] < x), `applied in order: ${coalesced.applied}`);
  assert.equal(coalesced.transform[12], 0.15);
  assert.ok(coalesced.handleError < 1e-5 * diag, `the page ends at the last drag: handle ${coalesced.handleError} from it`);
  // the server's side: two drags racing (separate connections); whichever order they arrive in,
  // the session ends at the newer one (seq), the older is dropped (409) or applied before it
  const raced = await page.evaluate(async () => {
    const s = window.editor.state, headers = { 'Content-Type': 'application/json', 'X-Editor-Token': window.editor.token };
    const seq = s.seq + 1000;
    const send = (k, x) => fetch('/api/drag', { method: 'POST', headers,
      body: JSON.stringify({ session: s.session, seq: seq + k, translation: [x, 0, 0], iterations: 20 }) });
    const [a, b] = await Promise.all([send(1, 0.01), send(2, 0.02)]);
    const late = await send(0, 0.03);
    const def = await (await fetch(`/api/download?session=${s.session}&format=def&token=${window.editor.token}`)).text();
    return { a: a.status, aBody: await a.text(), b: b.status, late: late.status, lateBody: await late.text(), def };
  });
  assert.equal(raced.b, 200);
  assert.ok(raced.a === 200 || (raced.a === 409 && /superseded/.test(raced.aBody)), `first: ${raced.a} ${raced.aBody}`);
  assert.equal(raced.late, 409);
  assert.match(raced.lateBody, /superseded: drag \d+ of this session was overtaken/);
  const translation = raced.def.split('\n').filter((l) => /^\s*-?[\d.e+-]+(\s+-?[\d.e+-]+){3}\s*$/.test(l))[0].trim().split(/\s+/).map(Number);
  assert.ok(Math.abs(translation[3] - 0.02) < 1e-9, `the session ends at the newer drag: .def row ${translation}`);

  // refusals seen from a page: no token, another content type
  const refused = await page.evaluate(async () => {
    const s = window.editor.state.session;
    const noToken = await fetch('/api/reset', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ session: s }) });
    const plain = await fetch('/api/reset', { method: 'POST', headers: { 'X-Editor-Token': window.editor.token }, body: JSON.stringify({ session: s }) });
    return { noToken: noToken.status, noTokenText: await noToken.text(), plain: plain.status, plainText: await plain.text() };
  });
  assert.equal(refused.noToken, 401);
  assert.match(refused.noTokenText, /missing token/);
  assert.equal(refused.plain, 415);
  assert.match(refused.plainText, /Content-Type: application\/json/);

  // downloads, and malformed requests from the page
  const files = await page.evaluate(async () => {
    const s = window.editor.state.session, t = window.editor.token;
    const headers = { 'Content-Type': 'application/json', 'X-Editor-Token': t };
    const get = async (f) => (await fetch(`/api/download?session=${s}&format=${f}&token=${t}`)).text();
    const bad = await fetch('/api/drag', { method: 'POST', headers, body: '{"session": ' });
    const nan = await fetch('/api/drag', { method: 'POST', headers, body: JSON.stringify({ session: s, translation: [0, 'NaN', 0] }) });
    return { off: await get('off'), sel: await get('sel'), def: await get('def'), bad: bad.status, badText: await bad.text(),
             nan: nan.status, nanText: await nan.text() };
  });
  assert.match(files.off, /^OFF/);
  assert.match(files.sel, /^# per vertex status/);
  assert.equal(files.sel.split('\n').filter((l) => l === '2').length, counts.handles);
  assert.match(files.def, /4x4 handle transformation/);
  assert.equal(files.bad, 400);
  assert.match(files.badText, /not valid JSON/);
  assert.equal(files.nan, 400);
  assert.match(files.nanText, /translation\[1\] must be a number/);

  // reset: back to rest
  await page.click('#reset');
  await page.waitForFunction((r) => window.editor.positions().every((x, i) => Math.abs(x - r[i]) < 1e-5), rest);

  // a drag that moves and is released while its selection is still being preprocessed (the
  // selection's reply held back 1.5 s): nothing is lost, the handle ends where the pointer was
  // released, and the pointer moving afterwards without a button drags nothing
  // (the page's drag numbers continue past those the race above sent without it)
  await page.evaluate(() => { window.editor.state.selectionDirty = true; window.editor.state.seq += 2000; });
  await page.route('**/api/select', async (route) => { await new Promise((r) => setTimeout(r, 1500)); await route.continue(); });
  const before2 = await page.evaluate(() => window.editor.state.updates);
  const h2 = await page.evaluate((v) => window.editor.screenOf(v), center);
  await page.mouse.move(h2.x, h2.y);
  await page.mouse.down();
  await page.mouse.move(h2.x + 30, h2.y - 100, { steps: 6 });
  await page.mouse.up();
  const duringPreprocess = await page.evaluate(() => window.editor.state.updates);
  await page.evaluate(() => window.editor.idle());
  await page.unroute('**/api/select');
  const late = await page.evaluate(() => ({ updates: window.editor.state.updates, handleError: window.editor.handleError(),
                                            positions: window.editor.positions() }));
  assert.equal(duringPreprocess, before2, 'no drag before the selection is ready');
  assert.equal(late.updates, before2 + 1, 'one drag, to where the pointer was released');
  assert.ok(late.handleError < 1e-5 * diag, `the handle is ${late.handleError} from its target`);
  const lateMove = Math.hypot(...[0, 1, 2].map((k) => late.positions[3 * center + k] - rest[3 * center + k]));
  assert.ok(lateMove > 0.02 * diag, `the handle moved by ${lateMove} (diagonal ${diag})`);
  await page.mouse.move(h2.x - 50, h2.y + 40, { steps: 4 });
  await page.evaluate(() => window.editor.idle());
  assert.equal(await page.evaluate(() => window.editor.state.updates), late.updates, 'no drag after the button was released');
  assert.deepEqual(errors, []);
});

test('the page without the token says so, and another origin is refused', { timeout: 120000 }, async () => {
  const page = await context.newPage();
  await page.goto(server.origin);
  await page.waitForFunction(() => /no token in the address/.test(document.getElementById('message').textContent), null, { timeout: 60000 });
  // a page of another origin (here about:blank posting to the server) is refused by its Origin
  const other = await context.newPage();
  const status = await other.evaluate(async ([url, token]) => {
    try {
      const r = await fetch(`${url}api/meshes?token=${token}`, { mode: 'cors' });
      return r.status;
    } catch(e) { return 'blocked'; }
  }, [server.origin, server.token]);
  assert.equal(status, 'blocked');   // no CORS header: the browser does not hand the reply to the page
  const direct = await fetch(`${server.origin}api/meshes?token=${server.token}`, { headers: { Origin: 'http://evil.example' } });
  assert.equal(direct.status, 403);
  assert.match(await direct.text(), /from another site/);
  const rebound = await fetch(`${server.origin}api/meshes?token=${server.token}`);
  assert.equal(rebound.status, 200);
  await page.close();
  await other.close();
});

test('a second server on a taken port fails and names the port', { timeout: 60000 }, async () => {
  const child = spawn(tool, ['--serve', '--port', String(server.port), '--output', path.join(out, 'saved2')], { stdio: ['ignore', 'pipe', 'pipe'] });
  let text = '';
  child.stdout.on('data', (c) => { text += c; });
  child.stderr.on('data', (c) => { text += c; });
  const code = await new Promise((resolve) => {
    const timer = setTimeout(() => { child.kill(); resolve('still running'); }, 30000);
    child.on('exit', (c) => { clearTimeout(timer); resolve(c); });
  });
  assert.equal(code, 1, text);
  assert.match(text, new RegExp(`cannot listen on 127\\.0\\.0\\.1:${server.port} \\(is the port in use`));
});
