// End-to-end test of `laplacian_deform --serve` in real Chromium (headless, SwiftShader): starts the
// C++ server on a free port, opens the editor, paints a region of interest and a handle with the
// mouse, drags the handle (translate, then Ctrl-drag to rotate), switches the representation, and
// checks that the mesh moved, the handle reached its target, one factorisation served every drag,
// and malformed requests get 400. Writes a screenshot (editor.png) to --out.
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
      const m = /editor at (http:\/\/127\.0\.0\.1:\d+\/)/.exec(text);
      if(m) { clearTimeout(timer); resolve({ child, url: m[1] }); }
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
  await page.mouse.up();
  await page.evaluate(() => window.editor.idle());
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
  assert.match(await page.textContent('#timing'), /update [\d.]+ ms .* factorizations 1/);
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

  // downloads, and malformed requests from the page
  const files = await page.evaluate(async () => {
    const s = window.editor.state.session;
    const get = async (f) => (await fetch(`/api/download?session=${s}&format=${f}`)).text();
    const bad = await fetch('/api/drag', { method: 'POST', body: '{"session": ' });
    const nan = await fetch('/api/drag', { method: 'POST', body: JSON.stringify({ session: s, translation: [0, 'NaN', 0] }) });
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
  assert.deepEqual(errors, []);
});
