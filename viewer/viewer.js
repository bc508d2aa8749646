// The result-folder viewer: one panel per entry of task.json's "panels", one shared camera,
// vertex colours from the distortion field over ONE range shared by every panel, one colour bar.
//
// URL parameters: task=<folder> (default: the first task), colormap=viridis|heat,
// range=lo,hi (either may be empty: that end stays the shared min/max),
// figure=1 (fixed-size figure, no toolbar: what render.mjs captures) with w=<panel width> and
// h=<panel height> in CSS pixels (without h, the height follows the objects' shape).
// When the page is done, window.viewerState.status is 'rendered' (or 'error', with .error);
// .warnings lists the panels without a file (shown empty, marked "no result").
import { parsePLY } from './lib/ply.js';
import { COLORMAPS, sharedRange, fieldExtent, drawColorBar, formatValue } from './lib/colormap.js';
import { createFieldMesh } from './lib/mesh.js';
import { PanelView } from './lib/panels.js';
import * as THREE from 'three';

const DEFAULT_PANELS = ['rest', 'vertex', 'edge', 'cgal_arap'];
const PANEL_TITLES = {
  rest: 'Rest', vertex: 'Vertex-based', edge: 'Edge-based',
  cgal_arap: 'CGAL ARAP', cgal_spokes_and_rims: 'CGAL spokes and rims', cgal_sre_arap: 'CGAL SR-ARAP',
};

const state = window.viewerState = { status: 'loading', error: null, warnings: [], task: null, range: null, panels: [] };
const params = new URLSearchParams(location.search);
const figureMode = params.get('figure') === '1';
const $ = (id) => document.getElementById(id);

function fail(message) {
  state.status = 'error';
  state.error = message;
  $('message').textContent = message;
  document.body.dataset.status = 'error';
  console.error(message);
}

async function fetchOk(url, what) {
  const response = await fetch(url, { cache: 'no-store' });
  if(!response.ok) throw new Error(`${what}: HTTP ${response.status} ${response.statusText}`);
  return response;
}

/** The folder part of a URL under results/ ('.' is the result folder itself). */
function folderUrl(dir) {
  return dir === '.' ? 'results/' : 'results/' + dir.split('/').map(encodeURIComponent).join('/') + '/';
}

function positiveNumber(name, fallback) {
  const value = Number(params.get(name));
  return Number.isFinite(value) && value > 0 ? value : fallback;
}

async function main() {
  const tasks = await (await fetchOk('tasks.json', 'the task list')).json();
  if(tasks.length === 0) throw new Error('the result folder holds no task.json (neither at its top nor in a sub-folder)');
  const dir = params.get('task') || tasks[0].dir;
  const entry = tasks.find((t) => t.dir === dir);
  if(!entry) throw new Error(`no task folder '${dir}' (have: ${tasks.map((t) => t.dir).join(', ')})`);
  if(entry.error) throw new Error(`${dir}/task.json: ${entry.error}`);

  const base = folderUrl(dir);
  const task = await (await fetchOk(base + 'task.json', `${dir}/task.json`)).json();
  const panelNames = Array.isArray(task.panels) && task.panels.length > 0 ? task.panels : DEFAULT_PANELS;
  const fieldName = task.property || 'distortion';
  const colormap = params.get('colormap') || task.colormap || 'viridis';
  if(!COLORMAPS[colormap]) throw new Error(`unknown colour map '${colormap}' (known: ${Object.keys(COLORMAPS).join(', ')})`);
  state.task = task.task || dir;

  // Toolbar (interactive mode).
  const select = $('task');
  for(const t of tasks) select.add(new Option(t.title ? `${t.task} - ${t.title}` : t.task, t.dir, false, t.dir === dir));
  select.onchange = () => { params.set('task', select.value); location.search = params.toString(); };
  const cmapSelect = $('colormap');
  for(const name of Object.keys(COLORMAPS)) cmapSelect.add(new Option(name, name, false, name === colormap));
  cmapSelect.onchange = () => { params.set('colormap', cmapSelect.value); location.search = params.toString(); };

  // Meshes. A panel whose file does not exist (HTTP 404: e.g. that method failed) is shown empty,
  // marked "no result", and listed in state.warnings; any other problem fails the page.
  const loaded = await Promise.all(panelNames.map(async (name) => {
    const file = `${dir}/${name}.ply`;
    const response = await fetch(base + encodeURIComponent(name) + '.ply', { cache: 'no-store' });
    if(response.status === 404) return { name, file, missing: `${file}: HTTP 404 ${response.statusText}` };
    if(!response.ok) throw new Error(`${file}: HTTP ${response.status} ${response.statusText}`);
    const bytes = await response.arrayBuffer();
    let mesh;
    try { mesh = parsePLY(bytes); } catch(e) { throw new Error(`${file}: ${e.message}`); }
    const field = mesh.vertexProperties[fieldName];
    if(!field)
      throw new Error(`${file} has no vertex property '${fieldName}' (it has: ${Object.keys(mesh.vertexProperties).join(', ') || 'none'})`);
    if(mesh.indices.length === 0) throw new Error(`${file} has no faces`);
    return { name, file, ...mesh, field };
  }));
  state.warnings = loaded.filter((m) => m.missing).map((m) => m.missing);
  const meshes = loaded.filter((m) => !m.missing);
  if(meshes.length === 0) throw new Error(`no panel could be loaded: ${state.warnings.join('; ')}`);

  let range = null;
  if(params.has('range')) range = params.get('range').split(',').map((s) => (s.trim() === '' ? null : Number(s)));
  else if(Array.isArray(task.range)) range = task.range;
  const shared = sharedRange(meshes.map((m) => m.field), range);
  const data = sharedRange(meshes.map((m) => m.field));
  state.range = shared;
  state.panels = loaded.map((m) => {
    if(m.missing) return { name: m.name, missing: true };
    const own = fieldExtent(m.field) || { min: null, max: null };
    return { name: m.name, vertices: m.vertexCount, faces: m.indices.length / 3, min: own.min, max: own.max };
  });

  // Layout: fixed panel size in figure mode, the window otherwise.
  const w = positiveNumber('w', 400);
  if(figureMode) {
    document.body.classList.add('figure');
    $('figure').style.width = `${w * loaded.length}px`;
    $('panels').style.height = `${positiveNumber('h', w)}px`;
  }
  $('figure-title').textContent = task.title || task.task || dir;
  document.title = `${task.task || dir} - Laplacian_deformation viewer`;

  const letters = 'abcdefghijklmnopqrstuvwxyz';
  const titles = task.panel_titles || {};
  const view = new PanelView($('panels'), { interactive: !figureMode, preserveDrawingBuffer: figureMode });
  view.setPanels(loaded.map((m, i) => ({
    title: `(${letters[i % 26]}) ${titles[m.name] || PANEL_TITLES[m.name] || m.name}`,
    object: m.missing ? new THREE.Group()
                      : createFieldMesh(m, shared, colormap, { flatShading: Boolean(task.flat_shading) }),
  })));
  loaded.forEach((m, i) => {
    if(!m.missing) return;
    const note = document.createElement('div');
    note.className = 'panel-missing';
    note.textContent = `no result (${m.name}.ply not found)`;
    view.panels[i].port.append(note);
  });
  view.resize();
  const camera = task.camera || {};
  const fit = () => view.fitCamera({ direction: camera.direction || null, up: camera.up || null, margin: camera.margin || 1.06 });
  if(figureMode && !params.has('h')) {
    // Panel height from the objects' shape seen along the view (between w/3 and 2w), plus
    // captions; then shrunk to what the perspective view actually fills.
    const aspect = view.contentAspect({ direction: camera.direction || null, up: camera.up || null });
    const caption = view.panels[0].element.offsetHeight - view.panels[0].port.offsetHeight;
    let port = Math.min(2 * w, Math.max(w / 3, 1.08 * w / aspect));
    for(let pass = 0; pass < 2; ++pass) {
      $('panels').style.height = `${Math.round(port + caption)}px`;
      view.resize();
      fit();
      const { y } = view.projectedExtent();
      const used = (y[1] - y[0]) / 2 * 1.06;                  // the fraction of the height in use
      if(!(used > 0) || used > 0.97) break;
      port = Math.max(w / 3, port * used);
    }
  }
  fit();

  drawColorBar($('colorbar'), {
    min: shared.min, max: shared.max, colormap, label: (task.field || fieldName).replace(/_/g, ' '),
    clippedMax: shared.max < data.max, clippedMin: shared.min > data.min,
  });
  const counts = [...new Set(meshes.map((m) => m.vertexCount))];
  $('info').textContent = `${counts.join(' / ')} vertices - drag: turn, wheel: zoom, right drag: pan`;
  // Hovering shows the field at the vertex nearest to the pointer.
  let probe = null;
  view.canvas.addEventListener('pointermove', (event) => {
    if(event.buttons !== 0 || probe) return;
    probe = requestAnimationFrame(() => {
      probe = null;
      const hit = view.pick(event.clientX, event.clientY);
      if(!hit) { $('probe').textContent = ''; return; }
      const mesh = meshes.find((m) => m.name === loaded[hit.panel].name);
      $('probe').textContent = `${mesh.name}, vertex ${hit.vertex}: ${formatValue(mesh.field[hit.vertex])}`;
    });
  });
  $('reset').onclick = () => view.resetView();
  window.addEventListener('keydown', (e) => { if(e.key === 'r' || e.key === 'R') view.resetView(); });
  state.view = view;

  // Rendered: after the first render, once the frame has been presented.
  await new Promise((resolve) => {
    view.onRender(() => resolve());
    view.requestRender();
  });
  await new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)));
  state.status = 'rendered';
  document.body.dataset.status = 'rendered';
}

main().catch((e) => fail(e && e.message ? e.message : String(e)));
