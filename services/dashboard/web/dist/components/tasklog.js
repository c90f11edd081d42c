// A task's log (the worker's "task.log": the lines it logged for one attempt), read from
// GET /api/blobs/{digest}?name=task.log (text/plain) and shown as text, never as HTML.
// One panel under the task table; a task row's "Log" button (logButtons) opens it on that
// task's log, and again closes it.
import { blobUrl } from "../api.js";
import { ARTIFACT } from "../contract.gen.js";
import { h, setAttr, setText } from "../dom.js";
import { artifact } from "../types.js";
/** The logs a task has: its success's (among its outputs) and its last failed attempt's. */
export function taskLogs(t) {
    const out = [];
    const done = artifact(t.outputs, ARTIFACT.TASK_LOG);
    if (done)
        out.push({ label: "Log", which: "done", log: done });
    if (t.log?.digest)
        out.push({ label: done ? "Failed attempt's log" : "Log", which: "failed", log: t.log });
    return out;
}
/** Fills a table cell with a button per log of t; TaskLogPanel.attach handles their clicks. */
export function logButtons(t, td) {
    td.replaceChildren(...taskLogs(t).map((l) => h("button", {
        type: "button",
        class: "button button--small",
        "data-testid": "task-log-button",
        "data-task-id": t.id,
        "data-which": l.which,
        "data-digest": l.log.digest,
        "aria-controls": "task-log",
    }, l.label)));
}
/** The signature of logButtons' cell: it changes when a log appears. */
export function logSig(t) {
    return taskLogs(t)
        .map((l) => `${l.which}:${l.log.digest}`)
        .join(",");
}
export class TaskLogPanel {
    constructor() {
        this.title = h("h3", { class: "task-log__title" });
        this.status = h("p", { class: "muted", "aria-live": "polite" });
        this.text = h("pre", { class: "task-log__text", "data-testid": "task-log-text", tabindex: 0 });
        this.shown = ""; // the digest shown (or being read)
        const close = h("button", { type: "button", class: "button button--small", "data-testid": "task-log-close" }, "Close");
        close.addEventListener("click", () => this.close());
        this.element = h("section", { id: "task-log", class: "task-log", hidden: true, "data-testid": "task-log" }, h("div", { class: "task-log__header" }, this.title, close), this.status, this.text);
    }
    /** Opens the panel from the log buttons inside container (delegated: no per-row listeners). */
    attach(container) {
        container.addEventListener("click", (ev) => {
            const b = ev.target.closest("button[data-testid=task-log-button]");
            if (!b)
                return;
            const digest = b.dataset["digest"] ?? "";
            if (digest === this.shown && !this.element.hidden) {
                this.close();
                return;
            }
            const failed = b.dataset["which"] === "failed";
            void this.show(b.dataset["taskId"] ?? "", digest, failed);
        });
    }
    close() {
        this.shown = "";
        this.element.hidden = true;
        setAttr(this.element, "data-task-id", null);
    }
    async show(taskId, digest, failed) {
        this.shown = digest;
        this.element.hidden = false;
        setAttr(this.element, "data-task-id", taskId);
        setAttr(this.element, "data-ready", null);
        setText(this.title, failed ? `Log of task ${taskId}'s last failed attempt` : `Log of task ${taskId}`);
        setText(this.status, "Reading task.log…");
        this.text.textContent = "";
        try {
            const res = await fetch(blobUrl(digest, ARTIFACT.TASK_LOG), { credentials: "same-origin" });
            if (!res.ok)
                throw new Error(`${res.status} ${res.statusText}`);
            const body = await res.text();
            if (digest !== this.shown)
                return;
            this.text.textContent = body; // text, never markup
            setText(this.status, "");
            setAttr(this.element, "data-ready", "true");
        }
        catch (err) {
            if (digest !== this.shown)
                return;
            setText(this.status, `Could not read task.log: ${err instanceof Error ? err.message : String(err)}`);
        }
    }
}
