// Colour maps, shared value ranges, tick marks and the colour bar.
// No three.js; drawColorBar needs a 2D canvas (browser), everything else also runs in Node.

// Control points in sRGB [0, 1], evenly spaced over [0, 1].
export const COLORMAPS = {
  // matplotlib's viridis (perceptually uniform, readable in grey and by colour-blind readers).
  viridis: ['#440154', '#472d7b', '#3b528b', '#2c728e', '#21918c', '#28ae80', '#5ec962', '#addc30', '#fde725'],
  // Light grey (no distortion: the model looks plain) through yellow and orange to dark red.
  heat: ['#d9d9d9', '#fee391', '#fec44f', '#fe9929', '#ec7014', '#cc4c02', '#8c2d04'],
};

const parsed = {};
function controlPoints(name) {
  if(!COLORMAPS[name]) throw new Error(`unknown colour map '${name}' (known: ${Object.keys(COLORMAPS).join(', ')})`);
  if(!parsed[name])
    parsed[name] = COLORMAPS[name].map((hex) => [1, 3, 5].map((k) => parseInt(hex.slice(k, k + 2), 16) / 255));
  return parsed[name];
}

/** The colour of t in [0, 1] (clamped; NaN gives mid grey) as sRGB [r, g, b] in [0, 1]. */
export function sampleColormap(name, t) {
  const points = controlPoints(name);
  if(Number.isNaN(t)) return [0.5, 0.5, 0.5];
  const s = Math.min(1, Math.max(0, t)) * (points.length - 1);
  const i = Math.min(points.length - 2, Math.floor(s));
  const f = s - i;
  return [0, 1, 2].map((k) => points[i][k] * (1 - f) + points[i + 1][k] * f);
}

/** { min, max } of the finite values of a field, or null when it has none. */
export function fieldExtent(field) {
  let min = Infinity, max = -Infinity;
  for(let i = 0; i < field.length; ++i) {
    const v = field[i];
    if(Number.isFinite(v)) { if(v < min) min = v; if(v > max) max = v; }
  }
  return min <= max ? { min, max } : null;
}

/**
 * The shared range of several fields (arrays of numbers): { min, max } over every finite value.
 * An empty or constant field set gives a range of width 1 starting at the value (or 0), so a
 * colour bar can always be drawn. `range` ([lo, hi], either may be null) overrides either end.
 */
export function sharedRange(fields, range = null) {
  let min = Infinity, max = -Infinity;
  for(const field of fields) {
    const e = fieldExtent(field);
    if(e) { min = Math.min(min, e.min); max = Math.max(max, e.max); }
  }
  if(range && range[0] != null) min = Number(range[0]);
  if(range && range[1] != null) max = Number(range[1]);
  if(!Number.isFinite(min)) min = 0;
  if(!Number.isFinite(max) || max <= min) max = min + 1;
  return { min, max };
}

/** About `count` round tick values covering [min, max] (ends included when they are round). */
export function niceTicks(min, max, count = 5) {
  const span = max - min;
  if(!(span > 0)) return [min];
  const raw = span / Math.max(1, count - 1);
  const magnitude = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * magnitude).find((s) => s >= raw * 0.999);
  const ticks = [];
  for(let k = Math.ceil(min / step - 1e-9); k * step <= max + step * 1e-9; ++k)
    ticks.push(k === 0 ? 0 : Number((k * step).toPrecision(12)));
  return ticks;
}

/** A short label for a value (3 significant digits, exponent form for very large/small). */
export function formatValue(v) {
  if(v === 0) return '0';
  const a = Math.abs(v);
  if(a >= 1e4 || a < 1e-3) return v.toExponential(1).replace('e+', 'e');
  return String(Number(v.toPrecision(3)));
}

/** Fills an RGB(A) array (stride 3 or 4) with the colours of `field` over `range`, linear-light if asked. */
export function fieldColors(field, { min, max }, colormap = 'viridis', { linear = false, out = null } = {}) {
  const colors = out || new Float32Array(3 * field.length);
  const toLinear = (c) => (c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4));
  for(let i = 0; i < field.length; ++i) {
    const c = sampleColormap(colormap, (field[i] - min) / (max - min));
    for(let k = 0; k < 3; ++k) colors[3 * i + k] = linear ? toLinear(c[k]) : c[k];
  }
  return colors;
}

/**
 * Draws a horizontal colour bar on a 2D canvas: the gradient, round ticks with labels, and a
 * caption (the field's name). The canvas keeps its CSS size; its pixels follow devicePixelRatio.
 */
export function drawColorBar(canvas, { min, max, colormap = 'viridis', label = '', clippedMax = false, clippedMin = false }) {
  const ratio = (typeof window !== 'undefined' && window.devicePixelRatio) || 1;
  const width = canvas.clientWidth || canvas.width;
  const height = canvas.clientHeight || canvas.height;
  canvas.width = Math.round(width * ratio);
  canvas.height = Math.round(height * ratio);
  const g = canvas.getContext('2d');
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  g.clearRect(0, 0, width, height);
  const margin = 40, barTop = 4, barHeight = Math.max(8, Math.round(height * 0.3));
  const barWidth = width - 2 * margin;
  for(let x = 0; x < barWidth; ++x) {
    const [r, gg, b] = sampleColormap(colormap, x / Math.max(1, barWidth - 1));
    g.fillStyle = `rgb(${Math.round(r * 255)},${Math.round(gg * 255)},${Math.round(b * 255)})`;
    g.fillRect(margin + x, barTop, 1.5, barHeight);
  }
  g.strokeStyle = '#333';
  g.lineWidth = 1;
  g.strokeRect(margin - 0.5, barTop - 0.5, barWidth + 1, barHeight + 1);
  g.fillStyle = '#222';
  g.font = '13px sans-serif';
  g.textAlign = 'center';
  g.textBaseline = 'top';
  // The exact ends, and the round values between them that are not too close to an end.
  const ticks = [min, ...niceTicks(min, max, 5).filter((v) => v - min > 0.1 * (max - min) && max - v > 0.1 * (max - min)), max];
  for(const v of ticks) {
    const x = margin + (v - min) / (max - min) * barWidth;
    g.fillRect(Math.round(x) - 0.5, barTop + barHeight, 1, 4);
    let text = formatValue(v);
    if(clippedMax && Math.abs(v - max) < (max - min) * 1e-6) text = '\u2265 ' + text;
    if(clippedMin && Math.abs(v - min) < (max - min) * 1e-6) text = '\u2264 ' + text;
    g.fillText(text, x, barTop + barHeight + 6);
  }
  if(label) {
    g.font = '14px sans-serif';
    g.fillText(label, width / 2, barTop + barHeight + 24);
  }
}
