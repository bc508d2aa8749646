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
