// The interactive editor of `laplacian_deform --serve`: paint the region of interest and the
// handle, drag the handle (translate; Ctrl or Alt: rotate about the view axis) and watch the
// deformation computed by the C++ server (one Mesh_deformer per session, factored once per
// selection). Reuses the viewer's modules: PanelView (camera, orbit controls, picking) and
// createFieldMesh / movingRegion / setSomePositions (a selection costs what the selection costs:
// only its vertices go back to rest). The JSON API is described in the user manual. Every API call
// carries the server's per-run token (X-Editor-Token), taken from the address the tool printed
// (#token=... or ?token=...). A drag reply is a binary frame holding only the moving vertices'
// positions (float32, in the order of the selection reply's "moving"); at most one drag is in
// flight and only the latest pending one is sent; the tool bar shows the round trip (request to
// positions on the page) next to the server's times.
import * as THREE from 'three';
import { PanelView } from './lib/panels.js';
import { createFieldMesh, movingRegion, setSomePositions, vertexFaces, vertexNeighbours } from './lib/mesh.js';

const $ = (id) => document.getElementById(id);
const COLORS = [new THREE.Color(0xb8bcc4), new THREE.Color(0xe8c547), new THREE.Color(0xd7263d)];
const FIXED = 0, ROI = 1, HANDLE = 2;

const state = {
  session: null, mesh: null, n: 0, rest: null, faces: null, neighbours: null,
  status: null,            // per vertex: FIXED, ROI or HANDLE (as painted)
  selectionDirty: true,    // painted since the last POST /api/select
  mode: 'roi',
  transform: new THREE.Matrix4(),   // the handle's motion from rest (sent as rotation + translation)
  moving: new Int32Array(0),        // the vertices whose positions a drag reply holds, in its order
  region: null,                     // movingRegion(mesh, moving): the normals a drag changes
  seq: 0,                           // the number of the last drag sent (the server drops superseded ones)
  epoch: 0,                         // bumped by a new mesh or selection: older drag replies are ignored
  inFlight: false, pending: null, updates: 0, lastReply: null, lastRoundTrip: null, applied: [], busy: Promise.resolve(),
  starting: Promise.resolve(),      // the start of the last drag gesture (its selection's preprocess)
};

function message(text) { $('message').textContent = text || ''; }

const TOKEN = new URLSearchParams(location.hash.slice(1)).get('token') || new URLSearchParams(location.search).get('token') || '';
const HEADERS = { 'Content-Type': 'application/json', 'X-Editor-Token': TOKEN };

async function api(path, body) {
  const response = await fetch(path, { method: 'POST', headers: HEADERS, body: JSON.stringify(body) });
  const reply = await response.json();
  if(!response.ok) throw Object.assign(new Error(reply.error || `${path}: HTTP ${response.status}`), { status: response.status });
  return reply;
}

/** A POST whose reply is the binary frame (see the manual): {header, xyz: Float32Array, bytes}. */
async function apiFrame(path, body) {
  const response = await fetch(path, { method: 'POST', headers: HEADERS, body: JSON.stringify({ ...body, binary: true }) });
  if(!response.ok) {
    const reply = await response.json();
    throw Object.assign(new Error(reply.error || `${path}: HTTP ${response.status}`), { status: response.status, reply });
  }
  const buffer = await response.arrayBuffer();
  const n = new DataView(buffer).getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, n)));
  return { header, xyz: new Float32Array(buffer, 4 + n), bytes: buffer.byteLength };
}

/**
 * POST /api/session with "binary": its reply is the mesh frame (see the manual): the header, then
 * the rest positions (float64) and the triangles (uint32) as typed arrays over the reply's bytes.
 */
async function apiMesh(body) {
  const response = await fetch('/api/session', { method: 'POST', headers: HEADERS, body: JSON.stringify({ ...body, binary: true }) });
  if(!response.ok) {
    const reply = await response.json();
    throw Object.assign(new Error(reply.error || `/api/session: HTTP ${response.status}`), { status: response.status, reply });
  }
  const buffer = await response.arrayBuffer();
  const n = new DataView(buffer).getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, n)));
  const nv = header.vertex_count, nf = header.face_count, at = 4 + n;
  if(buffer.byteLength !== at + 24 * nv + 12 * nf) throw new Error(`/api/session: a mesh frame of ${buffer.byteLength} bytes for ${nv} vertices and ${nf} faces`);
  return { ...header, vertices: new Float64Array(buffer, at, 3 * nv), faces: new Uint32Array(buffer, at + 24 * nv, 3 * nf) };
}

// (lighterOnSoftware: without a GPU, no multisampling, and half the resolution during a drag or an orbit)
const view = new PanelView($('panels'), { background: '#ffffff', captionPosition: 'bottom', lighterOnSoftware: true });
// Left button edits; right button turns (shift: pans), middle and wheel zoom.
view.controls.mouseButtons = { LEFT: null, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.ROTATE };


/** The vertices within k rings of v. */
function kRing(v, k) {
  const seen = new Set([v]);
  let front = [v];
  for(let r = 0; r < k; ++r) {
    const next = [];
    for(const u of front) for(const w of state.neighbours[u]) if(!seen.has(w)) { seen.add(w); next.push(w); }
    front = next;
  }
  return [...seen];
}

function recolor() {
  const color = state.mesh.geometry.getAttribute('color');
  for(let v = 0; v < state.n; ++v) COLORS[state.status[v]].toArray(color.array, 3 * v);
  color.needsUpdate = true;
  let roi = 0, handles = 0;
  for(const s of state.status) { roi += s === ROI; handles += s === HANDLE; }
  $('counts').textContent = `${state.n} vertices, ROI ${roi}, handles ${handles}`;
  view.requestRender();
}

function updateDownloads() {
  for(const format of ['off', 'ply', 'sel', 'def'])
    $(`dl-${format}`).href = `/api/download?session=${state.session}&format=${format}&token=${encodeURIComponent(TOKEN)}`;
}

function closeSession(keepalive) {
  if(!state.session) return;
  fetch('/api/close', { method: 'POST', headers: HEADERS, body: JSON.stringify({ session: state.session }), keepalive })
    .catch(() => {});
  state.session = null;
}

async function openMesh(name) {
  const reply = await apiMesh({ mesh: name });
  closeSession(false);   // the previous mesh's session
  ++state.epoch;
  state.session = reply.session;
  state.moving = new Int32Array(0);
  state.region = null;
  state.n = reply.vertices.length / 3;
  state.rest = reply.vertices;
  state.faces = reply.faces;
  state.neighbours = vertexNeighbours(state.n, reply.faces);
  state.status = new Uint8Array(state.n);
  state.selectionDirty = true;
  state.transform.identity();
  state.updates = 0;
  state.lastReply = null;
  for(const key of ['representation', 'weights', 'transform', 'start']) $(key).value = reply.policy[key];
  state.mesh = createFieldMesh({ positions: reply.vertices, indices: reply.faces, field: new Float32Array(state.n) },
                               { min: 0, max: 1 });
  vertexFaces(state.mesh);   // built with the mesh, so that a selection's cost is the selection's
  view.setPanels([{ title: reply.mesh === 'default' ? 'default mesh' : reply.mesh, object: state.mesh }]);
  view.fitCamera();
  recolor();
  updateDownloads();
  $('timing').textContent = '';
  message('');
}

/**
 * Puts the vertices of the last selection back at rest: they are the only ones a drag moves, so
 * the cost is the selection's, not the mesh's (without a selection, nothing has moved).
 */
function restoreRest() {
  if(!state.region) return;
  const moving = state.region.moving, xyz = new Float64Array(3 * moving.length);
  moving.forEach((v, i) => { xyz[3 * i] = state.rest[3 * v]; xyz[3 * i + 1] = state.rest[3 * v + 1]; xyz[3 * i + 2] = state.rest[3 * v + 2]; });
  setSomePositions(state.mesh, state.region, xyz);
}

/** Puts the moving vertices at `xyz` (x, y, z per vertex of state.moving); the others stay. */
function setMovingPositions(xyz) {
  setSomePositions(state.mesh, state.region, xyz);
  view.requestRender();
}

function showTiming(reply, roundTrip) {
  const ms = (s) => (1000 * s).toFixed(1);
  $('timing').textContent = (roundTrip !== undefined ? `round trip ${roundTrip.toFixed(1)} ms, ` : '') +
    `update ${ms(reply.seconds)} ms (local ${ms(reply.local_step_seconds)}, rhs ` +
    `${ms(reply.right_hand_side_seconds)}, solve ${ms(reply.solve_seconds)}), ${reply.iterations} it, ` +
    `server ${ms(reply.handler_seconds)} ms, factorizations ${reply.factorizations}`;
  // the deformation succeeded, but the library flags results that may not be what was meant
  const warnings = reply.warnings || [];
  if(warnings.length) message('warning: ' + warnings.map((w) => w.message).join('; '));
}

/** Sends the painted selection (preprocess: one factorisation) if it changed. */
async function commitSelection() {
  if(!state.selectionDirty) return true;
  const roi = [], handles = [];
  state.status.forEach((s, v) => { if(s === ROI) roi.push(v); else if(s === HANDLE) handles.push(v); });
  if(handles.length === 0) { message('paint at least one handle vertex first (Handle mode)'); return false; }
  const reply = await api('/api/select', { session: state.session, roi, handles });
  ++state.epoch;
  restoreRest();
  state.moving = Int32Array.from(reply.moving);
  state.region = movingRegion(state.mesh, state.moving);
  state.selectionDirty = false;
  state.transform.identity();
  $('timing').textContent = `preprocess ${(1000 * reply.preprocess_seconds).toFixed(1)} ms, factorizations ${reply.factorizations}`;
  message('');
  return true;
}

/** The drag request for a transform: p -> R p + t (rotation about the origin). */
function dragBody(matrix) {
  const position = new THREE.Vector3(), quaternion = new THREE.Quaternion(), scale = new THREE.Vector3();
  matrix.decompose(position, quaternion, scale);
  const angle = 2 * Math.acos(Math.min(1, Math.abs(quaternion.w)));
  const sign = quaternion.w < 0 ? -1 : 1;
  const s = Math.sqrt(Math.max(0, 1 - quaternion.w * quaternion.w));
  const axis = s > 1e-12 ? [sign * quaternion.x / s, sign * quaternion.y / s, sign * quaternion.z / s] : [0, 0, 1];
  return { session: state.session, translation: position.toArray(), rotation: { axis, angle: s > 1e-12 ? angle : 0, center: [0, 0, 0] },
           iterations: Math.max(1, Math.min(100, Number($('iterations').value) || 4)) };
}

/** Sends one drag; applies its reply unless a newer mesh or selection came meanwhile. */
async function sendDrag(matrix) {
  const epoch = state.epoch, body = { ...dragBody(matrix), seq: ++state.seq };
  const t0 = performance.now();
  let frame;
  try { frame = await apiFrame('/api/drag', body); } catch(e) {
    if(e.status === 409 && e.reply && e.reply.superseded) return;   // a newer drag of this page is on its way
    throw e;
  }
  if(epoch !== state.epoch) return;
  setMovingPositions(frame.xyz);
  const roundTrip = performance.now() - t0;
  showTiming(frame.header, roundTrip);
  state.lastReply = frame.header;
  state.lastRoundTrip = { ms: roundTrip, bytes: frame.bytes, seq: frame.header.seq,
                          serverMs: 1000 * frame.header.handler_seconds, updateMs: 1000 * frame.header.seconds };
  state.applied.push(frame.header.seq);
  ++state.updates;
}

/** Queues a deformation for the current transform: at most one request is in flight; while it is,
 *  newer transforms replace each other and only the latest is sent next. */
function requestDrag() {
  state.pending = state.transform.clone();
  if(state.inFlight) return state.busy;
  state.busy = (async () => {
    state.inFlight = true;
    try {
      while(state.pending) {
        const matrix = state.pending;
        state.pending = null;
        await sendDrag(matrix);
      }
    } catch(e) { message(e.message); } finally { state.inFlight = false; }
  })();
  return state.busy;
}

function handleCentroid() {
  const c = new THREE.Vector3(), p = new THREE.Vector3();
  let count = 0;
  state.status.forEach((s, v) => { if(s === HANDLE) { c.add(p.fromArray(state.rest, 3 * v)); ++count; } });
  return count ? c.divideScalar(count).applyMatrix4(state.transform) : null;
}

function paint(event) {
  const hit = view.pick(event.clientX, event.clientY);
  if(!hit) return;
  const k = Number($('brush').value);
  const value = state.mode === 'roi' ? ROI : state.mode === 'handle' ? HANDLE : FIXED;
  let changed = false;
  for(const v of kRing(hit.vertex, k))
    if(state.status[v] !== value && !(value === ROI && state.status[v] === HANDLE)) { state.status[v] = value; changed = true; }
  if(changed) {
    state.selectionDirty = true;
    if(!state.transform.equals(new THREE.Matrix4())) {   // a new selection starts from rest
      state.transform.identity();
      restoreRest();
    }
    recolor();
  }
}

// ---- mouse
let gesture = null;
const canvas = view.canvas;
function rayPlane(event, point, normal) {
  const rect = canvas.getBoundingClientRect();
  const ndc = new THREE.Vector2(2 * (event.clientX - rect.left) / rect.width - 1, 1 - 2 * (event.clientY - rect.top) / rect.height);
  const raycaster = new THREE.Raycaster();
  raycaster.setFromCamera(ndc, view.camera);
  return raycaster.ray.intersectPlane(new THREE.Plane().setFromNormalAndCoplanarPoint(normal, point), new THREE.Vector3());
}

/** The handle's transform for a pointer position during a translate or rotate gesture. */
function gestureTransform(g, event) {
  if(g.kind === 'translate') {
    const p = rayPlane(event, g.center, g.normal);
    if(!p) return null;
    const d = p.sub(g.start);
    return new THREE.Matrix4().makeTranslation(d.x, d.y, d.z).multiply(g.base);
  }
  const angle = (event.clientX - g.x) * 0.01;
  const c = g.center;
  return new THREE.Matrix4().makeTranslation(c.x, c.y, c.z)
    .multiply(new THREE.Matrix4().makeRotationAxis(g.normal.clone().negate(), angle))
    .multiply(new THREE.Matrix4().makeTranslation(-c.x, -c.y, -c.z)).multiply(g.base);
}

// A drag that starts on a changed selection waits for its preprocess (POST /api/select). The
// pointer may move, and even be released, meanwhile: the waiting gesture keeps the last position
// and the release, and once the selection is ready the handle goes to that last position (and the
// gesture ends there if the button was already up), so no motion of the user is lost.
canvas.addEventListener('pointerdown', (event) => {
  if(event.button !== 0 || !state.mesh) return;
  canvas.setPointerCapture(event.pointerId);
  if(state.mode !== 'drag') { gesture = { kind: 'paint' }; paint(event); return; }
  const waiting = { kind: 'wait', last: null, released: false };
  gesture = waiting;
  // the lighter frames of software WebGL (setInteracting) start with the drag, once the selection
  // is ready: switching at the press drew a frame on the CPU while the server prepared the selection
  const abandon = () => { if(gesture === waiting) { gesture = null; view.setInteracting(false); } };
  state.starting = (async () => {
    try { if(!(await commitSelection())) { abandon(); return; } } catch(e) {
      message(e.message);
      abandon();
      return;
    }
    if(gesture !== waiting) return;   // another gesture replaced this one
    const center = handleCentroid();
    const normal = view.camera.getWorldDirection(new THREE.Vector3());
    const start = rayPlane(event, center, normal);
    if(!start) { abandon(); return; }
    const g = { kind: event.ctrlKey || event.altKey ? 'rotate' : 'translate', center, normal, start,
                x: event.clientX, base: state.transform.clone() };
    gesture = waiting.released ? null : g;   // null: released while the selection was being prepared
    if(gesture) view.setInteracting(true);     // until the gesture ends (see endGesture)
    const transform = waiting.last && gestureTransform(g, waiting.last);
    if(transform) { state.transform = transform; requestDrag(); }
  })();
});
canvas.addEventListener('pointermove', (event) => {
  if(!gesture) return;
  if(gesture.kind === 'paint') { paint(event); return; }
  if(gesture.kind === 'wait') { gesture.last = { clientX: event.clientX, clientY: event.clientY }; return; }
  const transform = gestureTransform(gesture, event);
  if(!transform) return;
  state.transform = transform;
  requestDrag();
});
const endGesture = (event) => {
  if(gesture && canvas.hasPointerCapture(event.pointerId)) canvas.releasePointerCapture(event.pointerId);
  if(gesture && gesture.kind === 'wait') { gesture.released = true; return; }   // ends once the selection is ready
  gesture = null;
  view.setInteracting(false);   // the next frame at the full resolution
};
canvas.addEventListener('pointerup', endGesture);
canvas.addEventListener('pointercancel', endGesture);

// ---- tool bar
function setMode(mode) {
  state.mode = mode;
  for(const b of document.querySelectorAll('.mode')) b.classList.toggle('active', b.dataset.mode === mode);
}
for(const b of document.querySelectorAll('.mode')) b.addEventListener('click', () => setMode(b.dataset.mode));
window.addEventListener('keydown', (e) => {
  const modes = { 1: 'roi', 2: 'handle', 3: 'erase', 4: 'drag' };
  if(modes[e.key] && e.target.tagName !== 'INPUT') setMode(modes[e.key]);
});
$('brush').addEventListener('input', () => { $('brush-value').textContent = $('brush').value; });
$('view').addEventListener('click', () => view.resetView());
$('reset').addEventListener('click', async () => {
  try {
    state.transform.identity();
    if(state.selectionDirty) { restoreRest(); view.requestRender(); return; }
    await api('/api/reset', { session: state.session });
    restoreRest();
    view.requestRender();
    $('timing').textContent = '';
  } catch(e) { message(e.message); }
});
$('clear').addEventListener('click', async () => {
  try {
    state.status.fill(FIXED);
    state.selectionDirty = true;
    state.transform.identity();
    await api('/api/reset', { session: state.session, selection: true });
    ++state.epoch;
    restoreRest();
    state.moving = new Int32Array(0);
    state.region = null;
    recolor();
  } catch(e) { message(e.message); }
});
async function changePolicy() {
  try {
    const body = { session: state.session };
    for(const key of ['representation', 'weights', 'transform', 'start']) body[key] = $(key).value;
    const epoch = state.epoch, t0 = performance.now();
    const { header: reply, xyz } = await apiFrame('/api/policy', body);
    // a selection painted since the last drag is sent at the next drag: until then the mesh stays at rest
    if(reply.seconds !== undefined && !state.selectionDirty && epoch === state.epoch) {
      setMovingPositions(xyz); showTiming(reply, performance.now() - t0); ++state.updates; state.lastReply = reply;
    }
    message('');
  } catch(e) { message(e.message); }
}
for(const key of ['representation', 'weights', 'transform', 'start']) $(key).addEventListener('change', changePolicy);
$('mesh').addEventListener('change', () => openMesh($('mesh').value).catch((e) => message(e.message)));

// ---- hooks for scripts and tests (they drive the same functions as the mouse)
window.editor = {
  state,
  /** Client coordinates of vertex v as drawn now. */
  screenOf(v) {
    const rect = canvas.getBoundingClientRect();
    const p = new THREE.Vector3().fromBufferAttribute(state.mesh.geometry.getAttribute('position'), v).project(view.camera);
    return { x: rect.left + (p.x + 1) / 2 * rect.width, y: rect.top + (1 - p.y) / 2 * rect.height };
  },
  /** The vertex under client coordinates (or null). */
  vertexAt(x, y) { const hit = view.pick(x, y); return hit ? hit.vertex : null; },
  /** 'cpu' (software WebGL: lighter frames, see PanelView) or 'gpu', and the resolution drawn now (1: full). */
  renderer() { return view.software ? 'cpu' : 'gpu'; },
  renderScale() { return view.renderer.getPixelRatio() / view.pixelRatio; },
  antialias() { return view.renderer.getContext().getContextAttributes().antialias; },
  /** Current positions (as drawn). */
  positions() { return Array.from(state.mesh.geometry.getAttribute('position').array); },
  /** Largest distance between a handle vertex as drawn and its target (transform applied to its rest position). */
  handleError() {
    let error = 0;
    const drawn = state.mesh.geometry.getAttribute('position');
    state.status.forEach((s, v) => {
      if(s !== HANDLE) return;
      const target = new THREE.Vector3().fromArray(state.rest, 3 * v).applyMatrix4(state.transform);
      error = Math.max(error, target.distanceTo(new THREE.Vector3().fromBufferAttribute(drawn, v)));
    });
    return error;
  },
  /** Resolves once the last gesture has started and no drag is in flight or pending. */
  async idle() { await state.starting; await state.busy; },
  /** Queues a drag for `elements` (a column-major 4x4 matrix, as THREE.Matrix4.elements), as a pointer move does. */
  drag(elements) { state.transform = new THREE.Matrix4().fromArray(elements); return requestDrag(); },
  commitSelection,
  setMode, openMesh, token: TOKEN,
  ready: false,
};

(async () => {
  try {
    if(!TOKEN) throw new Error('no token in the address: open the address laplacian_deform --serve printed (it ends with #token=...)');
    setMode('roi');
    const meshes = (async () => {   // the list and the default mesh at once
      const response = await fetch('/api/meshes', { headers: { 'X-Editor-Token': TOKEN } });
      const list = await response.json();
      if(!response.ok) throw new Error(list.error || `HTTP ${response.status}`);
      for(const name of list.meshes) $('mesh').append(new Option(name, name));
    })();
    await Promise.all([meshes, openMesh('default')]);
    window.editor.ready = true;
    // leaving the page closes its session (the server keeps a bounded number); back to it from the
    // browser's cache, it starts again
    window.addEventListener('pagehide', () => closeSession(true));
    window.addEventListener('pageshow', (e) => { if(e.persisted) location.reload(); });
  } catch(e) { message(`cannot start: ${e.message}`); }
})();
