// The final-image viewer: the job's image.exr drawn on a canvas from its linear values,
// with an exposure slider, a switcher over the file's layers (the beauty image and each
// AOV: direct, indirect, caustic, albedo, normal, depth...) and zoom with nearest-neighbour
// pixels (1:1 shows one image pixel per CSS pixel, larger zooms show square pixels, never
// a blurred stretch).

import { srgb8 } from "../display.js";
import { h, setAttr, setText } from "../dom.js";
import { decodeExr, type ExrImage } from "../exr.js";

/** The layer of channels without a "layer." prefix (R, G, B, A). */
const BEAUTY = "beauty";

const ZOOMS: { value: string; label: string }[] = [
  { value: "fit", label: "Fit" },
  { value: "1", label: "1:1" },
  { value: "2", label: "2×" },
  { value: "4", label: "4×" },
  { value: "8", label: "8×" },
];

/** One layer: its name and its channels' suffixes in the file ("R", "G", "B"; "X", "Y", "Z"; "Z"). */
interface Layer {
  name: string;
  channels: Map<string, Float32Array>;
}

/** Groups the channels by the part of their name before the last dot. */
export function layersOf(img: ExrImage): Layer[] {
  const layers = new Map<string, Layer>();
  for (const [full, values] of img.channels) {
    const dot = full.lastIndexOf(".");
    const name = dot < 0 ? BEAUTY : full.slice(0, dot);
    const suffix = full.slice(dot + 1);
    if (!layers.has(name)) layers.set(name, { name, channels: new Map() });
    layers.get(name)!.channels.set(suffix, values);
  }
  // The beauty image first, the AOVs in the file's (alphabetical) order.
  return [...layers.values()].sort((a, b) => Number(b.name === BEAUTY) - Number(a.name === BEAUTY));
}

/**
 * The layer's display values for each of R, G, B: colour layers and single channels are
 * radiance-like and scaled by 2^exposure; a vector layer (X, Y, Z: the normal) is shown
 * as (v + 1) / 2, and a lone Z (depth) and the samples layer (camera samples a pixel,
 * samples.Y) over the image's largest value, neither exposed: they are not light. The
 * bias layer (the photon estimates' estimated bias, signed: docs/error-estimate.md) is
 * shown by its magnitude over the image's largest, not exposed either.
 */
function displayChannels(layer: Layer, exposure: number): { rgb: Float32Array[]; scale: number; offset: number; srgb: boolean } {
  const c = layer.channels;
  if (layer.name === "bias" && c.has("R") && c.has("G") && c.has("B")) {
    const rgb = [c.get("R")!, c.get("G")!, c.get("B")!].map((ch) => ch.map(Math.abs));
    return { rgb, scale: overLargest(rgb), offset: 0, srgb: false };
  }
  if (c.has("R") && c.has("G") && c.has("B")) return { rgb: [c.get("R")!, c.get("G")!, c.get("B")!], scale: 2 ** exposure, offset: 0, srgb: true };
  if (c.has("X") && c.has("Y") && c.has("Z")) return { rgb: [c.get("X")!, c.get("Y")!, c.get("Z")!], scale: 0.5, offset: 0.5, srgb: false };
  const only = [...c.values()][0]!;
  if (c.size === 1 && (c.has("Z") || layer.name === "samples")) return { rgb: [only, only, only], scale: overLargest([only]), offset: 0, srgb: false };
  return { rgb: [only, only, only], scale: 2 ** exposure, offset: 0, srgb: true };
}

/** The scale that brings the largest finite value of the channels to 1 (0 when none is positive). */
function overLargest(channels: Float32Array[]): number {
  let max = 0;
  for (const ch of channels) for (const v of ch) if (Number.isFinite(v) && v > max) max = v;
  return max > 0 ? 1 / max : 0;
}

export class ImageViewer {
  readonly element: HTMLElement;
  private readonly canvas = h("canvas", { class: "viewer__canvas", "data-testid": "final-canvas" });
  private readonly exposure = h("input", {
    id: "viewer-exposure",
    type: "range",
    min: "-8",
    max: "8",
    step: "0.5",
    value: "0",
    class: "viewer__slider",
    "data-testid": "exposure-slider",
  });
  private readonly exposureValue = h("output", { for: "viewer-exposure", class: "mono viewer__ev", "data-testid": "exposure-value" }, "+0 EV");
  private readonly layerSelect = h("select", { id: "viewer-layer", class: "input", "data-testid": "layer-select" });
  private readonly zoomSelect = h(
    "select",
    { id: "viewer-zoom", class: "input", "data-testid": "zoom-select" },
    ...ZOOMS.map((z) => h("option", { value: z.value }, z.label)),
  );
  private readonly status = h("p", { class: "muted viewer__status", "aria-live": "polite", "data-testid": "viewer-status" });
  private readonly frame = h("div", { class: "viewer__frame" }, this.canvas);
  private layers: Layer[] = [];
  private width = 0;
  private height = 0;
  private url = "";

  constructor() {
    this.element = h(
      "div",
      { class: "viewer" },
      h(
        "div",
        { class: "viewer__controls" },
        h("label", { for: "viewer-layer", class: "inline-form__label" }, "Layer"),
        this.layerSelect,
        h("label", { for: "viewer-exposure", class: "inline-form__label" }, "Exposure"),
        this.exposure,
        this.exposureValue,
        h("label", { for: "viewer-zoom", class: "inline-form__label" }, "Zoom"),
        this.zoomSelect,
      ),
      this.status,
      this.frame,
    );
    this.exposure.addEventListener("input", () => this.draw());
    this.layerSelect.addEventListener("change", () => this.draw());
    this.zoomSelect.addEventListener("change", () => this.applyZoom());
  }

  /** Reads and shows the EXR at url (once per url). */
  async load(url: string): Promise<void> {
    if (url === this.url) return;
    this.url = url;
    setText(this.status, "Reading image.exr…");
    setAttr(this.element, "data-ready", null);
    try {
      const res = await fetch(url, { credentials: "same-origin" });
      if (!res.ok) throw new Error(`${res.status} ${res.statusText}`);
      const img = await decodeExr(await res.arrayBuffer());
      if (url !== this.url) return;
      this.width = img.width;
      this.height = img.height;
      this.canvas.width = img.width;
      this.canvas.height = img.height;
      this.layers = layersOf(img);
      this.layerSelect.replaceChildren(...this.layers.map((l) => h("option", { value: l.name }, l.name)));
      setText(this.status, "");
      this.applyZoom();
      this.draw();
      setAttr(this.element, "data-ready", "true");
    } catch (err) {
      setText(this.status, `Could not show image.exr: ${err instanceof Error ? err.message : String(err)}`);
    }
  }

  private applyZoom(): void {
    const zoom = this.zoomSelect.value;
    this.frame.classList.toggle("is-fit", zoom === "fit");
    this.canvas.style.width = zoom === "fit" ? "" : `${this.width * Number(zoom)}px`;
    this.canvas.style.height = zoom === "fit" ? "" : `${this.height * Number(zoom)}px`;
    if (zoom === "fit" && this.width && this.height) this.canvas.style.aspectRatio = `${this.width} / ${this.height}`;
  }

  private draw(): void {
    const layer = this.layers.find((l) => l.name === this.layerSelect.value) ?? this.layers[0];
    const ctx = this.canvas.getContext("2d");
    if (!layer || !ctx) return;
    const ev = Number(this.exposure.value);
    setText(this.exposureValue, `${ev >= 0 ? "+" : ""}${ev} EV`);
    const { rgb, scale, offset, srgb } = displayChannels(layer, ev);
    const out = ctx.createImageData(this.width, this.height);
    const px = out.data;
    for (let i = 0; i < this.width * this.height; i++) {
      for (let c = 0; c < 3; c++) {
        const v = rgb[c]![i]! * scale + offset;
        px[4 * i + c] = srgb ? srgb8(v) : Math.round(Math.min(1, Math.max(0, v)) * 255);
      }
      px[4 * i + 3] = 255;
    }
    ctx.putImageData(out, 0, 0);
    setAttr(this.canvas, "data-layer", layer.name);
    setAttr(this.canvas, "data-exposure", String(ev));
  }
}
