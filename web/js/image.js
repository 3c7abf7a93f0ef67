// Pixels of the service's 8-bit sRGB PNGs: loading, exposure and differences, done in linear light
// (decode sRGB, operate, encode), per the sRGB transfer function (IEC 61966-2-1).

export const toLinear = v => (v <= 0.04045 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4));
export const toSrgb = v => (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055);

const LINEAR = Float32Array.from({length: 256}, (_, i) => toLinear(i / 255));

/** Encodes a linear value in [0, ∞) as an 8-bit sRGB code (clipped at 1). */
function encode8(linear) {
  return Math.round(255 * toSrgb(Math.min(1, Math.max(0, linear))));
}

/** Loads an image URL (same origin) into ImageData. */
export async function loadImageData(url, signal) {
  const res = await fetch(url, {signal});
  if (!res.ok) throw new Error(`${url}: HTTP ${res.status}`);
  const bitmap = await createImageBitmap(await res.blob(), {colorSpaceConversion: 'none',
    premultiplyAlpha: 'none'});
  const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
  const ctx = canvas.getContext('2d');
  ctx.drawImage(bitmap, 0, 0);
  bitmap.close();
  return ctx.getImageData(0, 0, canvas.width, canvas.height);
}

/** A copy of `src` with every colour scaled by 2^ev in linear light. Alpha is kept. */
export function exposed(src, ev) {
  const out = new ImageData(src.width, src.height);
  const gain = Math.pow(2, ev);
  const lut = new Uint8ClampedArray(256);
  for (let i = 0; i < 256; i++) lut[i] = encode8(LINEAR[i] * gain);
  const s = src.data, d = out.data;
  for (let i = 0; i < s.length; i += 4) {
    d[i] = lut[s[i]];
    d[i + 1] = lut[s[i + 1]];
    d[i + 2] = lut[s[i + 2]];
    d[i + 3] = s[i + 3];
  }
  return out;
}

/** |a − b| per channel in linear light, times `scale`, encoded to sRGB; a and b have one size.
 *  Also returns the mean absolute difference (linear, over every channel). */
export function difference(a, b, scale) {
  const out = new ImageData(a.width, a.height);
  const x = a.data, y = b.data, d = out.data;
  let sum = 0;
  for (let i = 0; i < x.length; i += 4) {
    for (let c = 0; c < 3; c++) {
      const diff = Math.abs(LINEAR[x[i + c]] - LINEAR[y[i + c]]);
      sum += diff;
      d[i + c] = encode8(diff * scale);
    }
    d[i + 3] = 255;
  }
  return {image: out, mean: sum / (3 * a.width * a.height)};
}

/** Draws ImageData into a canvas, resizing it to the image. */
export function paint(canvas, image) {
  if (canvas.width !== image.width) canvas.width = image.width;
  if (canvas.height !== image.height) canvas.height = image.height;
  canvas.getContext('2d').putImageData(image, 0, 0);
}
