// Browser editor timings, measured in real Chromium (headless, software WebGL) against
// `laplacian_deform --serve`: page load (cold profile, then a reload), opening a mesh of the data
// folder, and drags of a 10% region of interest: the time from a pointer move until the new
// positions are on the page (the round trip) next to the server's own `update` time.
// Prints the numbers; asserts nothing (timings depend on the machine and its load).
//   usage: node benchmark/editor_round_trip.mjs --server PATH/laplacian_deform
//            [--mesh armadillo.off] [--drags 8] [--iterations 4] [--chromium /usr/bin/chromium]
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
const meshName = arg('--mesh', 'armadillo.off');
const drags = Number(arg('--drags', '8'));
const iterations = Number(arg('--iterations', '4'));
const executablePath = arg('--chromium', '/usr/bin/chromium');
if(!tool) { console.error('usage: node benchmark/editor_round_trip.mjs --server PATH/laplacian_deform [--mesh NAME]'); process.exit(2); }

const median = (a) => { const s = [...a].sort((x, y) => x - y); return s.length ? s[Math.floor(s.length / 2)] : NaN; };
const f1 = (x) => x.toFixed(1);

function startServer() {
  const out = fs.mkdtempSync(path.join(os.tmpdir(), 'editor-bench-out-'));
  const child = spawn(tool, ['--serve', '--port', '0', '--output', out], { stdio: ['ignore', 'pipe', 'pipe'] });
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

  // a 10% ROI grown around the vertex in the middle of the view, its 1-ring as the handle
  const box = await page.locator('#panels').boundingBox();
  const handle = await page.evaluate(([x, y]) => window.editor.vertexAt(x, y), [box.x + box.width / 2, box.y + box.height / 2]);
  if(handle === null) throw new Error('no vertex in the middle of the view');
  const selection = await page.evaluate(([h, it]) => {
    const s = window.editor.state;
    const ring = (v, k) => {
      const seen = new Set([v]); let front = [v];
      for(let r = 0; r < k && seen.size < 0.1 * s.n; ++r) {
        const next = [];
        for(const u of front) for(const w of s.neighbours[u]) if(!seen.has(w)) { seen.add(w); next.push(w); }
        front = next;
      }
      return seen;
    };
    for(const v of ring(h, 1000)) s.status[v] = 1;
    for(const v of ring(h, 1)) s.status[v] = 2;
    s.selectionDirty = true;
    document.getElementById('iterations').value = String(it);
    return { roi: s.status.filter((x) => x === 1).length, handles: s.status.filter((x) => x === 2).length };
  }, [handle, iterations]);
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
      if(d && m && d.applied === undefined) { d.applied = performance.now(); d.update = Number(m[1]); }
    }).observe(document.getElementById('timing'), { childList: true, characterData: true, subtree: true });
  });
  await page.click('#mode-drag');
  const h = await page.evaluate((v) => window.editor.screenOf(v), handle);
  await page.mouse.move(h.x, h.y);
  await page.mouse.down();
  // the selection is sent (and factored) on the press
  await page.waitForFunction(() => /preprocess/.test(document.getElementById('timing').textContent), null,
                             { timeout: 120000, polling: 5 });
  for(let i = 1; i <= drags; ++i) {
    await page.mouse.move(h.x - 3 * i, h.y - 6 * i);
    await page.waitForFunction((k) => window.__drags.length >= k && window.__drags[k - 1].applied !== undefined,
                               i, { timeout: 120000, polling: 5 });
  }
  await page.mouse.up();
  const samples = await page.evaluate(() => window.__drags);
  // the network part: request start to the reply's last byte (resource timing), per drag
  const network = await page.evaluate(() => performance.getEntriesByType('resource')
    .filter((e) => e.name.endsWith('/api/drag')).slice(-window.__drags.length).map((e) => e.responseEnd - e.startTime));
  const trips = samples.map((d) => d.applied - d.sent), updates = samples.map((d) => d.update);
  console.log(`drag: round trip median ${f1(median(trips))} ms (min ${f1(Math.min(...trips))}, max ${f1(Math.max(...trips))}), ` +
              `server update median ${f1(median(updates))} ms; target 1.5 x update + 10 ms = ${f1(1.5 * median(updates) + 10)} ms`);
  const within = samples.filter((d) => d.applied - d.sent <= 1.5 * d.update + 10).length;
  console.log(`drag round trips (ms): ${trips.map(f1).join(' ')}; within 1.5 x their own update + 10 ms: ${within}/${samples.length}`);
  console.log(`drag request to last byte of the reply (ms): ${network.map(f1).join(' ')} (the rest of the round trip is the page's: ` +
              `decoding, normals, and waiting for the main thread, e.g. a frame being drawn)`);
  console.log(`page timing line: ${await page.textContent('#timing')}`);
} finally {
  await context.close();
  fs.rmSync(userDataDir, { recursive: true, force: true });
  fs.rmSync(server.out, { recursive: true, force: true });
  server.child.kill();
}
