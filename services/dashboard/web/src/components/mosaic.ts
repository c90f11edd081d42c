// The live tile mosaic: the image the job would deliver if it stopped now (the mean of
// every round so far, accumulation.ts), drawn on a canvas as each tile finishes, under a
// box per render tile at its rectangle (in percent of the image, so the box scales
// freely): dimmed until the current round's tile is done, outlined while leased. The
// pixels are linear values clipped to sRGB, as the final-image viewer shows them at 0 EV.

import { RunningImage, tileValues, type Rect } from "../accumulation.js";
import { blobUrl } from "../api.js";
import { ARTIFACT } from "../contract.gen.js";
import { srgb8 } from "../display.js";
import { h, setAttr, setText } from "../dom.js";
import { decodeExr, type ExrImage } from "../exr.js";
import { formatNumber } from "../format.js";
import type { Job, PixelRect, Task, TaskState } from "../types.js";
import { artifact } from "../types.js";
import { workerName } from "../workernames.js";

/** A rectangle of the image and the current round's task at it. */
interface Cell {
  rect: Required<PixelRect>;
  task?: Task;
}

/** Fetches at once at most: a job page opened late reads one composite, not every tile. */
const MAX_FETCHES = 6;

function rectOf(task: Task): Required<PixelRect> | undefined {
  const r = task.renderTile?.rect;
  if (!r || !r.width || !r.height) return undefined;
  return { x: r.x ?? 0, y: r.y ?? 0, width: r.width, height: r.height };
}

const STATE_CLASS: Partial<Record<TaskState, string>> = {
  TASK_STATE_LEASED: "is-leased",
  TASK_STATE_SUCCEEDED: "is-done",
  TASK_STATE_FAILED: "is-failed",
  TASK_STATE_CANCELLED: "is-cancelled",
};

/** A blob to read into the running image: a round's accumulation or a newer tile. */
interface Source {
  key: string;
  digest: string;
  name: string;
  apply: (img: ExrImage) => boolean;
}

export class Mosaic {
  readonly element: HTMLElement;
  private readonly box: HTMLDivElement;
  private readonly canvas: HTMLCanvasElement;
  private readonly caption: HTMLElement;
  private readonly slots = new Map<string, HTMLDivElement>();
  private size = "";
  private image?: RunningImage;
  /** Blobs being read, by Source.key, and those that could not be read. */
  private readonly reading = new Set<string>();
  private readonly unreadable = new Map<string, string>();
  private queue: Source[] = [];
  private drawPending = false;
  /** What the canvas shows, and the rectangles of it to draw again (undefined: all). */
  private pixels?: ImageData;
  private dirty: Rect[] | undefined = [];

  constructor() {
    this.canvas = h("canvas", { class: "mosaic__canvas", "data-testid": "mosaic-canvas" });
    this.box = h(
      "div",
      { class: "mosaic", "data-testid": "mosaic", role: "img", "aria-label": "The image so far" },
      this.canvas,
    );
    this.caption = h("figcaption", { class: "mosaic__caption" });
    this.element = h("figure", { class: "mosaic-figure" }, this.box, this.caption);
  }

  /** Shows the render tiles among tasks; complete says whether they are all the job's. */
  update(job: Job, tasks: readonly Task[], complete = true): void {
    const width = job.width ?? 0;
    const height = job.height ?? 0;
    const size = `${width}x${height}`;
    if (size !== this.size && width > 0 && height > 0) {
      this.size = size;
      this.box.style.aspectRatio = `${width} / ${height}`;
      // Fit the viewport's height too: never taller than 70vh.
      this.box.style.maxWidth = `min(100%, calc(70vh * ${width / height}), ${Math.max(width * 4, 480)}px)`;
      this.box.dataset["width"] = String(width);
      this.box.dataset["height"] = String(height);
      this.canvas.width = width;
      this.canvas.height = height;
      this.image = new RunningImage(width, height);
      this.pixels = undefined;
      this.dirty = undefined;
      this.queue = [];
    }

    // Tasks arrive in plan order, so later rounds come later: the last one wins.
    let round = 0;
    for (const t of tasks) if (t.renderTile && (t.round ?? 0) > round) round = t.round ?? 0;
    const current = new Map<string, Cell>();
    for (const t of tasks) {
      const rect = rectOf(t);
      if (!rect) continue;
      const key = `${rect.x},${rect.y},${rect.width},${rect.height}`;
      const cell: Cell = current.get(key) ?? { rect };
      if ((t.round ?? 0) === round) cell.task = t;
      current.set(key, cell);
    }
    this.collect(tasks);

    let done = 0;
    const order: HTMLElement[] = [this.canvas];
    for (const [key, cell] of current) {
      let slot = this.slots.get(key);
      if (!slot) {
        const { x, y, width: w, height: hgt } = cell.rect;
        slot = h("div", { class: "mosaic__slot" });
        if (width > 0 && height > 0) {
          slot.style.left = `${(100 * x) / width}%`;
          slot.style.top = `${(100 * y) / height}%`;
          slot.style.width = `${(100 * w) / width}%`;
          slot.style.height = `${(100 * hgt) / height}%`;
        }
        this.slots.set(key, slot);
      }
      const state = cell.task?.state;
      if (state === "TASK_STATE_SUCCEEDED") done++;
      const cls = `mosaic__slot ${(state && STATE_CLASS[state]) ?? "is-pending"}`;
      if (slot.className !== cls) slot.className = cls;
      const r = cell.rect;
      setAttr(
        slot,
        "title",
        `Tile ${r.x},${r.y} ${r.width}×${r.height}` +
          (cell.task ? ` · ${(state ?? "").replace("TASK_STATE_", "").toLowerCase()}` : "") +
          (cell.task?.workerId ? ` · ${workerName(cell.task.workerId)}` : ""),
      );
      order.push(slot);
    }
    for (const key of [...this.slots.keys()]) if (!current.has(key)) this.slots.delete(key);
    const have = this.box.children;
    let same = have.length === order.length;
    for (let i = 0; same && i < order.length; i++) same = have[i] === order[i];
    if (!same) this.box.replaceChildren(...order);

    const unreadable = this.unreadable.size ? ` · ${this.unreadable.size} could not be read: ${[...this.unreadable.values()][0]}` : "";
    setText(
      this.caption,
      current.size === 0
        ? "No render tiles yet."
        : `Round ${round || 1} · ${formatNumber(done)} of ${formatNumber(current.size)} tiles${complete ? "" : " read so far"} · ${width}×${height} px · the mean of every round so far${unreadable}`,
    );
  }

  /**
   * Queues what the running image lacks: the newest composite's accumulation if it is newer
   * than the one held, and every finished tile of a later round.
   */
  private collect(tasks: readonly Task[]): void {
    const image = this.image;
    if (!image) return;
    let base: { round: number; digest: string } | undefined;
    for (const t of tasks) {
      if (t.phase !== "PHASE_COMPOSITE" || t.state !== "TASK_STATE_SUCCEEDED") continue;
      const acc = artifact(t.outputs, ARTIFACT.ACCUMULATION_EXR);
      const r = t.round ?? 1;
      if (acc?.digest && r > (base?.round ?? image.baseRound)) base = { round: r, digest: acc.digest };
    }
    const sources: Source[] = [];
    if (base) {
      const { round, digest } = base;
      sources.push({ key: `acc:${round}`, digest, name: ARTIFACT.ACCUMULATION_EXR, apply: (img) => image.setBase(round, img) && this.changed() });
    }
    const after = base?.round ?? image.baseRound;
    for (const t of tasks) {
      const rect = rectOf(t);
      const round = t.round ?? 1;
      const exr = t.state === "TASK_STATE_SUCCEEDED" ? artifact(t.outputs, ARTIFACT.TILE_EXR) : undefined;
      if (!rect || !exr?.digest || round <= after || image.has(t.id, round)) continue;
      sources.push({
        key: `tile:${t.id}`,
        digest: exr.digest,
        name: ARTIFACT.TILE_EXR,
        apply: (img) => image.addTile(t.id, tileValues(img, round, rect)) && this.changed(rect),
      });
    }
    this.queue = sources.filter((s) => !this.reading.has(s.key) && !this.unreadable.has(s.key));
    this.pump();
  }

  private pump(): void {
    while (this.reading.size < MAX_FETCHES && this.queue.length > 0) {
      const source = this.queue.shift()!;
      this.reading.add(source.key);
      const image = this.image;
      void this.read(source).finally(() => {
        this.reading.delete(source.key);
        if (image === this.image) this.pump();
        this.syncState();
      });
    }
    this.syncState();
  }

  private async read(source: Source): Promise<void> {
    const image = this.image;
    try {
      const res = await fetch(blobUrl(source.digest, source.name), { credentials: "same-origin" });
      if (!res.ok) throw new Error(`${source.name}: ${res.status} ${res.statusText}`);
      const img = await decodeExr(await res.arrayBuffer());
      if (image === this.image) source.apply(img);
    } catch (err) {
      this.unreadable.set(source.key, err instanceof Error ? err.message : String(err));
    }
  }

  /** What the tests (and a curious user) can read off the canvas. */
  private syncState(): void {
    setAttr(this.canvas, "data-base-round", String(this.image?.baseRound ?? 0));
    setAttr(this.canvas, "data-reading", String(this.reading.size + this.queue.length));
  }

  /** Marks rect (undefined: the whole image) to draw again at the next frame. */
  private changed(rect?: Rect): true {
    if (!rect) this.dirty = undefined;
    else this.dirty?.push(rect);
    if (!this.drawPending) {
      this.drawPending = true;
      requestAnimationFrame(() => {
        this.drawPending = false;
        this.draw();
      });
    }
    return true;
  }

  private draw(): void {
    const image = this.image;
    const ctx = this.canvas.getContext("2d");
    if (!image || !ctx) return;
    const { width, height } = image;
    this.pixels ??= ctx.createImageData(width, height);
    const rects = this.dirty ?? [{ x: 0, y: 0, width, height }];
    this.dirty = [];
    const px = this.pixels.data;
    const rgb = new Float32Array(3);
    for (const r of rects) {
      for (let y = r.y; y < r.y + r.height; y++) {
        for (let x = r.x; x < r.x + r.width; x++) {
          const p = y * width + x;
          image.meanAt(p, rgb);
          if (Number.isNaN(rgb[0])) continue; // nothing yet: clear
          for (let c = 0; c < 3; c++) px[4 * p + c] = srgb8(rgb[c]!);
          px[4 * p + 3] = 255;
        }
      }
      ctx.putImageData(this.pixels, 0, 0, r.x, r.y, r.width, r.height);
    }
    setAttr(this.canvas, "data-drawn", String(Number(this.canvas.dataset["drawn"] ?? 0) + 1));
  }
}
