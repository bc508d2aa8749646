// A tiny PNG decoder for the tests (node's zlib): 8-bit grey, grey+alpha, RGB and RGBA,
// non-interlaced -- what Chromium's screenshots are. decodePNG(buffer) -> { width, height, rgba }.
import zlib from 'node:zlib';

export function decodePNG(buffer) {
  const signature = [137, 80, 78, 71, 13, 10, 26, 10];
  if(buffer.length < 8 || signature.some((b, i) => buffer[i] !== b)) throw new Error('not a PNG file');
  let pos = 8, header = null;
  const data = [];
  while(pos + 8 <= buffer.length) {
    const length = buffer.readUInt32BE(pos);
    const type = buffer.toString('latin1', pos + 4, pos + 8);
    const body = buffer.subarray(pos + 8, pos + 8 + length);
    pos += 12 + length;
    if(type === 'IHDR') header = { width: body.readUInt32BE(0), height: body.readUInt32BE(4), depth: body[8],
                                   colorType: body[9], interlace: body[12] };
    else if(type === 'IDAT') data.push(body);
    else if(type === 'IEND') break;
  }
  if(!header) throw new Error('PNG: no IHDR chunk');
  const channels = { 0: 1, 2: 3, 4: 2, 6: 4 }[header.colorType];
  if(header.depth !== 8 || !channels || header.interlace !== 0)
    throw new Error(`PNG: unsupported depth ${header.depth} / colour type ${header.colorType} / interlace ${header.interlace}`);
  const { width, height } = header;
  const raw = zlib.inflateSync(Buffer.concat(data));
  const stride = width * channels;
  if(raw.length < height * (stride + 1)) throw new Error('PNG: image data too short');
  const pixels = Buffer.alloc(height * stride);
  for(let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const out = y * stride;
    for(let x = 0; x < stride; ++x) {
      const a = x >= channels ? pixels[out + x - channels] : 0;
      const b = y > 0 ? pixels[out - stride + x] : 0;
      const c = x >= channels && y > 0 ? pixels[out - stride + x - channels] : 0;
      let predictor;
      switch(filter) {
        case 0: predictor = 0; break;
        case 1: predictor = a; break;
        case 2: predictor = b; break;
        case 3: predictor = (a + b) >> 1; break;
        case 4: {
          const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
          predictor = pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
          break;
        }
        default: throw new Error(`PNG: bad filter ${filter} on row ${y}`);
      }
      pixels[out + x] = (line[x] + predictor) & 0xff;
    }
  }
  const rgba = Buffer.alloc(width * height * 4);
  for(let i = 0; i < width * height; ++i) {
    const s = i * channels;
    if(channels <= 2) { rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = pixels[s]; rgba[4 * i + 3] = channels === 2 ? pixels[s + 1] : 255; }
    else { rgba[4 * i] = pixels[s]; rgba[4 * i + 1] = pixels[s + 1]; rgba[4 * i + 2] = pixels[s + 2]; rgba[4 * i + 3] = channels === 4 ? pixels[s + 3] : 255; }
  }
  return { width, height, rgba };
}
