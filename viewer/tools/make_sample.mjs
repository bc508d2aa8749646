#!/usr/bin/env node
// Writes a small SYNTHETIC result folder in the harness's format, for trying the viewer and for
// its tests (no deformation method is run: the deformed shapes are analytic lifts).
//   OUT/bumpy_plane/{rest,vertex,edge,cgal_arap}.ply + task.json
// A bumpy plane's centre is lifted with three different bell profiles; each panel's
// `distortion` is the mean relative change of the lengths of the edges at a vertex (0 at rest).
//   usage: node viewer/tools/make_sample.mjs OUT_DIR [--n GRID]
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { writePLY } from '../lib/ply.js';

/** An n x n vertex grid on [-1, 1]^2 with bumps: { positions, indices }. */
export function bumpyPlane(n) {
  const positions = [];
  for(let j = 0; j < n; ++j)
    for(let i = 0; i < n; ++i) {
      const x = -1 + 2 * i / (n - 1), y = -1 + 2 * j / (n - 1);
      positions.push(x, y, 0.04 * Math.sin(3 * Math.PI * x) * Math.sin(3 * Math.PI * y));
    }
  const indices = [];
  for(let j = 0; j + 1 < n; ++j)
    for(let i = 0; i + 1 < n; ++i) {
      const a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      indices.push(a, b, d, a, d, c);
    }
  return { positions, indices };
}

/** The centre lifted by `height` with a bell of width `sigma`, and `shear` sideways at the top. */
export function lift({ positions }, height, sigma, shear = 0) {
  const out = positions.slice();
  for(let v = 0; v < out.length; v += 3) {
    const r2 = out[v] * out[v] + out[v + 1] * out[v + 1];
    const bell = Math.exp(-r2 / (sigma * sigma));
    out[v + 2] += height * bell;
    out[v] += shear * bell * bell;
  }
  return out;
}

/** Per vertex: mean over its edges of |l' - l| / l (rest and deformed share the triangles). */
export function edgeLengthDistortion(rest, deformed, indices) {
  const n = rest.length / 3;
  const sum = new Float64Array(n), count = new Uint32Array(n);
  const length = (p, a, b) => Math.hypot(p[3 * a] - p[3 * b], p[3 * a + 1] - p[3 * b + 1], p[3 * a + 2] - p[3 * b + 2]);
  for(let f = 0; f < indices.length; f += 3)
    for(let k = 0; k < 3; ++k) {
      const a = indices[f + k], b = indices[f + (k + 1) % 3];
      const l0 = length(rest, a, b);
      const change = l0 > 0 ? Math.abs(length(deformed, a, b) - l0) / l0 : 0;
      // Interior edges are seen from two triangles: both count, the mean is unchanged.
      sum[a] += change; sum[b] += change; ++count[a]; ++count[b];
    }
  return Array.from(sum, (s, i) => (count[i] ? s / count[i] : 0));
}

/**
 * Writes OUT/<task>/ (default task 'bumpy_plane') with the four panels of the harness. Options:
 * n (grid size), panels (subset and order), format ('binary_little_endian' or 'ascii').
 */
export function writeSampleTask(outDir, { task = 'bumpy_plane', n = 32, panels = ['rest', 'vertex', 'edge', 'cgal_arap'],
                                          format = 'binary_little_endian', title = null } = {}) {
  const plane = bumpyPlane(n);
  const shapes = {
    rest: plane.positions,
    vertex: lift(plane, 0.6, 0.35, 0.15),
    edge: lift(plane, 0.6, 0.65, 0.05),
    cgal_arap: lift(plane, 0.6, 0.42, 0.12),
  };
  const folder = path.join(outDir, task);
  fs.mkdirSync(folder, { recursive: true });
  for(const name of panels) {
    if(!shapes[name]) throw new Error(`no synthetic shape for panel '${name}'`);
    const distortion = edgeLengthDistortion(plane.positions, shapes[name], plane.indices);
    fs.writeFileSync(path.join(folder, `${name}.ply`),
      writePLY({ positions: shapes[name], indices: plane.indices, vertexProperties: { distortion } }, { format }));
  }
  fs.writeFileSync(path.join(folder, 'task.json'), JSON.stringify({
    task, title: title || 'Synthetic sample: a bumpy plane with its centre lifted (analytic shapes, no solver)',
    field: 'mean relative edge-length change', panels,
  }, null, 2) + '\n');
  return folder;
}

if(process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const args = process.argv.slice(2);
  let out = null, n = 32;
  for(let i = 0; i < args.length; ++i) {
    if(args[i] === '--n') n = Number(args[++i]);
    else if(out === null) out = args[i];
    else { console.error(`make_sample.mjs: unexpected argument '${args[i]}'`); process.exit(2); }
  }
  if(out === null || !Number.isInteger(n) || n < 2) {
    console.error('usage: node viewer/tools/make_sample.mjs OUT_DIR [--n GRID (>= 2)]');
    process.exit(2);
  }
  console.log(`wrote ${writeSampleTask(out, { n })}`);
}
