// The workers (#/workers): host, state, current task, tasks done and failed, last
// heartbeat and cores, live from /api/events ("workers", every 2 s: the first page of
// them); "Show more" adds the next pages, as they were when asked for.

import { LiveStream, api } from "../api.js";
import { DataTable } from "../components/table.js";
import { badgeCell, timeElement } from "../components/widgets.js";
import { frameScheduler, h, setText } from "../dom.js";
import { enumKey, formatNumber, formatRelative, parseTime, workerStateLabel } from "../format.js";
import { jobHref, type Page } from "../router.js";
import type { WorkerInfo, WorkerPage } from "../types.js";
import { rememberWorkers } from "../workernames.js";

/** A task id is "{job_id}.{index}". */
function jobOfTask(taskId: string): string {
  const dot = taskId.lastIndexOf(".");
  return dot > 0 ? taskId.slice(0, dot) : taskId;
}

export function workersPage(): Page {
  let live: WorkerInfo[] = []; // the first page, live
  let more: WorkerInfo[] = []; // the pages after it that "Show more" loaded
  let next = ""; // the token of the page after the last one shown
  let workers: WorkerInfo[] = [];
  let received = false;
  let now = Date.now();

  /** The first page, then the loaded ones (without workers the first page now holds). */
  function merge(): void {
    const seen = new Set(live.map((w) => w.id));
    workers = [...live, ...more.filter((w) => !seen.has(w.id))];
  }

  const table = new DataTable<WorkerInfo>({
    caption: "Workers, by registration time",
    captionHidden: true,
    className: "table--workers",
    key: (w) => w.id,
    rowAttrs: (w) => ({ "data-testid": "worker-row", "data-worker-id": w.id, "data-state": w.state ?? "WORKER_STATE_UNSPECIFIED" }),
    empty: "Loading workers…",
    columns: [
      {
        header: "Host",
        sig: (w) => `${w.hostname}|${w.id}|${w.version}`,
        render: (w, td) =>
          td.replaceChildren(
            h("span", { class: "table__primary" }, w.hostname || "(unknown host)"),
            h("span", { class: "table__secondary mono", title: w.version ? `version ${w.version}` : null }, w.id),
          ),
      },
      {
        header: "State",
        sig: (w) => w.state ?? "",
        render: (w, td) => badgeCell(td, workerStateLabel(w.state), enumKey(w.state, "WORKER_STATE_"), { "data-testid": "worker-state" }),
      },
      {
        header: "Current task",
        className: "mono",
        sig: (w) => w.currentTaskId ?? "",
        render: (w, td) =>
          td.replaceChildren(
            w.currentTaskId ? h("a", { href: jobHref(jobOfTask(w.currentTaskId)) }, w.currentTaskId) : h("span", { class: "muted" }, "—"),
          ),
      },
      { header: "Tasks done", className: "num", text: (w) => formatNumber(w.tasksDone) },
      { header: "Failures", className: "num", text: (w) => formatNumber(w.tasksFailed) },
      {
        header: "Last heartbeat",
        className: "num",
        sig: (w, t) => formatRelative(parseTime(w.lastHeartbeat), t),
        render: (w, td, t) => td.replaceChildren(timeElement(w.lastHeartbeat, (ms) => formatRelative(ms, t))),
      },
      { header: "Cores", className: "num", text: (w) => String(w.cores ?? 0) },
    ],
  });

  const summary = h("p", { class: "page__summary muted", "aria-live": "polite" }, "Loading workers…");
  const moreButton = h("button", { type: "button", class: "button", hidden: true, "data-testid": "workers-more" }, "Show more");
  moreButton.addEventListener("click", async () => {
    moreButton.disabled = true;
    try {
      const page = await api.workers(next);
      more = [...more, ...(page.workers ?? [])];
      next = page.nextPageToken ?? "";
      merge();
      render.schedule();
    } finally {
      moreButton.disabled = false;
    }
  });
  const element = h(
    "section",
    { class: "page", "aria-labelledby": "workers-title" },
    h("div", { class: "page__header" }, h("div", null, h("h1", { id: "workers-title" }, "Workers"), summary)),
    h("div", { class: "card card--flush table-wrap" }, table.element),
    h("div", { class: "table-more" }, moreButton),
  );

  const render = frameScheduler(() => {
    table.update(workers, now);
    if (!received) return;
    table.setEmptyText("No worker has registered yet.");
    const count = (s: string) => workers.filter((w) => w.state === s).length;
    const cores = workers.filter((w) => w.state !== "WORKER_STATE_LOST").reduce((n, w) => n + (w.cores ?? 0), 0);
    setText(
      summary,
      `${workers.length}${next ? "+" : ""} ${workers.length === 1 ? "worker" : "workers"} · ${count("WORKER_STATE_BUSY")} busy · ` +
        `${count("WORKER_STATE_IDLE")} idle · ${count("WORKER_STATE_LOST")} lost · ${cores} cores online` +
        (next ? " (of those shown)" : ""),
    );
    moreButton.hidden = !next;
  });

  const stream = new LiveStream("api/events", {
    events: {
      workers: (data: WorkerPage) => {
        live = data.workers ?? [];
        rememberWorkers(live);
        // The first page's token names the page after it; once more pages are loaded,
        // the last of them says where to go on.
        if (!more.length) next = data.nextPageToken ?? "";
        merge();
        received = true;
        now = Date.now();
        render.schedule();
      },
    },
    probe: () => api.workers(),
  });

  return {
    element,
    title: "Workers",
    tick(t) {
      now = t;
      render.schedule();
    },
    destroy() {
      stream.close();
      render.cancel();
    },
  };
}
