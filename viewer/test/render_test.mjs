// Renders small generated figures in real Chromium (headless, SwiftShader) and checks the PNGs
// are not blank: every panel drew its mesh, the colours follow ONE shared range (the rest shape,
// all zeros, has none of the upper colours that the most distorted panel has), the colour bar runs
// from the first to the last colour of the map, and a broken task fails alone with a clear message.
//   usage: node viewer/test/render_test.mjs [--out DIR] [--chromium PATH]
//   (--out: keep the results and figures there; default: a temporary folder, removed)
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { renderFigures } from '../render.mjs';
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

  const scale = 1, width = 200;
  const results = await renderFigures(resultsDir, figuresDir, { width, scale, executablePath, log: (l) => console.log(l) });
  const byTask = Object.fromEntries(results.map((r) => [r.task, r]));
  assert.deepEqual(Object.keys(byTask).sort(), ['broken', 'bumpy_plane', 'two_panels']);

  // A missing panel file fails that task only, naming the file; no PNG is written for it.
  assert.equal(byTask.broken.ok, false);
  assert.match(byTask.broken.error, /broken\/vertex\.ply: HTTP 404/);
  assert.ok(!fs.existsSync(path.join(figuresDir, 'broken.png')));

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

test.after(() => { if(!keep) fs.rmSync(root, { recursive: true, force: true }); });
