// The live tile mosaic: a box of the image's aspect ratio in which every render tile sits
// at its rectangle (in percent of the image, so the box scales freely). A rectangle shows
// its newest finished tile.png; until the current round's tile is done it is dimmed
// (a placeholder, empty before any round finished it), and outlined while leased.

import { blobUrl } from "../api.js";
import { ARTIFACT } from "../contract.gen.js";
import { h, setAttr, setText } from "../dom.js";
import { formatNumber } from "../format.js";
import type { Job, PixelRect, Task, TaskState } from "../types.js";
import { artifact } from "../types.js";
import { workerName } from "../workernames.js";

interface Cell {
  rect: Required<PixelRect>;
  /** The current round's task at this rectangle. */
  current?: Task;
  /** The newest succeeded task at this rectangle with a tile.png. */
  shown?: { task: Task; digest: string };
}

interface CellElements {
  slot: HTMLDivElement;
  img?: HTMLImageElement;
  digest?: string;
}

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

export class Mosaic {
  readonly element: HTMLElement;
  private readonly box: HTMLDivElement;
  private readonly caption: HTMLElement;
  private readonly cells = new Map<string, CellElements>();
  private size = "";

  constructor() {
    this.box = h("div", {
      class: "mosaic",
      "data-testid": "mosaic",
      role: "img",
      "aria-label": "Rendered tiles",
    });
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
    }

    // Tasks arrive in plan order, so later rounds come later: the last one wins.
    let round = 0;
    for (const t of tasks) if (t.renderTile && (t.round ?? 0) > round) round = t.round ?? 0;
    const cells = new Map<string, Cell>();
    for (const t of tasks) {
      const rect = rectOf(t);
      if (!rect) continue;
      const key = `${rect.x},${rect.y},${rect.width},${rect.height}`;
      let cell = cells.get(key);
      if (!cell) {
        cell = { rect };
        cells.set(key, cell);
      }
      if ((t.round ?? 0) === round) cell.current = t;
      const png = t.state === "TASK_STATE_SUCCEEDED" ? artifact(t.outputs, ARTIFACT.TILE_PNG) : undefined;
      if (png?.digest) cell.shown = { task: t, digest: png.digest };
    }

    let done = 0;
    const order: HTMLElement[] = [];
    for (const [key, cell] of cells) {
      let el = this.cells.get(key);
      if (!el) {
        const { x, y, width: w, height: hgt } = cell.rect;
        const slot = h("div", { class: "mosaic__slot" });
        if (width > 0 && height > 0) {
          slot.style.left = `${(100 * x) / width}%`;
          slot.style.top = `${(100 * y) / height}%`;
          slot.style.width = `${(100 * w) / width}%`;
          slot.style.height = `${(100 * hgt) / height}%`;
        }
        el = { slot };
        this.cells.set(key, el);
      }
      const state = cell.current?.state;
      if (state === "TASK_STATE_SUCCEEDED") done++;
      const cls = `mosaic__slot ${(state && STATE_CLASS[state]) ?? "is-pending"}`;
      if (el.slot.className !== cls) el.slot.className = cls;
      const r = cell.rect;
      setAttr(
        el.slot,
        "title",
        `Tile ${r.x},${r.y} ${r.width}×${r.height}` +
          (cell.current ? ` · ${(state ?? "").replace("TASK_STATE_", "").toLowerCase()}` : "") +
          (cell.current?.workerId ? ` · ${workerName(cell.current.workerId)}` : ""),
      );
      if (cell.shown && cell.shown.digest !== el.digest) {
        if (!el.img) {
          el.img = h("img", { class: "mosaic__tile", "data-testid": "tile", alt: "", decoding: "async" });
          el.slot.append(el.img);
        }
        el.digest = cell.shown.digest;
        el.img.src = blobUrl(cell.shown.digest, ARTIFACT.TILE_PNG);
        el.img.dataset["taskId"] = cell.shown.task.id;
        el.img.dataset["round"] = String(cell.shown.task.round ?? 0);
      }
      order.push(el.slot);
    }
    for (const key of [...this.cells.keys()]) if (!cells.has(key)) this.cells.delete(key);
    const have = this.box.children;
    let same = have.length === order.length;
    for (let i = 0; same && i < order.length; i++) same = have[i] === order[i];
    if (!same) this.box.replaceChildren(...order);

    setText(
      this.caption,
      cells.size === 0
        ? "No render tiles yet."
        : `Round ${round || 1} · ${formatNumber(done)} of ${formatNumber(cells.size)} tiles${complete ? "" : " read so far"} · ${width}×${height} px`,
    );
  }
}
