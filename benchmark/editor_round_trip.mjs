// Browser editor timings, measured in real Chromium (headless, software WebGL) against
// `laplacian_deform --serve`: page load (cold profile, then a reload), opening a mesh of the data
// folder, drags of a region of interest (10% of the mesh by default): the time from a pointer move
// until the new positions are on the page (the round trip) next to the server's own `update` time;
// then selections: the time from the press on a new selection until its preprocess is on the page
// (the first selection of the session, then --selections more at other places of the view).
// Prints the numbers; asserts nothing (timings depend on the machine and its load).
//   usage: node benchmark/editor_round_trip.mjs --server PATH/laplacian_deform
//            [--mesh armadillo.off | --mesh-file PATH] [--roi-percent 10] [--drags 8]
//            [--selections 4] [--iterations 4] [--chromium /usr/bin/chromium] [--trace FILE]
// --trace writes Chromium's trace of the drags (DevTools protocol; open it in chrome://tracing or
// Perfetto): the main thread's tasks and the GPU process's work per frame.
// --mesh-file serves PATH as the session's "default" mesh (e.g. a large mesh outside the data folder).
// Needs `npm ci` in viewer/ (playwright-core) and the mesh in the tool's data folder
// (scripts/setup.sh unpacks CGAL's meshes).
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { chromium } from '../viewer/node_modules/playwright-core/index.mjs';
import { CHROMIUM_ARGS } from '../viewer/render.mjs';

const arg = (name, fallback) => { const i = process.argv.indexOf(name); return i > 0 ? process.argv[i + 1] : fallback; };
const tool = arg('--server', null);
const meshFile = arg('--mesh-file', null);
const meshName = meshFile ? 'default' : arg('--mesh', 'armadillo.off');
const roiPercent = Number(arg('--roi-percent', '10'));
const drags = Number(arg('--drags', '8'));
const selections = Number(arg('--selections', '4'));
const iterations = Number(arg('--iterations', '4'));
const executablePath = arg('--chromium', '/usr/bin/chromium');
const traceFile = arg('--trace', null);
if(!tool) { console.error('usage: node benchmark/editor_round_trip.mjs --server PATH/laplacian_deform [--mesh NAME]'); process.exit(2); }

const median = (a) => { const s = [...a].sort((x, y) => x - y); return s.length ? s[Math.floor(s.length / 2)] : NaN; };
const f1 = (x) => x.toFixed(1);

function startServer() {
  const out = fs.mkdtempSync(path.join(os.tmpdir(), 'editor-bench-out-'));
  const child = spawn(tool, ['--serve', ...(meshFile ? [meshFile] : []), '--port', '0', '--output', out],
                      { stdio: ['ignore', 'pipe', 'pipe'] });
  return new Promise((resolve, reject) => {
    let text = '';
    child.stdout.on('data', (c) => {
      text += c;
      const m = /editor at (http:\/\/127\.0\.0\.1:\d+\/\S*)/.exec(text);
      if(m) resolve({ child, url: m[1], out });
    });
    child.stderr.on('data', (c) => { text += c; });
    child.on('exit', (code) => reject(new Error(`the server exited (${code}): ${text}`)));
  });
}

const server = await startServer();
const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'editor-bench-chromium-'));
const context = await chromium.launchPersistentContext(userDataDir, {
  executablePath, headless: true, args: CHROMIUM_ARGS, viewport: { width: 1100, height: 760 } });
try {
  const page = context.pages()[0] || await context.newPage();
  const load = async (reload) => {
    const t0 = Date.now();
    if(reload) await page.reload(); else await page.goto(server.url);
    await page.waitForFunction(() => window.editor && window.editor.ready, null, { timeout: 120000, polling: 10 });
    const ms = Date.now() - t0;
    const three = await page.evaluate(() => performance.getEntriesByType('resource')
      .filter((e) => /\/three\//.test(e.name))
      .reduce((a, e) => ({ files: a.files + 1, ms: Math.max(a.ms, e.responseEnd - e.startTime),
                           bytes: a.bytes + e.transferSize }), { files: 0, ms: 0, bytes: 0 }));
    return { ms, three };
  };
  const cold = await load(false);
  const warm = await load(true);
  console.log(`page load: cold ${cold.ms} ms (three.js: ${cold.three.files} files, slowest ${f1(cold.three.ms)} ms, ` +
              `${cold.three.bytes} bytes transferred), reload ${warm.ms} ms (three.js ${warm.three.bytes} bytes transferred)`);

  const open = await page.evaluate(async (name) => {
    const t = performance.now();
    await window.editor.openMesh(name);
    return { ms: performance.now() - t, n: window.editor.state.n };
  }, meshName);
  console.log(`open ${meshName}: ${f1(open.ms)} ms (${open.n} vertices)`);

  // a ROI of --roi-percent of the mesh grown around the vertex at (x, y) of the view, its 1-ring as the handle
  const paintSelection = async (x, y) => {
    const handle = await page.evaluate(([px, py]) => window.editor.vertexAt(px, py), [x, y]);
    if(handle === null) throw new Error(`no vertex at (${x}, ${y}) of the view`);
    const counts = await page.evaluate(([h, it, fraction]) => {
      const s = window.editor.state;
      const ring = (v, k) => {
        const seen = new Set([v]); let front = [v];
        for(let r = 0; r < k && seen.size < fraction * s.n; ++r) {
          const next = [];
          for(const u of front) for(const w of s.neighbours[u]) if(!seen.has(w)) { seen.add(w); next.push(w); }
          front = next;
        }
        return seen;
      };
      s.status.fill(0);
      for(const v of ring(h, 1000)) s.status[v] = 1;
      for(const v of ring(h, 1)) s.status[v] = 2;
      s.selectionDirty = true;
      document.getElementById('iterations').value = String(it);
      return { roi: s.status.filter((x) => x === 1).length, handles: s.status.filter((x) => x === 2).length };
    }, [handle, iterations, roiPercent / 100]);
    return { handle, ...counts };
  };
  // the press on a changed selection sends it (POST /api/select, the preprocess): the time from
  // the press until the page shows the preprocess on its timing line
  await page.evaluate(() => {
    window.__presses = [];
    window.addEventListener('pointerdown', () => window.__presses.push({ at: performance.now() }), true);
    new MutationObserver(() => {
      const p = window.__presses[window.__presses.length - 1];
      const m = /^preprocess ([\d.]+) ms/.exec(document.getElementById('timing').textContent);
      if(p && m && p.shown === undefined) { p.shown = performance.now(); p.preprocess = Number(m[1]); }
    }).observe(document.getElementById('timing'), { childList: true, characterData: true, subtree: true });
  });
  const pressSelection = async (handle) => {
    const k = await page.evaluate(() => window.__presses.length) + 1;
    const at = await page.evaluate((v) => window.editor.screenOf(v), handle);
    await page.mouse.move(at.x, at.y);
    await page.mouse.down();
    await page.waitForFunction((i) => window.__presses.length >= i && window.__presses[i - 1].shown !== undefined,
                               k, { timeout: 120000, polling: 5 });
    const p = await page.evaluate((i) => window.__presses[i - 1], k);
    // the request's part: its start to the reply's last byte (resource timing of this POST /api/select)
    const network = await page.evaluate(() => {
      const e = performance.getEntriesByType('resource').filter((r) => r.name.endsWith('/api/select')).pop();
      return e ? e.responseEnd - e.startTime : NaN;
    });
    return { ms: p.shown - p.at, preprocess: p.preprocess, network, at };
  };

  const box = await page.locator('#panels').boundingBox();
  const selection = await paintSelection(box.x + box.width / 2, box.y + box.height / 2);
  const handle = selection.handle;
  console.log(`selection: ROI ${selection.roi} (${f1(100 * selection.roi / open.n)}%), handles ${selection.handles}, ${iterations} iterations`);

  // every drag request is timed from the pointer move to the moment the page shows its timing
  // (written right after the new positions are set)
  await page.evaluate(() => {
    window.__drags = [];
    const realFetch = window.fetch;
    window.fetch = (url, init) => {
      if(String(url).includes('/api/drag')) window.__drags.push({ sent: performance.now() });
      return realFetch(url, init);
    };
    new MutationObserver(() => {
      const d = window.__drags[window.__drags.length - 1];
      const m = /update ([\d.]+) ms/.exec(document.getElementById('timing').textContent);
      if(d && m && d.applied === undefined) {
        d.applied = performance.now(); d.update = Number(m[1]);
        // the view draws the new positions at the next animation frame (requested before this);
        // the frame after it starts once that one is drawn and handed to the compositor
        requestAnimationFrame(() => requestAnimationFrame(() => { d.drawn = performance.now(); }));
      }
    }).observe(document.getElementById('timing'), { childList: true, characterData: true, subtree: true });
  });
  await page.click('#mode-drag');
  // the selection is sent (and factored) on the press
  const first = await pressSelection(handle);
  const h = first.at;
  let stopTrace = async () => {};
  if(traceFile) {
    const cdp = await context.newCDPSession(page);
    const events = [];
    cdp.on('Tracing.dataCollected', (e) => events.push(...e.value));
    const complete = new Promise((resolve) => cdp.on('Tracing.tracingComplete', resolve));
    await cdp.send('Tracing.start', { traceConfig: { includedCategories: ['devtools.timeline', 'toplevel', 'gpu', 'cc', 'blink', 'v8'] } });
    stopTrace = async () => {
      await cdp.send('Tracing.end');
      await complete;
      fs.writeFileSync(traceFile, JSON.stringify({ traceEvents: events }));
      console.log(`trace of the drags: ${traceFile} (${events.length} events)`);
    };
  }
  for(let i = 1; i <= drags; ++i) {
    await page.mouse.move(h.x - 3 * i, h.y - 6 * i);
    await page.waitForFunction((k) => window.__drags.length >= k && window.__drags[k - 1].drawn !== undefined,
                               i, { timeout: 120000, polling: 5 });
  }
  await page.mouse.up();
  await stopTrace();
  const samples = await page.evaluate(() => window.__drags);
  // the network part: request start to the reply's last byte (resource timing), per drag
  const network = await page.evaluate(() => performance.getEntriesByType('resource')
    .filter((e) => e.name.endsWith('/api/drag')).slice(-window.__drags.length).map((e) => e.responseEnd - e.startTime));
  const trips = samples.map((d) => d.applied - d.sent), updates = samples.map((d) => d.update);
  console.log(`drag: round trip median ${f1(median(trips))} ms (min ${f1(Math.min(...trips))}, max ${f1(Math.max(...trips))}), ` +
              `server update median ${f1(median(updates))} ms; target 1.5 x update + 10 ms = ${f1(1.5 * median(updates) + 10)} ms`);
  const within = samples.filter((d) => d.applied - d.sent <= 1.5 * d.update + 10).length;
  console.log(`drag round trips (ms): ${trips.map(f1).join(' ')}; within 1.5 x their own update + 10 ms: ${within}/${samples.length}`);
  const drawn = samples.map((d) => d.drawn - d.sent);
  console.log(`drag to frame drawn (the round trip, then the frame with the new positions): median ${f1(median(drawn))} ms ` +
              `(max ${f1(Math.max(...drawn))}); WebGL drawn by ${await page.evaluate(() => (window.editor.renderer ? window.editor.renderer() : 'a renderer this page does not name'))}`);
  console.log(`drag request to last byte of the reply (ms): ${network.map(f1).join(' ')} (the rest of the round trip is the page's: ` +
              `decoding, normals, and waiting for the main thread, e.g. a frame being drawn)`);
  console.log(`page timing line: ${await page.textContent('#timing')}`);

  // later selections of the same session, at other places of the view, each pressed, dragged once, released
  const later = [];
  for(let i = 0; i < selections; ++i) {
    const angle = 2 * Math.PI * i / Math.max(1, selections);
    const sel = await paintSelection(box.x + box.width * (0.5 + 0.12 * Math.cos(angle)),
                                     box.y + box.height * (0.5 + 0.2 * Math.sin(angle))).catch(() => null);
    if(!sel) continue;
    later.push({ ...(await pressSelection(sel.handle)), roi: sel.roi });
    const n = await page.evaluate(() => window.__drags.length) + 1;
    await page.mouse.move(later[later.length - 1].at.x - 5, later[later.length - 1].at.y - 10);
    await page.waitForFunction((k) => window.__drags.length >= k && window.__drags[k - 1].applied !== undefined,
                               n, { timeout: 120000, polling: 5 });
    await page.mouse.up();
  }
  console.log(`selection: first press to preprocess shown ${f1(first.ms)} ms (request to last byte of the reply ` +
              `${f1(first.network)} ms, server preprocess ${f1(first.preprocess)} ms)`);
  if(later.length)
    console.log(`later selections (${later.length}, ROI ${later.map((x) => x.roi).join('/')}): press to preprocess shown ` +
                `${later.map((x) => f1(x.ms)).join(' ')} ms (median ${f1(median(later.map((x) => x.ms)))}), ` +
                `request to last byte ${later.map((x) => f1(x.network)).join(' ')} ms, ` +
                `server preprocess ${later.map((x) => f1(x.preprocess)).join(' ')} ms`);
} finally {
  await context.close();
  fs.rmSync(userDataDir, { recursive: true, force: true });
  fs.rmSync(server.out, { recursive: true, force: true });
  server.child.kill();
}
