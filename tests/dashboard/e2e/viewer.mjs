// The final-image viewer's checks (issue 16, acceptance 4): exposure, layers, zoom. Each
// reads what the canvas shows (getImageData, or a screenshot for zoom) and checks it
// against arithmetic the viewer must obey, never against the viewer's own output alone.

const tid = (id) => `[data-testid="${id}"]`;

// The AOVs a render worker writes (worker/render/tile_renderer.cpp) beside R, G, B, A, and
// samples (samples.Y: camera samples a pixel, summed over rounds). bias is the photon
// estimates' estimated bias (docs/error-estimate.md), shown by its magnitude.
export const WORKER_LAYERS = ['beauty', 'albedo', 'bias', 'caustic', 'depth', 'direct', 'edge', 'indirect', 'normal', 'samples', 'volume'];

// 8-bit sRGB to linear, and the linear interval an 8-bit value stands for.
const toLinear = (s) => (s <= 0.04045 ? s / 12.92 : ((s + 0.055) / 1.055) ** 2.4);
const linearRange = (v) => [toLinear(Math.max(0, v - 0.5) / 255), toLinear(Math.min(255, v + 0.5) / 255)];

/** The canvas's RGBA bytes, as a plain array. */
export function canvasPixels(page) {
  return page.locator(tid('final-canvas')).evaluate((c) => Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data));
}

async function setControl(page, testid, value, event) {
  await page.locator(tid(testid)).evaluate((el, [v, e]) => {
    el.value = v;
    el.dispatchEvent(new Event(e, { bubbles: true }));
  }, [String(value), event]);
}

export const setExposure = (page, ev) => setControl(page, 'exposure-slider', ev, 'input');
export const setLayer = (page, name) => setControl(page, 'layer-select', name, 'change');
export const setZoom = (page, zoom) => setControl(page, 'zoom-select', zoom, 'change');

/**
 * Pixels at +ev must be 2^ev times those at 0 EV in linear light: for each channel below
 * clipping at both exposures, the intervals its 8-bit values stand for must overlap once
 * scaled. Returns how many channels were compared and how many disagreed.
 */
export function compareExposure(at0, atEv, ev) {
  const k = 2 ** ev;
  let compared = 0;
  let wrong = 0;
  for (let i = 0; i < at0.length; i++) {
    if (i % 4 === 3 || at0[i] < 8 || atEv[i] >= 250) continue;
    const [lo0, hi0] = linearRange(at0[i]);
    const [lo, hi] = linearRange(atEv[i]);
    compared++;
    if (hi < lo0 * k * 0.999 || lo > hi0 * k * 1.001) wrong++;
  }
  return { compared, wrong };
}

/** Normals shown as (n + 1) / 2: every pixel that is not the background (n = 0, grey) decodes to a unit vector. */
export function normalLengths(px) {
  let surface = 0;
  let unit = 0;
  for (let i = 0; i < px.length; i += 4) {
    const n = [0, 1, 2].map((c) => (2 * px[i + c]) / 255 - 1);
    const len = Math.hypot(...n);
    if (len < 0.2) continue;
    surface++;
    if (Math.abs(len - 1) < 0.03) unit++;
  }
  return { surface, unit };
}

/**
 * Compares a screenshot of the canvas at zoom z (a PNG) with the canvas's own pixels
 * (`want`, RGBA, `width` wide): every screen pixel of the z×z block of image pixel (x, y)
 * must be that pixel's colour (within 2 for colour handling), which a smoothed stretch is
 * not. The PNG is decoded in `blank`, a page without the dashboard's CSP (which forbids
 * data: images).
 */
export function nearestNeighbourMismatches(blank, png, want, width, zoom) {
  return blank.evaluate(async ([b64, wantPx, w, z]) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const shot = document.createElement('canvas');
    shot.width = img.naturalWidth;
    shot.height = img.naturalHeight;
    const sctx = shot.getContext('2d');
    sctx.drawImage(img, 0, 0);
    const got = sctx.getImageData(0, 0, shot.width, shot.height).data;
    const h = wantPx.length / 4 / w;
    // The canvas may sit at a fractional position: the screenshot's first row or column
    // can be a pixel before or after the image's. Each shift is tried; the best must match.
    let best = { checked: 0, bad: Infinity };
    for (const oy of [-1, 0, 1]) {
      for (const ox of [-1, 0, 1]) {
        let checked = 0;
        let bad = 0;
        for (let y = 1; y < shot.height - 1; y++) {
          const iy = Math.floor((y + oy) / z);
          if (iy < 0 || iy >= h) continue;
          for (let x = 1; x < shot.width - 1; x++) {
            const ix = Math.floor((x + ox) / z);
            if (ix < 0 || ix >= w) continue;
            const g = 4 * (y * shot.width + x);
            const p = 4 * (iy * w + ix);
            checked++;
            if ([0, 1, 2].some((k) => Math.abs(got[g + k] - wantPx[p + k]) > 2)) bad++;
          }
        }
        if (bad < best.bad) best = { checked, bad, shift: [ox, oy] };
      }
    }
    return { ...best, width: shot.width, height: shot.height };
  }, [png.toString('base64'), want, width, zoom]);
}

export function hashPixels(px) {
  let h = 2166136261;
  for (const v of px) h = Math.imul(h ^ v, 16777619) >>> 0;
  return h;
}
