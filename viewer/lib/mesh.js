// three.js meshes coloured by a per-vertex scalar field.
// Reusable by any page that has the triangles as arrays (a PLY file, a JSON API, ...).
import * as THREE from 'three';
import { fieldColors } from './colormap.js';

/**
 * Builds a THREE.Mesh from { positions (3n numbers), indices (3m numbers), field (n numbers) }
 * coloured by `field` over `range` ({ min, max }) with `colormap`. Options: flatShading.
 */
export function createFieldMesh({ positions, indices, field }, range, colormap = 'viridis', { flatShading = false } = {}) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(Float32Array.from(positions), 3));
  const n = positions.length / 3;
  geometry.setIndex(new THREE.BufferAttribute(n > 65535 ? Uint32Array.from(indices) : Uint16Array.from(indices), 1));
  geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * n), 3));
  geometry.computeVertexNormals();
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();
  const material = new THREE.MeshPhongMaterial({
    vertexColors: true, side: THREE.DoubleSide, flatShading,
    shininess: 18, specular: new THREE.Color(0x1a1a1a),
  });
  const mesh = new THREE.Mesh(geometry, material);
  setFieldColors(mesh, field, range, colormap);
  return mesh;
}

/** Recolours a mesh made by createFieldMesh (the field has one value per vertex). */
export function setFieldColors(mesh, field, range, colormap = 'viridis') {
  const attribute = mesh.geometry.getAttribute('color');
  if(field.length !== attribute.count)
    throw new Error(`field has ${field.length} values for ${attribute.count} vertices`);
  // Vertex colours are in three.js's linear working space; the colour map is sRGB.
  fieldColors(field, range, colormap, { linear: true, out: attribute.array });
  attribute.needsUpdate = true;
  mesh.userData.field = field;
}

/** Moves the vertices of a mesh made by createFieldMesh (same count), recomputing its normals. */
export function setPositions(mesh, positions) {
  const attribute = mesh.geometry.getAttribute('position');
  if(positions.length !== attribute.array.length)
    throw new Error(`got ${positions.length / 3} positions for ${attribute.count} vertices`);
  attribute.array.set(positions);
  attribute.needsUpdate = true;
  mesh.geometry.computeVertexNormals();
  mesh.geometry.computeBoundingBox();
  mesh.geometry.computeBoundingSphere();
}

/**
 * The neighbours of every vertex of a triangle list (each once, in increasing order), as views into
 * one array: counted, filled and
 * deduplicated in place, without a Set per vertex (about 0.8 s on a 416k-vertex mesh).
 */
export function vertexNeighbours(n, faces) {
  const start = new Uint32Array(n + 1);
  for(let i = 0; i < faces.length; ++i) start[faces[i] + 1] += 2;
  for(let v = 0; v < n; ++v) start[v + 1] += start[v];
  const all = new Int32Array(start[n]), fill = start.slice(0, n);
  for(let f = 0; f < faces.length; f += 3)
    for(let k = 0; k < 3; ++k) {
      const a = faces[f + k], b = faces[f + (k + 1) % 3];
      all[fill[a]++] = b; all[fill[b]++] = a;
    }
  const lists = new Array(n);
  for(let v = 0; v < n; ++v) {
    const row = all.subarray(start[v], start[v + 1]);
    row.sort();
    let m = 0;
    for(let i = 0; i < row.length; ++i) if(i === 0 || row[i] !== row[i - 1]) row[m++] = row[i];
    lists[v] = row.subarray(0, m);
  }
  return lists;
}

/**
 * The faces around each vertex of a mesh made by createFieldMesh, as compressed rows (the faces of
 * vertex v are faces[start[v]] .. faces[start[v + 1] - 1], in increasing order); built once per
 * mesh and kept in mesh.userData (its triangles never change).
 */
export function vertexFaces(mesh) {
  const index = mesh.geometry.index.array, n = mesh.geometry.getAttribute('position').count;
  const cached = mesh.userData.vertexFaces;
  if(cached && cached.index === index && cached.start.length === n + 1) return cached;
  const start = new Uint32Array(n + 1);
  for(let i = 0; i < index.length; ++i) ++start[index[i] + 1];
  for(let v = 0; v < n; ++v) start[v + 1] += start[v];
  const faces = new Uint32Array(index.length), fill = start.slice(0, n);
  for(let i = 0; i < index.length; ++i) faces[fill[index[i]]++] = (i / 3) | 0;
  mesh.userData.vertexFaces = { index, start, faces };
  return mesh.userData.vertexFaces;
}

/**
 * What `setSomePositions` updates when only `vertices` of a mesh made by createFieldMesh move:
 * the vertices whose normals change (those of the faces around the moving ones) and the faces
 * their normals sum over, in increasing order (that of computeVertexNormals). Computed once per set
 * of moving vertices; its cost is the region's (the vertex-to-faces table is built once per mesh).
 */
export function movingRegion(mesh, vertices) {
  const index = mesh.geometry.index.array, n = mesh.geometry.getAttribute('position').count;
  const { start, faces } = vertexFaces(mesh);
  const affected = new Uint8Array(n), regionVertices = [];
  for(const v of vertices)
    for(let k = start[v]; k < start[v + 1]; ++k)
      for(let c = 0; c < 3; ++c) {
        const w = index[3 * faces[k] + c];
        if(!affected[w]) { affected[w] = 1; regionVertices.push(w); }
      }
  const seen = new Set(), regionFaces = [];
  for(const v of regionVertices)
    for(let k = start[v]; k < start[v + 1]; ++k) if(!seen.has(faces[k])) { seen.add(faces[k]); regionFaces.push(faces[k]); }
  return { moving: Int32Array.from(vertices), vertices: Uint32Array.from(regionVertices).sort(),
           faces: Uint32Array.from(regionFaces).sort(), affected };
}

/**
 * Moves the vertices `region.moving` (see movingRegion) of a mesh to `xyz` (x, y, z each, in that
 * order) and recomputes only the normals that change -- the same normals as computeVertexNormals
 * (the sum of the adjacent faces' cross products, normalised) for a fraction of its cost.
 */
export function setSomePositions(mesh, region, xyz) {
  if(xyz.length !== 3 * region.moving.length)
    throw new Error(`got ${xyz.length / 3} positions for ${region.moving.length} moving vertices`);
  const geometry = mesh.geometry, position = geometry.getAttribute('position'), normal = geometry.getAttribute('normal');
  const p = position.array, q = normal.array, index = geometry.index.array, affected = region.affected;
  region.moving.forEach((v, i) => { p[3 * v] = xyz[3 * i]; p[3 * v + 1] = xyz[3 * i + 1]; p[3 * v + 2] = xyz[3 * i + 2]; });
  for(const v of region.vertices) q[3 * v] = q[3 * v + 1] = q[3 * v + 2] = 0;
  for(const f of region.faces) {
    const a = 3 * index[3 * f], b = 3 * index[3 * f + 1], c = 3 * index[3 * f + 2];
    const cbx = p[c] - p[b], cby = p[c + 1] - p[b + 1], cbz = p[c + 2] - p[b + 2];
    const abx = p[a] - p[b], aby = p[a + 1] - p[b + 1], abz = p[a + 2] - p[b + 2];
    const nx = cby * abz - cbz * aby, ny = cbz * abx - cbx * abz, nz = cbx * aby - cby * abx;
    for(const w of [a, b, c]) if(affected[w / 3]) { q[w] += nx; q[w + 1] += ny; q[w + 2] += nz; }
  }
  for(const v of region.vertices) {
    const l = Math.hypot(q[3 * v], q[3 * v + 1], q[3 * v + 2]) || 1;
    q[3 * v] /= l; q[3 * v + 1] /= l; q[3 * v + 2] /= l;
  }
  position.needsUpdate = true;
  normal.needsUpdate = true;
  // the bounding sphere (culling, picking) grows to hold the moved vertices: O(moving), where
  // recomputing it reads every vertex (5 to 10 ms per drag on a 416k-vertex mesh); it never shrinks,
  // which only makes it looser
  if(!geometry.boundingSphere) { geometry.computeBoundingSphere(); return; }
  const point = new THREE.Vector3();
  for(const v of region.moving) geometry.boundingSphere.expandByPoint(point.set(p[3 * v], p[3 * v + 1], p[3 * v + 2]));
}

/** The bounding box of several meshes (world coordinates). */
export function boundsOf(objects) {
  const box = new THREE.Box3();
  for(const object of objects) box.expandByObject(object);
  return box;
}

/**
 * A default viewing direction (from the target towards the camera) and up vector for a box.
 * A flat box (a plate) is seen obliquely from about 40 degrees above, its thin axis up; any
 * other box is seen from the side of its thinnest axis, turned a little towards the others,
 * with its longest axis up -- tall pictures suit panels side by side.
 */
export function defaultView(box) {
  const size = box.getSize(new THREE.Vector3()).toArray();
  const order = [0, 1, 2].sort((a, b) => size[a] - size[b]);   // smallest ... largest
  const axis = (k) => new THREE.Vector3().setComponent(k, 1);
  if(size[order[0]] < 0.35 * size[order[1]]) {
    const direction = axis(order[0]).multiplyScalar(0.85)
      .add(axis(order[1]).multiplyScalar(0.9)).add(axis(order[2]).multiplyScalar(0.35)).normalize();
    return { direction, up: axis(order[0]) };
  }
  const direction = axis(order[0]).add(axis(order[1]).multiplyScalar(0.6))
    .add(axis(order[2]).multiplyScalar(0.2)).normalize();
  return { direction, up: axis(order[2]) };
}
