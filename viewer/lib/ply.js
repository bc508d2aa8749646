// PLY reading and writing for triangle meshes with per-vertex scalar fields.
// Pure JavaScript (no three.js, no DOM): runs in the browser and in Node.
//
// parsePLY(bytes) -> { positions: Float32Array(3n), indices: Uint32Array(3m),
//                      vertexProperties: { name: Float32Array(n) }, vertexCount, faceCount }
// Supports format ascii, binary_little_endian and binary_big_endian; every scalar type of the
// PLY specification (and the sized aliases int8 ... float64); faces as a list property named
// vertex_indices or vertex_index (polygons are fan-triangulated); other elements are skipped.
// writePLY(mesh, { format }) -> Uint8Array (the inverse, float vertex properties).

const SCALAR_TYPES = {
  char: ['Int8', 1], int8: ['Int8', 1],
  uchar: ['Uint8', 1], uint8: ['Uint8', 1],
  short: ['Int16', 2], int16: ['Int16', 2],
  ushort: ['Uint16', 2], uint16: ['Uint16', 2],
  int: ['Int32', 4], int32: ['Int32', 4],
  uint: ['Uint32', 4], uint32: ['Uint32', 4],
  float: ['Float32', 4], float32: ['Float32', 4],
  double: ['Float64', 8], float64: ['Float64', 8],
};

/** An error in a PLY file; the message says what and where. */
export class PlyError extends Error {
  constructor(message) { super(message); this.name = 'PlyError'; }
}

function scalarType(name, where) {
  const t = SCALAR_TYPES[name];
  if(!t) throw new PlyError(`PLY: unknown scalar type '${name}' in ${where}`);
  return t;
}

/** Parses the header; returns { format, elements: [{name, count, properties}], bodyOffset }. */
function parseHeader(bytes) {
  // The header is ASCII and ends with "end_header" followed by a newline.
  const limit = Math.min(bytes.length, 1 << 16);
  let text = '';
  for(let i = 0; i < limit; ++i) text += String.fromCharCode(bytes[i]);
  if(!/^ply\r?\n/.test(text)) throw new PlyError('PLY: missing "ply" magic line');
  const end = /(^|\n)end_header[ \t]*\r?\n/.exec(text);
  if(!end) throw new PlyError('PLY: missing "end_header" line');
  const bodyOffset = end.index + end[0].length;
  const lines = text.slice(0, end.index).split(/\r?\n/);
  let format = null;
  const elements = [];
  for(let i = 1; i < lines.length; ++i) {
    const words = lines[i].trim().split(/\s+/);
    if(words[0] === '' || words[0] === 'comment' || words[0] === 'obj_info') continue;
    if(words[0] === 'format') {
      format = words[1];
      if(!['ascii', 'binary_little_endian', 'binary_big_endian'].includes(format))
        throw new PlyError(`PLY: unsupported format '${format}'`);
    } else if(words[0] === 'element') {
      const count = Number(words[2]);
      if(!Number.isInteger(count) || count < 0)
        throw new PlyError(`PLY: bad count in header line '${lines[i]}'`);
      elements.push({ name: words[1], count, properties: [] });
    } else if(words[0] === 'property') {
      const element = elements[elements.length - 1];
      if(!element) throw new PlyError(`PLY: property before any element: '${lines[i]}'`);
      if(words[1] === 'list') {
        element.properties.push({ name: words[4], list: true,
          countType: scalarType(words[2], lines[i]), itemType: scalarType(words[3], lines[i]) });
      } else {
        element.properties.push({ name: words[2], list: false, type: scalarType(words[1], lines[i]) });
      }
    } else {
      throw new PlyError(`PLY: unexpected header line '${lines[i]}'`);
    }
  }
  if(!format) throw new PlyError('PLY: missing "format" line');
  return { format, elements, bodyOffset };
}

/** A reader of the body's numbers, ascii or binary. */
function makeReader(bytes, format, offset) {
  if(format === 'ascii') {
    let text = '';
    // Decode in chunks (String.fromCharCode.apply has an argument limit).
    for(let i = offset; i < bytes.length; i += 65536)
      text += String.fromCharCode.apply(null, bytes.subarray(i, Math.min(i + 65536, bytes.length)));
    const tokens = text.split(/\s+/).filter((t) => t.length > 0);
    let k = 0;
    return {
      read() {
        if(k >= tokens.length) throw new PlyError('PLY: file ends before all elements were read');
        const v = Number(tokens[k++]);
        if(Number.isNaN(v) && tokens[k - 1].toLowerCase() !== 'nan')
          throw new PlyError(`PLY: '${tokens[k - 1]}' is not a number`);
        return v;
      },
    };
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const little = format === 'binary_little_endian';
  let pos = offset;
  return {
    read(type) {
      const [getter, size] = type;
      if(pos + size > bytes.length) throw new PlyError('PLY: file ends before all elements were read');
      const v = view['get' + getter](pos, little);
      pos += size;
      return v;
    },
  };
}

/**
 * Parses a PLY file (ArrayBuffer, Uint8Array or, for ascii files, a string).
 * Throws a PlyError naming the problem for anything it cannot read.
 */
export function parsePLY(input) {
  let bytes;
  if(typeof input === 'string') bytes = Uint8Array.from(input, (c) => c.charCodeAt(0) & 0xff);
  else if(input instanceof ArrayBuffer) bytes = new Uint8Array(input);
  else if(ArrayBuffer.isView(input)) bytes = new Uint8Array(input.buffer, input.byteOffset, input.byteLength);
  else throw new PlyError('PLY: expected an ArrayBuffer, a typed array or a string');

  const { format, elements, bodyOffset } = parseHeader(bytes);
  const reader = makeReader(bytes, format, bodyOffset);
  let positions = null;
  const vertexProperties = {};
  const triangles = [];
  let vertexCount = 0;
  let faceCount = 0;

  for(const element of elements) {
    if(element.name === 'vertex') {
      vertexCount = element.count;
      const names = element.properties.map((p) => p.name);
      for(const axis of ['x', 'y', 'z'])
        if(!names.includes(axis)) throw new PlyError(`PLY: vertex element has no '${axis}' property`);
      positions = new Float32Array(3 * element.count);
      const columns = element.properties.map((p) =>
        (p.list || ['x', 'y', 'z'].includes(p.name)) ? null : (vertexProperties[p.name] = new Float32Array(element.count)));
      for(let i = 0; i < element.count; ++i) {
        element.properties.forEach((p, j) => {
          if(p.list) {
            const n = reader.read(p.countType);
            for(let k = 0; k < n; ++k) reader.read(p.itemType);
            return;
          }
          const v = reader.read(p.type);
          if(p.name === 'x') positions[3 * i] = v;
          else if(p.name === 'y') positions[3 * i + 1] = v;
          else if(p.name === 'z') positions[3 * i + 2] = v;
          else columns[j][i] = v;
        });
      }
    } else if(element.name === 'face') {
      faceCount = element.count;
      const listIndex = element.properties.findIndex((p) =>
        p.list && (p.name === 'vertex_indices' || p.name === 'vertex_index'));
      if(listIndex < 0) throw new PlyError('PLY: face element has no vertex_indices list');
      for(let i = 0; i < element.count; ++i) {
        element.properties.forEach((p, j) => {
          if(!p.list) { reader.read(p.type); return; }
          const n = reader.read(p.countType);
          const ids = [];
          for(let k = 0; k < n; ++k) ids.push(reader.read(p.itemType));
          if(j !== listIndex) return;
          if(n < 3) throw new PlyError(`PLY: face ${i} has ${n} vertices`);
          for(let k = 1; k + 1 < n; ++k) triangles.push(ids[0], ids[k], ids[k + 1]);
        });
      }
    } else {
      for(let i = 0; i < element.count; ++i)
        for(const p of element.properties) {
          if(p.list) { const n = reader.read(p.countType); for(let k = 0; k < n; ++k) reader.read(p.itemType); }
          else reader.read(p.type);
        }
    }
  }
  if(!positions) throw new PlyError('PLY: no vertex element');
  const indices = Uint32Array.from(triangles);
  for(let i = 0; i < indices.length; ++i)
    if(!Number.isInteger(triangles[i]) || triangles[i] < 0 || triangles[i] >= vertexCount)
      throw new PlyError(`PLY: face ${Math.floor(i / 3)} refers to vertex ${triangles[i]} of ${vertexCount}`);
  return { positions, indices, vertexProperties, vertexCount, faceCount };
}

/**
 * Writes a triangle mesh as PLY: { positions (3n numbers), indices (3m numbers),
 * vertexProperties: { name: n numbers } } -> Uint8Array. Options: format 'ascii' or
 * 'binary_little_endian' (default). Vertex properties are written as `property float name`.
 */
export function writePLY(mesh, { format = 'binary_little_endian' } = {}) {
  const n = mesh.positions.length / 3;
  const m = mesh.indices.length / 3;
  const props = Object.entries(mesh.vertexProperties || {});
  for(const [name, values] of props)
    if(values.length !== n) throw new PlyError(`PLY: property '${name}' has ${values.length} values for ${n} vertices`);
  let header = `ply\nformat ${format} 1.0\nelement vertex ${n}\n` +
    'property float x\nproperty float y\nproperty float z\n';
  for(const [name] of props) header += `property float ${name}\n`;
  header += `element face ${m}\nproperty list uchar int vertex_indices\nend_header\n`;
  const head = Uint8Array.from(header, (c) => c.charCodeAt(0));
  if(format === 'ascii') {
    const lines = [];
    for(let i = 0; i < n; ++i) {
      const row = [mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]];
      for(const [, values] of props) row.push(values[i]);
      lines.push(row.map((v) => Math.fround(v)).join(' '));
    }
    for(let f = 0; f < m; ++f)
      lines.push(`3 ${mesh.indices[3 * f]} ${mesh.indices[3 * f + 1]} ${mesh.indices[3 * f + 2]}`);
    const body = Uint8Array.from(lines.join('\n') + '\n', (c) => c.charCodeAt(0));
    const out = new Uint8Array(head.length + body.length);
    out.set(head); out.set(body, head.length);
    return out;
  }
  if(format !== 'binary_little_endian') throw new PlyError(`PLY: cannot write format '${format}'`);
  const size = head.length + n * 4 * (3 + props.length) + m * 13;
  const out = new Uint8Array(size);
  out.set(head);
  const view = new DataView(out.buffer);
  let pos = head.length;
  for(let i = 0; i < n; ++i) {
    for(let k = 0; k < 3; ++k) { view.setFloat32(pos, mesh.positions[3 * i + k], true); pos += 4; }
    for(const [, values] of props) { view.setFloat32(pos, values[i], true); pos += 4; }
  }
  for(let f = 0; f < m; ++f) {
    view.setUint8(pos, 3); pos += 1;
    for(let k = 0; k < 3; ++k) { view.setInt32(pos, mesh.indices[3 * f + k], true); pos += 4; }
  }
  return out;
}
