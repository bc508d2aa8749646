#!/usr/bin/env node
// Renders every task of a result folder to OUT_DIR/<task>.png, headless: the viewer page in
// Debian's chromium (SwiftShader WebGL), driven by playwright-core, served from 127.0.0.1.
//
//   usage: node viewer/render.mjs RESULTS_DIR OUT_DIR [--task DIR]... [--width PX] [--height PX]
//                                 [--scale F] [--colormap NAME] [--chromium PATH] [--timeout S]
// --width/--height: size of one panel in CSS pixels (default width 400, height from the objects'
// shape, between a third of the width and twice the width); --scale: device pixel
// ratio (default 1; 2 gives print resolution). Exit status 1 when a task could not be rendered
// (the others are still rendered), 2 for bad arguments or a missing set-up (chromium, npm ci).
import fs from 'node:fs';
import fsp from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { startServer, listTasks } from './serve.mjs';

export const CHROMIUM_ARGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync', '--enable-unsafe-swiftshader'];

/** A file name for a task folder ('.' is the result folder itself: the task's name). */
function pngName(task) {
  const base = task.dir === '.' ? task.task : task.dir;
  return base.replace(/[^A-Za-z0-9._-]+/g, '_') + '.png';
}

/**
 * Renders the tasks of `resultsDir` into `outDir`. Resolves to [{ task, png, ok, error, warnings,
 * range, panels, layout }]: warnings lists the panels without a file (drawn empty, marked "no
 * result"); range is the shared { min, max }; panels gives per panel its name, vertices, faces,
 * min, max (or missing); layout has the figure, ports and colorbar boxes in CSS pixels (times
 * `scale` in the PNG).
 * Options: tasks (folder names; default all), width, height (panel size), scale, colormap,
 * executablePath (default /usr/bin/chromium), timeoutMs (per task), log (a function).
 */
export async function renderFigures(resultsDir, outDir, { tasks: only = null, width = 400, height = null, scale = 1,
  colormap = null, executablePath = '/usr/bin/chromium', timeoutMs = 120000, log = () => {} } = {}) {
  let chromium;
  try { ({ chromium } = await import('playwright-core')); } catch(e) {
    throw new Error(`playwright-core is not installed: run 'npm ci' in ${path.dirname(fileURLToPath(import.meta.url))} (${e.message})`);
  }
  if(!fs.existsSync(executablePath)) throw new Error(`no chromium at ${executablePath} (scripts/setup.sh installs Debian's)`);
  let tasks = await listTasks(path.resolve(resultsDir));
  if(only) {
    const unknown = only.filter((dir) => !tasks.some((t) => t.dir === dir));
    if(unknown.length) throw new Error(`no task folder ${unknown.join(', ')} in ${resultsDir}`);
    tasks = tasks.filter((t) => only.includes(t.dir));
  }
  if(tasks.length === 0) throw new Error(`no task.json in ${resultsDir} (neither at its top nor in a sub-folder)`);
  await fsp.mkdir(outDir, { recursive: true });

  const server = await startServer(resultsDir);
  const userDataDir = await fsp.mkdtemp(path.join(os.tmpdir(), 'laplacian-viewer-chromium-'));
  const results = [];
  let context = null;
  try {
    // A persistent context is playwright's way to pass a (new, empty) --user-data-dir.
    context = await chromium.launchPersistentContext(userDataDir, {
      executablePath, headless: true, args: CHROMIUM_ARGS, deviceScaleFactor: scale,
      viewport: { width: 1280, height: 800 },
    });
    for(const task of tasks) {
      const png = path.join(outDir, pngName(task));
      const result = { task: task.dir, png, ok: false, error: null, warnings: [], range: null };
      results.push(result);
      if(task.error) { result.error = task.error; log(`${task.dir}: ${task.error}`); continue; }
      const panels = task.panels && task.panels.length ? task.panels.length : 4;
      const page = await context.newPage();
      const problems = [];
      page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
      page.on('console', (m) => { if(m.type() === 'error') problems.push(`console: ${m.text()}`); });
      try {
        await page.setViewportSize({ width: Math.ceil(panels * width) + 40, height: Math.ceil(height || 2 * width) + 200 });
        const query = new URLSearchParams({ figure: '1', task: task.dir, w: String(width) });
        if(height) query.set('h', String(height));
        if(colormap) query.set('colormap', colormap);
        await page.goto(`${server.url}?${query}`, { timeout: timeoutMs });
        // The page says when it is done (no sleeping).
        await page.waitForFunction(() => window.viewerState && window.viewerState.status !== 'loading', null,
                                   { timeout: timeoutMs, polling: 50 });
        const state = await page.evaluate(() => {
          // Where things are in the figure (CSS pixels from its top left corner).
          const origin = document.getElementById('figure').getBoundingClientRect();
          const box = (e) => { const r = e.getBoundingClientRect();
                               return { x: r.left - origin.left, y: r.top - origin.top, width: r.width, height: r.height }; };
          const s = window.viewerState;
          return { status: s.status, error: s.error, warnings: s.warnings, range: s.range, panels: s.panels,
                   layout: s.status === 'rendered' ? { figure: box(document.getElementById('figure')),
                     ports: s.view.panels.map((p) => box(p.port)), colorbar: box(document.getElementById('colorbar')) } : null };
        });
        if(state.status !== 'rendered') throw new Error(state.error || 'the page did not render');
        await page.locator('#figure').screenshot({ path: png, timeout: timeoutMs });
        result.ok = true;
        result.warnings = state.warnings;
        for(const w of state.warnings) log(`${task.dir}: warning: ${w} (panel left empty)`);
        result.range = state.range;
        result.panels = state.panels;
        result.layout = state.layout;
        log(`${task.dir}: ${png} (shared range ${state.range.min} .. ${state.range.max})`);
      } catch(e) {
        result.error = [e.message.split('\n')[0], ...problems].join('; ');
        log(`${task.dir}: FAILED: ${result.error}`);
      } finally {
        await page.close();
      }
    }
  } finally {
    if(context) await context.close();
    await server.close();
    await fsp.rm(userDataDir, { recursive: true, force: true });
  }
  return results;
}

function usage() {
  return 'usage: node viewer/render.mjs RESULTS_DIR OUT_DIR [--task DIR]... [--width PX] [--height PX] ' +
         '[--scale F] [--colormap viridis|heat] [--chromium PATH] [--timeout SECONDS]';
}

async function main(argv) {
  const args = argv.slice(2);
  const positional = [], options = { tasks: null, log: (line) => console.log(line) };
  const number = (name, value) => {
    const v = Number(value);
    if(!Number.isFinite(v) || v <= 0) throw Object.assign(new Error(`${name}: '${value}' is not a positive number`), { usage: true });
    return v;
  };
  for(let i = 0; i < args.length; ++i) {
    const a = args[i];
    if(a === '--help' || a === '-h') { console.log(usage()); return 0; }
    if(a.startsWith('--') && i + 1 >= args.length) throw Object.assign(new Error(`${a} needs a value`), { usage: true });
    if(a === '--task') (options.tasks ||= []).push(args[++i]);
    else if(a === '--width') options.width = number(a, args[++i]);
    else if(a === '--height') options.height = number(a, args[++i]);
    else if(a === '--scale') options.scale = number(a, args[++i]);
    else if(a === '--colormap') options.colormap = args[++i];
    else if(a === '--chromium') options.executablePath = args[++i];
    else if(a === '--timeout') options.timeoutMs = 1000 * number(a, args[++i]);
    else if(a.startsWith('--')) throw Object.assign(new Error(`unknown option ${a}`), { usage: true });
    else positional.push(a);
  }
  if(positional.length !== 2) throw Object.assign(new Error('expected RESULTS_DIR and OUT_DIR'), { usage: true });
  const [resultsDir, outDir] = positional;
  if(path.resolve(resultsDir) === path.resolve(outDir))
    console.log('note: the figures go into the result folder itself');
  const results = await renderFigures(resultsDir, outDir, options);
  const failed = results.filter((r) => !r.ok);
  console.log(`${results.length - failed.length} of ${results.length} figure(s) written to ${path.resolve(outDir)}`);
  return failed.length ? 1 : 0;
}

if(process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url))
  main(process.argv).then((code) => process.exit(code)).catch((e) => {
    console.error(`render.mjs: ${e.message}`);
    if(e.usage) console.error(usage());
    process.exit(2);
  });
