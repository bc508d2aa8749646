// Viewer tests without a browser: PLY reading/writing, colour maps and ranges, mesh colouring,
// the static server (what it serves, and that it serves nothing outside its folders), and the
// command lines' argument errors.   usage: node viewer/test/unit.mjs
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import http from 'node:http';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { parsePLY, writePLY, PlyError } from '../lib/ply.js';
import { sampleColormap, sharedRange, fieldExtent, niceTicks, formatValue, fieldColors, COLORMAPS } from '../lib/colormap.js';
import { createFieldMesh, setFieldColors, setPositions, defaultView, movingRegion, setSomePositions, vertexFaces, vertexNeighbours } from '../lib/mesh.js';
import { startServer, resolveInside, listTasks } from '../serve.mjs';
import { writeSampleTask, edgeLengthDistortion, bumpyPlane } from '../tools/make_sample.mjs';
import * as THREE from 'three';

const viewerDir = path.dirname(path.dirname(fileURLToPath(import.meta.url)));
const square = { positions: [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], indices: [0, 1, 2, 0, 2, 3],
                 vertexProperties: { distortion: [0, 0.25, 0.5, 1] } };

test('PLY: binary and ascii round trips keep positions, triangles and the float property', () => {
  for(const format of ['binary_little_endian', 'ascii']) {
    const mesh = parsePLY(writePLY(square, { format }));
    assert.deepEqual(Array.from(mesh.positions), square.positions, format);
    assert.deepEqual(Array.from(mesh.indices), square.indices, format);
    assert.deepEqual(Array.from(mesh.vertexProperties.distortion), [0, 0.25, 0.5, 1], format);
    assert.equal(mesh.vertexCount, 4);
    assert.equal(mesh.faceCount, 2);
  }
});

test('PLY: big endian, quads fan-triangulated, other elements and properties skipped', () => {
  const header = 'ply\nformat binary_big_endian 1.0\ncomment made by hand\nelement vertex 4\n' +
    'property double x\nproperty double y\nproperty double z\nproperty uchar red\nproperty float distortion\n' +
    'element face 1\nproperty list uchar uint vertex_indices\nproperty int flags\n' +
    'element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n';
  const body = Buffer.alloc(4 * (3 * 8 + 1 + 4) + (1 + 4 * 4 + 4) + 8);
  let pos = 0;
  square.positions.forEach((v, i) => {
    pos = body.writeDoubleBE(v, pos);
    if(i % 3 === 2) { pos = body.writeUInt8(200, pos); pos = body.writeFloatBE(square.vertexProperties.distortion[(i - 2) / 3], pos); }
  });
  pos = body.writeUInt8(4, pos);
  for(const v of [0, 1, 2, 3]) pos = body.writeUInt32BE(v, pos);
  pos = body.writeInt32BE(7, pos);
  pos = body.writeInt32BE(0, pos); pos = body.writeInt32BE(1, pos);
  const mesh = parsePLY(Buffer.concat([Buffer.from(header, 'latin1'), body]));
  assert.deepEqual(Array.from(mesh.indices), [0, 1, 2, 0, 2, 3]);
  assert.deepEqual(Array.from(mesh.vertexProperties.red), [200, 200, 200, 200]);
  assert.deepEqual(Array.from(mesh.vertexProperties.distortion), [0, 0.25, 0.5, 1]);
  assert.deepEqual(Array.from(mesh.positions), square.positions);
});

test('PLY: bad files are refused with a message naming the problem', () => {
  const good = Buffer.from(writePLY(square));
  const cases = [
    [Buffer.from('OFF\n3 1 0\n'), /missing "ply" magic/],
    [Buffer.from('ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n'), /missing "end_header"/],
    [good.subarray(0, good.length - 5), /file ends before/],
    [Buffer.from('ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n0 0\n1 0\n0 1\n'), /no 'z' property/],
    [Buffer.from('ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n' +
                 'element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n'), /face 0 refers to vertex 3 of 3/],
    [Buffer.from('ply\nformat binary_middle_endian 1.0\nend_header\n'), /unsupported format/],
    [Buffer.from('ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n'), /unknown scalar type 'quad'/],
    [Buffer.from('ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 zero 0\n'), /'zero' is not a number/],
  ];
  for(const [bytes, message] of cases) assert.throws(() => parsePLY(bytes), (e) => e instanceof PlyError && message.test(e.message));
  assert.throws(() => writePLY({ ...square, vertexProperties: { distortion: [1] } }), /1 values for 4 vertices/);
});

test('colour maps: ends, clamping, NaN; shared range; ticks', () => {
  for(const name of Object.keys(COLORMAPS)) {
    const first = COLORMAPS[name][0], last = COLORMAPS[name][COLORMAPS[name].length - 1];
    const hex = (c) => '#' + c.map((v) => Math.round(v * 255).toString(16).padStart(2, '0')).join('');
    assert.equal(hex(sampleColormap(name, 0)), first);
    assert.equal(hex(sampleColormap(name, 1)), last);
    assert.equal(hex(sampleColormap(name, -3)), first);
    assert.equal(hex(sampleColormap(name, 7)), last);
  }
  assert.deepEqual(sampleColormap('viridis', NaN), [0.5, 0.5, 0.5]);
  assert.throws(() => sampleColormap('jet', 0.5), /unknown colour map 'jet'/);
  assert.deepEqual(sharedRange([[0, 0], [0.5, NaN, 2], [Infinity, 1]]), { min: 0, max: 2 });
  assert.deepEqual(sharedRange([[3, 3]]), { min: 3, max: 4 });
  assert.deepEqual(fieldExtent([NaN, 2, -1]), { min: -1, max: 2 });
  assert.equal(fieldExtent([NaN]), null);
  assert.deepEqual(sharedRange([[0, 5]], [null, 2]), { min: 0, max: 2 });
  assert.deepEqual(niceTicks(0, 0.691, 5), [0, 0.2, 0.4, 0.6]);
  assert.deepEqual(niceTicks(-1, 1, 5), [-1, -0.5, 0, 0.5, 1]);
  assert.equal(formatValue(0.6907), '0.691');
  assert.equal(formatValue(123456), '1.2e5');
  const colors = fieldColors([0, 2], { min: 0, max: 2 }, 'viridis');
  assert.deepEqual(Array.from(colors.slice(3)).map((v) => Math.round(v * 255)), [0xfd, 0xe7, 0x25]);
});

test('meshes: one colour per vertex from the shared range, linear light; checks on sizes', () => {
  const mesh = createFieldMesh({ positions: square.positions, indices: square.indices, field: [0, 0, 0, 2] },
                               { min: 0, max: 4 }, 'viridis');
  const colors = mesh.geometry.getAttribute('color');
  const mid = new THREE.Color().setRGB(...sampleColormap('viridis', 0.5), THREE.SRGBColorSpace);
  assert.ok(Math.abs(colors.getX(3) - mid.r) < 1e-6 && Math.abs(colors.getY(3) - mid.g) < 1e-6);
  assert.equal(mesh.geometry.index.count, 6);
  assert.throws(() => setFieldColors(mesh, [1, 2], { min: 0, max: 1 }), /2 values for 4 vertices/);
  assert.throws(() => setPositions(mesh, [0, 0, 0]), /1 positions for 4 vertices/);
  setPositions(mesh, square.positions.map((v, i) => (i % 3 === 2 ? 1 : v)));
  assert.equal(mesh.geometry.boundingBox.min.z, 1);
  // A plate is seen obliquely with its thin axis up; a tall box with its long axis up.
  const plate = defaultView(new THREE.Box3(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 0.1)));
  assert.deepEqual(plate.up.toArray(), [0, 0, 1]);
  assert.ok(plate.direction.z > 0.3 && plate.direction.z < 0.9);
  const tall = defaultView(new THREE.Box3(new THREE.Vector3(0, 0, 0), new THREE.Vector3(1, 3, 0.6)));
  assert.deepEqual(tall.up.toArray(), [0, 1, 0]);
  assert.ok(tall.direction.z > 0.8);
});

test('meshes: moving some vertices updates their normals as recomputing all of them does', () => {
  const plane = bumpyPlane(9);   // 9 x 9 vertices
  const a = createFieldMesh({ ...plane, field: new Float32Array(81) }, { min: 0, max: 1 });
  const b = createFieldMesh({ ...plane, field: new Float32Array(81) }, { min: 0, max: 1 });
  const moving = [40, 41, 31, 49];   // around the middle
  const region = movingRegion(a, moving);
  assert.ok(region.vertices.length > moving.length && region.vertices.length < 81, `${region.vertices.length} normals change`);
  const xyz = moving.flatMap((v, i) => [plane.positions[3 * v] + 0.01 * i, plane.positions[3 * v + 1], plane.positions[3 * v + 2] + 0.3]);
  setSomePositions(a, region, xyz);
  const all = Array.from(plane.positions);
  moving.forEach((v, i) => { for(let k = 0; k < 3; ++k) all[3 * v + k] = xyz[3 * i + k]; });
  setPositions(b, all);
  const na = a.geometry.getAttribute('normal').array, nb = b.geometry.getAttribute('normal').array;
  let worst = 0;
  for(let i = 0; i < na.length; ++i) worst = Math.max(worst, Math.abs(na[i] - nb[i]));
  assert.ok(worst < 1e-6, `normals differ by ${worst}`);
  assert.deepEqual(Array.from(a.geometry.getAttribute('position').array), Array.from(b.geometry.getAttribute('position').array));
  assert.ok(a.geometry.getAttribute('normal').array.some((x, i) => Math.abs(x - createFieldMesh({ ...plane, field: new Float32Array(81) },
    { min: 0, max: 1 }).geometry.getAttribute('normal').array[i]) > 1e-3), 'the normals did change');
  assert.throws(() => setSomePositions(a, region, [0, 0, 0]), /1 positions for 4 moving vertices/);
  // the bounding sphere holds every vertex after moves far out, and back
  const far = moving.flatMap((v, i) => [plane.positions[3 * v] + 5 * i, plane.positions[3 * v + 1] - 3, plane.positions[3 * v + 2] + 7]);
  for(const xyzs of [far, xyz]) {
    setSomePositions(a, region, xyzs);
    const sphere = a.geometry.boundingSphere, p = a.geometry.getAttribute('position').array;
    for(let v = 0; v < 81; ++v)
      assert.ok(sphere.center.distanceTo(new THREE.Vector3(p[3 * v], p[3 * v + 1], p[3 * v + 2])) <= sphere.radius * (1 + 1e-6),
                `vertex ${v} outside the bounding sphere`);
  }
});

test('meshes: the moving region is that of a scan of every face, from a table built once per mesh', () => {
  const plane = bumpyPlane(9);
  const a = createFieldMesh({ ...plane, field: new Float32Array(81) }, { min: 0, max: 1 });
  const index = Array.from(a.geometry.index.array), faceCount = index.length / 3;
  for(const moving of [[40], [40, 41, 31, 49], [0, 80, 8], [72, 73, 74, 75]]) {
    // brute force: the vertices of the faces around a moving vertex, and the faces around those
    const near = new Set();
    for(let f = 0; f < faceCount; ++f)
      if(moving.some((v) => index.slice(3 * f, 3 * f + 3).includes(v))) index.slice(3 * f, 3 * f + 3).forEach((w) => near.add(w));
    const faces = [];
    for(let f = 0; f < faceCount; ++f) if(index.slice(3 * f, 3 * f + 3).some((w) => near.has(w))) faces.push(f);
    const region = movingRegion(a, moving);
    assert.deepEqual(Array.from(region.vertices), [...near].sort((x, y) => x - y), `vertices around ${moving}`);
    assert.deepEqual(Array.from(region.faces), faces, `faces around ${moving}`);
    assert.deepEqual(Array.from(region.moving), moving);
    for(let v = 0; v < 81; ++v) assert.equal(region.affected[v], near.has(v) ? 1 : 0);
  }
  assert.equal(vertexFaces(a), vertexFaces(a), 'the table is built once per mesh');
  const { start, faces } = vertexFaces(a);
  for(let v = 0; v < 81; ++v)
    for(let k = start[v]; k < start[v + 1]; ++k) assert.ok(index.slice(3 * faces[k], 3 * faces[k] + 3).includes(v));
  assert.equal(start[81], index.length);
});

test('meshes: the neighbours of every vertex, each once and sorted, as sets of the edges would give them', () => {
  const plane = bumpyPlane(9);
  const tetra = [0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2];
  for(const [n, faces] of [[81, plane.indices], [81, Uint32Array.from(plane.indices)], [4, tetra], [6, [...tetra, 4, 1, 2]]]) {
    const sets = Array.from({ length: n }, () => new Set());
    for(let f = 0; f < faces.length; f += 3)
      for(let k = 0; k < 3; ++k) { const a = faces[f + k], b = faces[f + (k + 1) % 3]; sets[a].add(b); sets[b].add(a); }
    const lists = vertexNeighbours(n, faces);
    assert.equal(lists.length, n);
    for(let v = 0; v < n; ++v)
      assert.deepEqual(Array.from(lists[v]), [...sets[v]].sort((x, y) => x - y), `neighbours of ${v}`);
  }
  assert.equal(vertexNeighbours(6, [0, 1, 2])[5].length, 0, 'an isolated vertex has none');
});

test('sample results: the distortion is 0 at rest and grows with the lift', () => {
  const plane = bumpyPlane(5);
  assert.equal(plane.positions.length, 75);
  assert.equal(plane.indices.length, 96);
  assert.ok(edgeLengthDistortion(plane.positions, plane.positions, plane.indices).every((v) => v === 0));
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'viewer-unit-'));
  try {
    writeSampleTask(dir, { n: 6 });
    const task = JSON.parse(fs.readFileSync(path.join(dir, 'bumpy_plane', 'task.json'), 'utf8'));
    assert.deepEqual(task.panels, ['rest', 'vertex', 'edge', 'cgal_arap']);
    const rest = parsePLY(fs.readFileSync(path.join(dir, 'bumpy_plane', 'rest.ply')));
    const vertex = parsePLY(fs.readFileSync(path.join(dir, 'bumpy_plane', 'vertex.ply')));
    assert.ok(rest.vertexProperties.distortion.every((v) => v === 0));
    assert.ok(Math.max(...vertex.vertexProperties.distortion) > 0.1);
  } finally { fs.rmSync(dir, { recursive: true, force: true }); }
});

/** A GET (or other method) with the raw path, as sent: no client-side normalisation. */
function request(url, rawPath, method = 'GET') {
  const { hostname, port } = new URL(url);
  return new Promise((resolve, reject) => {
    const req = http.request({ hostname, port, path: rawPath, method }, (res) => {
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => resolve({ status: res.statusCode, type: res.headers['content-type'], body: Buffer.concat(chunks) }));
    });
    req.on('error', reject);
    req.end();
  });
}

test('server: serves the page, three.js, the tasks and the results; nothing outside them', async () => {
  const sandbox = fs.mkdtempSync(path.join(os.tmpdir(), 'viewer-serve-'));
  const results = path.join(sandbox, 'results');
  fs.mkdirSync(results);
  fs.writeFileSync(path.join(sandbox, 'secret.txt'), 'secret');
  writeSampleTask(results, { n: 4 });
  fs.mkdirSync(path.join(results, 'bad'));
  fs.writeFileSync(path.join(results, 'bad', 'task.json'), '{ not json');
  fs.mkdirSync(path.join(results, 'not_a_task'));
  fs.symlinkSync(path.join(sandbox, 'secret.txt'), path.join(results, 'link.txt'));
  const server = await startServer(results);
  try {
    assert.match(server.url, /^http:\/\/127\.0\.0\.1:\d+\/$/);
    const page = await request(server.url, '/');
    assert.equal(page.status, 200);
    assert.match(page.type, /text\/html/);
    assert.match(page.body.toString(), /importmap/);
    assert.equal((await request(server.url, '/viewer.js')).status, 200);
    const lib = await request(server.url, '/lib/ply.js?v=1');
    assert.equal(lib.status, 200);
    assert.match(lib.type, /javascript/);
    const three = await request(server.url, '/three/build/three.module.js');
    assert.equal(three.status, 200);
    assert.match(three.type, /javascript/);
    assert.equal((await request(server.url, '/three/examples/jsm/controls/OrbitControls.js')).status, 200);
    const ply = await request(server.url, '/results/bumpy_plane/rest.ply');
    assert.equal(ply.status, 200);
    assert.equal(parsePLY(ply.body).vertexCount, 16);
    assert.equal((await request(server.url, '/results/bumpy_plane/rest.ply', 'HEAD')).status, 200);
    const tasks = JSON.parse((await request(server.url, '/tasks.json')).body.toString());
    assert.deepEqual(tasks.map((t) => t.dir), ['bad', 'bumpy_plane']);
    assert.match(tasks[0].error, /cannot read task.json/);
    assert.deepEqual(tasks[1].panels, ['rest', 'vertex', 'edge', 'cgal_arap']);
    assert.deepEqual(await listTasks(results), tasks);

    const refused = ['/results/../secret.txt', '/results/%2e%2e/secret.txt', '/results/..%2fsecret.txt',
      '/results/%2E%2E%2F%2E%2E%2Fetc%2Fpasswd', '/results/..%5csecret.txt', '/three/..%2f..%2fserve.mjs',
      '/lib/%2e%2e/serve.mjs', '/results/%00', '/results/link.txt', '/results/%2fetc%2fpasswd/..%2f..'];
    for(const raw of refused) {
      const answer = await request(server.url, raw);
      assert.equal(answer.status, 403, raw);
      assert.doesNotMatch(answer.body.toString(), /secret|root:/, raw);
    }
    for(const raw of ['/serve.mjs', '/package.json', '/node_modules/three/package.json', '/results/bumpy_plane/',
                      '/results/missing.ply', '/results/%e0%a4%a'])
      assert.ok([400, 403, 404].includes((await request(server.url, raw)).status), raw);
    assert.equal((await request(server.url, '/results/bumpy_plane/rest.ply', 'POST')).status, 405);
  } finally {
    await server.close();
    fs.rmSync(sandbox, { recursive: true, force: true });
  }
  // The guard alone.
  assert.equal(resolveInside('/srv/r', 'a/b.ply'), path.resolve('/srv/r/a/b.ply'));
  assert.equal(resolveInside('/srv/r', 'a/../../x'), null);
  assert.equal(resolveInside('/srv/r', '%2fetc/passwd'), path.resolve('/srv/r/etc/passwd'));
  assert.equal(resolveInside('/srv/r', 'C:%5cx'), null);
});

test('command lines: clear errors for bad arguments and folders', () => {
  const run = (script, ...args) => spawnSync(process.execPath, [path.join(viewerDir, script), ...args], { encoding: 'utf8' });
  let r = run('serve.mjs');
  assert.equal(r.status, 2);
  assert.match(r.stderr, /usage: node viewer\/serve.mjs RESULTS_DIR/);
  r = run('serve.mjs', '/nonexistent/results', '--port', '0');
  assert.equal(r.status, 2);
  assert.match(r.stderr, /result folder '\/nonexistent\/results' does not exist/);
  r = run('render.mjs', '/nonexistent/results');
  assert.equal(r.status, 2);
  assert.match(r.stderr, /expected RESULTS_DIR and OUT_DIR/);
  r = run('render.mjs', 'a', 'b', '--width', '-3');
  assert.equal(r.status, 2);
  assert.match(r.stderr, /--width: '-3' is not a positive number/);
  const empty = fs.mkdtempSync(path.join(os.tmpdir(), 'viewer-empty-'));
  try {
    r = run('render.mjs', empty, path.join(empty, 'out'));
    assert.equal(r.status, 2);
    assert.match(r.stderr, /no task.json in/);
    assert.ok(!fs.existsSync(path.join(empty, 'out')), 'nothing is written when there is nothing to render');
  } finally { fs.rmSync(empty, { recursive: true, force: true }); }
});
