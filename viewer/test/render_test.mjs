// Renders small generated figures in real Chromium (headless, SwiftShader) and checks the PNGs
// are not blank: every panel drew its mesh, the colours follow ONE shared range (the rest shape,
// all zeros, has none of the upper colours that the most distorted panel has), the colour bar runs
// from the first to the last colour of the map; a missing panel file leaves that panel empty with a
// warning, and a task that cannot be drawn fails alone with a clear message.
//   usage: node viewer/test/render_test.mjs [--out DIR] [--chromium PATH]
//   (--out: keep the results and figures there; default: a temporary folder, removed)
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { renderFigures, CHROMIUM_ARGS } from '../render.mjs';
import { startServer } from '../serve.mjs';
import { chromium } from 'playwright-core';
import { writeSampleTask } from '../tools/make_sample.mjs';
import { sampleColormap } from '../lib/colormap.js';
import { decodePNG } from './png.mjs';

const chromiumArg = process.argv.indexOf('--chromium');
const executablePath = chromiumArg > 0 ? process.argv[chromiumArg + 1] : '/usr/bin/chromium';
const outArg = process.argv.indexOf('--out');
const keep = outArg > 0;
const root = keep ? path.resolve(process.argv[outArg + 1]) : fs.mkdtempSync(path.join(os.tmpdir(), 'viewer-render-'));
if(keep) fs.rmSync(root, { recursive: true, force: true });
const resultsDir = path.join(root, 'results'), figuresDir = path.join(root, 'figures');

/** Pixel statistics of a rectangle (CSS pixels times scale) of a decoded PNG. */
function stats(image, box, scale, predicate = () => true) {
  const x0 = Math.round(box.x * scale), y0 = Math.round(box.y * scale);
  const x1 = Math.min(image.width, Math.round((box.x + box.width) * scale));
  const y1 = Math.min(image.height, Math.round((box.y + box.height) * scale));
  let background = 0, matching = 0, total = 0;
  const colors = new Set();
  for(let y = y0; y < y1; ++y)
    for(let x = x0; x < x1; ++x) {
      const i = 4 * (y * image.width + x);
      const [r, g, b] = image.rgba.subarray(i, i + 3);
      ++total;
      if(r > 245 && g > 245 && b > 245) ++background;
      if(predicate(r, g, b)) ++matching;
      colors.add((r << 16) | (g << 8) | b);
    }
  return { total, background, foreground: total - background, matching, distinct: colors.size };
}

const near = (rgb, target, tolerance) => rgb.every((v, k) => Math.abs(v - Math.round(255 * target[k])) <= tolerance);
// The upper part of viridis (green to yellow, t >= about 0.6), lit or not; its dark purple start
// and the white background never match.
const upper = (r, g, b) => g > 140 && g > b + 30;

test('figures render in Chromium and are not blank', { timeout: 600000 }, async () => {
  writeSampleTask(resultsDir, { n: 20 });
  writeSampleTask(resultsDir, { task: 'two_panels', n: 12, panels: ['rest', 'edge'], format: 'ascii',
                                title: 'Two panels, ASCII PLY' });
  writeSampleTask(resultsDir, { task: 'broken', n: 4, panels: ['rest'] });
  const brokenTask = path.join(resultsDir, 'broken', 'task.json');
  fs.writeFileSync(brokenTask, JSON.stringify({ ...JSON.parse(fs.readFileSync(brokenTask, 'utf8')), panels: ['rest', 'vertex'] }));
  fs.mkdirSync(path.join(resultsDir, 'empty'));
  fs.writeFileSync(path.join(resultsDir, 'empty', 'task.json'), JSON.stringify({ task: 'empty', panels: ['rest'] }));
  writeSampleTask(resultsDir, { task: 'bad_ply', n: 4, panels: ['rest'], format: 'ascii' });
  const badPly = path.join(resultsDir, 'bad_ply', 'rest.ply');
  fs.writeFileSync(badPly, fs.readFileSync(badPly, 'latin1').replace('property float distortion', 'property float quality'), 'latin1');

  const scale = 1, width = 200;
  const results = await renderFigures(resultsDir, figuresDir, { width, scale, executablePath, log: (l) => console.log(l) });
  const byTask = Object.fromEntries(results.map((r) => [r.task, r]));
  assert.deepEqual(Object.keys(byTask).sort(), ['bad_ply', 'broken', 'bumpy_plane', 'empty', 'two_panels']);

  // A missing panel file leaves that panel empty, with a warning naming the file.
  const broken = byTask.broken;
  assert.ok(broken.ok, broken.error);
  assert.equal(broken.warnings.length, 1);
  assert.match(broken.warnings[0], /broken\/vertex\.ply: HTTP 404/);
  assert.deepEqual(broken.panels.map((p) => Boolean(p.missing)), [false, true]);
  const brokenImage = decodePNG(fs.readFileSync(broken.png));
  const [present, absent] = broken.layout.ports.map((box) => stats(brokenImage, box, scale, upper));
  assert.ok(present.foreground > 0.1 * present.total, 'the rest panel of the broken task is blank');
  assert.ok(absent.foreground < 0.05 * absent.total, 'the missing panel is not empty');
  assert.ok(absent.foreground > 0, 'the missing panel does not say "no result"');

  // A task whose every panel is missing, or has a bad file, fails alone with a clear message.
  assert.equal(byTask.empty.ok, false);
  assert.match(byTask.empty.error, /no panel could be loaded: empty\/rest\.ply: HTTP 404/);
  assert.equal(byTask.bad_ply.ok, false);
  assert.match(byTask.bad_ply.error, /bad_ply\/rest\.ply has no vertex property 'distortion' \(it has: quality\)/);
  assert.ok(!fs.existsSync(path.join(figuresDir, 'empty.png')) && !fs.existsSync(path.join(figuresDir, 'bad_ply.png')));

  // The four-panel figure.
  const four = byTask.bumpy_plane;
  assert.ok(four.ok, four.error);
  const image = decodePNG(fs.readFileSync(four.png));
  assert.equal(image.width, Math.round(four.layout.figure.width * scale));
  assert.equal(image.width, 4 * width * scale);
  assert.ok(image.height >= four.layout.colorbar.y + four.layout.colorbar.height);
  assert.deepEqual(Array.from(image.rgba.subarray(0, 3)), [255, 255, 255], 'white background');
  const whole = stats(image, four.layout.figure, scale);
  assert.ok(whole.distinct > 500, `only ${whole.distinct} distinct colours`);

  // Every panel drew its mesh (a good part of its port is not background).
  const ports = four.layout.ports;
  assert.equal(ports.length, 4);
  const panelStats = ports.map((box) => stats(image, box, scale, upper));
  panelStats.forEach((s, i) => assert.ok(s.foreground > 0.1 * s.total, `panel ${i} is blank (${s.foreground} of ${s.total})`));
  // One shared range: the rest shape (all zeros) has no upper colour; the most distorted has some.
  const maxima = four.panels.map((p) => p.max);
  assert.equal(four.panels[0].name, 'rest');
  assert.deepEqual([four.panels[0].min, four.panels[0].max], [0, 0], 'the rest field is all zeros');
  assert.equal(four.range.min, 0);
  const most = four.panels.findIndex((p) => p.max === Math.max(...maxima.slice(1)));
  assert.equal(panelStats[0].matching, 0, 'the rest shape shows an upper colour');
  assert.ok(panelStats[most].matching > 0, `the most distorted panel (${four.panels[most].name}) shows no upper colour`);
  // ... and the least distorted deformed panel much less of it (per-panel ranges would colour it alike).
  const least = four.panels.findIndex((p) => p.max === Math.min(...maxima.slice(1)));
  assert.ok(four.panels[least].max < 0.7 * four.panels[most].max, 'the sample should have distinct maxima');
  assert.ok(panelStats[least].matching < 0.25 * panelStats[most].matching,
            `${four.panels[least].name}: ${panelStats[least].matching} upper pixels, ${four.panels[most].name}: ${panelStats[most].matching}`);

  // The colour bar runs from the map's first colour to its last.
  const bar = four.layout.colorbar;
  const row = Math.round((bar.y + 4 + 6) * scale);   // inside the gradient (drawn from y = 4, >= 8 px high)
  const first = [], last = [];
  for(let x = 0; x < image.width; ++x) {
    const i = 4 * (row * image.width + x);
    const rgb = Array.from(image.rgba.subarray(i, i + 3));
    if(near(rgb, sampleColormap('viridis', 0), 6)) first.push(x);
    if(near(rgb, sampleColormap('viridis', 1), 6)) last.push(x);
  }
  assert.ok(first.length > 0 && last.length > 0, 'colour bar ends not found');
  assert.ok(Math.min(...first) < Math.max(...last), 'the colour bar runs from low (left) to high (right)');
  const barStats = stats(image, { x: bar.x, y: bar.y + 4, width: bar.width, height: 8 }, scale);
  assert.ok(barStats.distinct > 100, `colour bar has only ${barStats.distinct} colours`);

  // The two-panel figure (ASCII PLY) takes its panels from task.json.
  const two = byTask.two_panels;
  assert.ok(two.ok, two.error);
  const twoImage = decodePNG(fs.readFileSync(two.png));
  assert.equal(twoImage.width, 2 * width * scale);
  assert.deepEqual(two.panels.map((p) => p.name), ['rest', 'edge']);
  two.layout.ports.forEach((box, i) => {
    const s = stats(twoImage, box, scale);
    assert.ok(s.foreground > 0.1 * s.total, `two_panels: panel ${i} is blank`);
  });
});

test('interactive viewer: dragging in one panel turns every panel', { timeout: 600000 }, async () => {
  const dir = path.join(root, 'interactive');
  writeSampleTask(dir, { n: 12 });
  const server = await startServer(dir);
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'viewer-chromium-'));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath, headless: true, args: CHROMIUM_ARGS, viewport: { width: 1000, height: 500 } });
  try {
    const page = await context.newPage();
    await page.goto(server.url);
    await page.waitForFunction(() => window.viewerState && window.viewerState.status !== 'loading', null, { timeout: 120000 });
    assert.equal(await page.evaluate(() => window.viewerState.status), 'rendered');
    assert.equal(await page.locator('#task option').count(), 1);
    const ports = await page.evaluate(() => window.viewerState.view.panels.map((p) => {
      const r = p.port.getBoundingClientRect(); return { x: r.left, y: r.top, width: r.width, height: r.height }; }));
    assert.equal(ports.length, 4);
    const shot = async () => decodePNG(await page.screenshot());
    const before = await shot();
    const count = await page.evaluate(() => window.viewerState.view.renderCount);
    // Drag horizontally across the first panel only.
    const y = ports[0].y + ports[0].height / 2;
    await page.mouse.move(ports[0].x + ports[0].width * 0.3, y);
    await page.mouse.down();
    await page.mouse.move(ports[0].x + ports[0].width * 0.7, y, { steps: 8 });
    await page.mouse.up();
    await page.waitForFunction((c) => window.viewerState.view.renderCount > c, count, { timeout: 60000 });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    const after = await shot();
    for(const [i, box] of ports.entries()) {
      let changed = 0;
      for(let yy = Math.round(box.y); yy < box.y + box.height; ++yy)
        for(let xx = Math.round(box.x); xx < box.x + box.width; ++xx) {
          const k = 4 * (yy * before.width + xx);
          if(Math.abs(before.rgba[k] - after.rgba[k]) + Math.abs(before.rgba[k + 1] - after.rgba[k + 1]) > 30) ++changed;
        }
      assert.ok(changed > 0.02 * box.width * box.height, `panel ${i} did not turn (${changed} pixels changed)`);
    }
    // "Reset view" brings back the first picture.
    const renders = await page.evaluate(() => window.viewerState.view.renderCount);
    await page.click('#reset');
    await page.waitForFunction((c) => window.viewerState.view.renderCount > c, renders, { timeout: 60000 });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    const reset = await shot();
    let differing = 0;
    for(let k = 0; k < reset.rgba.length; k += 4) if(Math.abs(reset.rgba[k] - before.rgba[k]) > 30) ++differing;
    assert.ok(differing < 0.001 * reset.width * reset.height, `${differing} pixels differ after Reset view`);
    // Hovering a mesh shows the field at the nearest vertex; hovering the background shows nothing.
    await page.mouse.move(ports[1].x + ports[1].width / 2, ports[1].y + ports[1].height / 2);
    await page.waitForFunction(() => document.getElementById('probe').textContent !== '', null, { timeout: 60000 });
    assert.match(await page.locator('#probe').textContent(), /^vertex, vertex \d+: [-0-9.e]+$/);
    await page.mouse.move(ports[1].x + 2, ports[1].y + 2);
    await page.waitForFunction(() => document.getElementById('probe').textContent === '', null, { timeout: 60000 });
  } finally {
    await context.close();
    await server.close();
    fs.rmSync(userDataDir, { recursive: true, force: true });
  }
});

test.after(() => { if(!keep) fs.rmSync(root, { recursive: true, force: true }); });
