// The error-against-time chart: an inline SVG with a logarithmic y axis, one line for the
// estimated error (an estimate made without a reference, each point with a bar over its 95%
// interval) and one for the RMSE against the scene's reference image, each point a finished
// round.

import { h, svg } from "../dom.js";
import { formatDuration, formatEstimate } from "../format.js";
import type { Job, RoundReport } from "../types.js";

const W = 640;
const H = 260;
const M = { left: 64, right: 20, top: 16, bottom: 46 };

interface Point {
  t: number;
  v: number;
  round: number;
  // The 95% interval about v, for an estimate that has one.
  low?: number;
  high?: number;
}

interface Series {
  name: string;
  className: string;
  points: Point[];
}

function series(
  rounds: readonly RoundReport[],
  name: string,
  className: string,
  pick: (r: RoundReport) => number | undefined,
  interval?: (r: RoundReport) => [number | undefined, number | undefined],
): Series {
  const points: Point[] = [];
  const positive = (v: number | undefined): v is number => v !== undefined && Number.isFinite(v) && v > 0;
  for (const r of rounds) {
    const v = pick(r);
    if (!positive(v)) continue;
    const p: Point = { t: r.elapsedSeconds ?? 0, v, round: r.round ?? points.length + 1 };
    const [low, high] = interval?.(r) ?? [undefined, undefined];
    if (positive(low) && positive(high)) Object.assign(p, { low, high });
    points.push(p);
  }
  return { name, className, points };
}

/** About n round steps (1, 2 or 5 times a power of ten) covering [0, max]. */
function linearTicks(max: number, n: number): number[] {
  if (max <= 0) return [0];
  const raw = max / n;
  const mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((k) => k * mag).find((s) => s >= raw) ?? 10 * mag;
  const ticks: number[] = [];
  const count = Math.ceil(max / step - 1e-9);
  for (let i = 0; i <= count; i++) ticks.push(Number((i * step).toPrecision(12)));
  return ticks;
}

function logTicks(lo: number, hi: number): number[] {
  const ticks: number[] = [];
  const decades = hi - lo;
  const mult = decades <= 1 ? [1, 2, 5] : decades <= 3 ? [1, 3] : [1];
  for (let d = Math.floor(lo); d <= Math.ceil(hi); d++) {
    for (const m of mult) {
      const v = m * 10 ** d;
      const l = Math.log10(v);
      if (l >= lo - 1e-9 && l <= hi + 1e-9) ticks.push(v);
    }
  }
  return ticks;
}

/** A y tick: 0.1, 0.02, 5e-4. */
function tickLabel(v: number): string {
  if (v >= 1e-3 && v < 1e4) return String(Number(v.toPrecision(3)));
  return v.toExponential(0);
}

export class ErrorChart {
  readonly element: HTMLElement;
  private readonly body: HTMLDivElement;
  private sig = "";

  constructor() {
    this.body = h("div", { class: "chart__body" });
    this.element = h("figure", { class: "chart", "data-testid": "error-chart" }, this.body);
  }

  update(job: Job): void {
    const rounds = job.rounds ?? [];
    const sig = JSON.stringify(
      rounds.map((r) => [r.round, r.elapsedSeconds, r.errorEstimate, r.errorEstimateLow, r.errorEstimateHigh, r.referenceRmse]),
    );
    if (sig === this.sig) return;
    this.sig = sig;

    const all = [
      series(rounds, "Estimated error", "chart__line--estimate", (r) => r.errorEstimate, (r) => [r.errorEstimateLow, r.errorEstimateHigh]),
      series(rounds, "Error against reference", "chart__line--reference", (r) => r.referenceRmse),
    ].filter((s) => s.points.length > 0);

    if (rounds.length < 2 || all.length === 0) {
      this.element.dataset["empty"] = "true";
      this.body.replaceChildren(
        h(
          "p",
          { class: "empty" },
          rounds.length < 2
            ? `The error curve appears once two rounds have finished (${rounds.length} so far).`
            : "No estimated error was reported.",
        ),
      );
      return;
    }
    delete this.element.dataset["empty"];
    this.body.replaceChildren(this.draw(all), this.legend(all));
  }

  private legend(all: Series[]): HTMLElement {
    return h(
      "ul",
      { class: "chart__legend" },
      ...all.map((s) => h("li", null, h("span", { class: `chart__swatch ${s.className}`, "aria-hidden": "true" }), s.name)),
    );
  }

  private draw(all: Series[]): SVGSVGElement {
    const points = all.flatMap((s) => s.points);
    const tMax = Math.max(...points.map((p) => p.t), 1e-3);
    let lo = Math.log10(Math.min(...points.map((p) => p.low ?? p.v)));
    let hi = Math.log10(Math.max(...points.map((p) => p.high ?? p.v)));
    // Round out to whole decades, at least one decade tall.
    lo = Math.floor(lo + 1e-9);
    hi = Math.ceil(hi - 1e-9);
    if (hi - lo < 1) hi = lo + 1;

    const xTicks = linearTicks(tMax, 5);
    const xMax = Math.max(xTicks[xTicks.length - 1]!, tMax);
    const pw = W - M.left - M.right;
    const ph = H - M.top - M.bottom;
    const x = (t: number) => M.left + (t / xMax) * pw;
    const y = (v: number) => M.top + (1 - (Math.log10(v) - lo) / (hi - lo)) * ph;

    const root = svg("svg", {
      class: "chart__svg",
      viewBox: `0 0 ${W} ${H}`,
      role: "img",
      "aria-label": `Error against time over ${points.length} measurements, logarithmic scale`,
      preserveAspectRatio: "xMidYMid meet",
    });

    const grid = svg("g", { class: "chart__grid" });
    const axes = svg("g", { class: "chart__axes" });
    for (const v of logTicks(lo, hi)) {
      const yy = y(v);
      grid.append(svg("line", { x1: M.left, x2: W - M.right, y1: yy, y2: yy }));
      axes.append(svg("text", { x: M.left - 8, y: yy, "text-anchor": "end", "dominant-baseline": "middle" }, tickLabel(v)));
    }
    for (const t of xTicks) {
      const xx = x(t);
      grid.append(svg("line", { x1: xx, x2: xx, y1: M.top, y2: M.top + ph }));
      axes.append(svg("text", { x: xx, y: M.top + ph + 18, "text-anchor": "middle" }, t === 0 ? "0" : formatDuration(t)));
    }
    axes.append(
      svg("line", { class: "chart__axis", x1: M.left, x2: W - M.right, y1: M.top + ph, y2: M.top + ph }),
      svg("line", { class: "chart__axis", x1: M.left, x2: M.left, y1: M.top, y2: M.top + ph }),
      svg("text", { class: "chart__label", x: M.left + pw / 2, y: H - 6, "text-anchor": "middle" }, "Elapsed time"),
      svg(
        "text",
        { class: "chart__label", x: 14, y: M.top + ph / 2, "text-anchor": "middle", transform: `rotate(-90 14 ${M.top + ph / 2})` },
        "RMSE (log scale)",
      ),
    );
    root.append(grid, axes);

    for (const s of all) {
      const g = svg("g", { class: `chart__series ${s.className}` });
      if (s.points.length > 1) {
        const d = s.points.map((p, i) => `${i ? "L" : "M"}${x(p.t).toFixed(1)},${y(p.v).toFixed(1)}`).join(" ");
        g.append(svg("path", { class: "chart__path", d }));
      }
      for (const p of s.points) {
        if (p.low !== undefined && p.high !== undefined) {
          const xx = x(p.t).toFixed(1);
          g.append(svg("line", { class: "chart__interval", x1: xx, x2: xx, y1: y(p.low).toFixed(1), y2: y(p.high).toFixed(1) }));
        }
        g.append(
          svg(
            "circle",
            { class: "chart__point", cx: x(p.t).toFixed(1), cy: y(p.v).toFixed(1), r: 3.5 },
            svg("title", null, `${s.name}, round ${p.round}: ${formatEstimate(p.v, p.low, p.high)} at ${formatDuration(p.t)}`),
          ),
        );
      }
      root.append(g);
    }
    return root;
  }
}
