// One job (#/jobs/{id}): header and actions (priority, cancel, requeue, delete; retry on a
// failed task's row), progress figures, the live
// tile mosaic, phases, plan, error chart, final image (components/viewer.ts), blocked workers and the task table,
// live from /api/jobs/{id}/events. The server sends the job with the first page of its
// tasks; the page reads the next pages itself (/api/jobs/{id}/tasks), by itself up to
// AUTO_LOAD_TASKS and then a page per "Show more", so a job of 95,000 tasks is never
// read whole at once. Once the job has ended the page follows it on /api/events (the job
// list): a requeue or retry from anywhere reopens its stream, and a delete says so.
import { ApiError, LiveStream, api, blobUrl } from "../api.js";
import { ErrorChart } from "../components/chart.js";
import { Mosaic } from "../components/mosaic.js";
import { ImageViewer } from "../components/viewer.js";
import { PhaseList } from "../components/phases.js";
import { TaskLogPanel, logButtons, logSig } from "../components/tasklog.js";
import { DataTable } from "../components/table.js";
import { badge, badgeCell, progressBar, timeElement, updateBadge, updateProgressBar } from "../components/widgets.js";
import { ARTIFACT } from "../contract.gen.js";
import { frameScheduler, h, setAttr, setText } from "../dom.js";
import { enumKey, formatCompact, formatDuration, formatError, formatEstimate, formatEta, formatRelative, failureLabel, jobStateLabel, phaseShort, taskStateLabel, } from "../format.js";
import { jobElapsed, jobEta, jobProgress } from "../progress.js";
import { artifact, jobEnded } from "../types.js";
import { progressLabel } from "./jobs.js";
import { onWorkerNames, workerName } from "../workernames.js";
/** Rows the task table shows at first, and adds per "Show more". */
const PAGE_ROWS = 500;
/** Tasks the page reads by itself (pages of the server's 500); past this, "Show more" reads a page more. */
const AUTO_LOAD_TASKS = 5000;
const TASK_STATES = [
    "TASK_STATE_WAITING",
    "TASK_STATE_QUEUED",
    "TASK_STATE_LEASED",
    "TASK_STATE_SUCCEEDED",
    "TASK_STATE_FAILED",
    "TASK_STATE_CANCELLED",
];
function errorMessage(err) {
    return err instanceof ApiError || err instanceof Error ? err.message : String(err);
}
function card(title, ...children) {
    const id = `card-${title.toLowerCase().replace(/[^a-z]+/g, "-")}`;
    return h("section", { class: "card", "aria-labelledby": id }, h("h2", { id, class: "card__title" }, title), ...children);
}
/** A figure in the stats strip: a label and a value that updates in place. */
function stat(label) {
    const value = h("dd", { class: "stat__value" }, "—");
    return { element: h("div", { class: "stat" }, h("dt", { class: "stat__label" }, label), value), value };
}
export function jobPage(id) {
    let job = null;
    const tasks = [];
    const byId = new Map();
    // The token of the next page of tasks not read yet ("" once every task is here), and
    // the generation of the list: a page read for an older list is dropped.
    let next = "";
    let generation = 0;
    let loading = false;
    let now = Date.now();
    let stateFilter = "";
    let phaseFilter = "";
    let limit = PAGE_ROWS;
    let priorityDirty = false;
    // ---- header and actions
    const title = h("h1", { class: "job__title" }, "Loading…");
    const stateBadge = badge("…", "unspecified", { "data-testid": "job-state" });
    const idLine = h("p", { class: "job__id mono muted" }, id);
    const priorityInput = h("input", {
        id: "job-priority",
        type: "number",
        min: "-1000",
        max: "1000",
        step: "1",
        value: "0",
        class: "input input--narrow",
        "data-testid": "priority-input",
    });
    const priorityButton = h("button", { type: "submit", class: "button", "data-testid": "priority-submit" }, "Set");
    const priorityForm = h("form", { class: "inline-form", "aria-label": "Priority", novalidate: true }, h("label", { for: "job-priority", class: "inline-form__label" }, "Priority"), priorityInput, priorityButton);
    const cancelButton = h("button", { type: "button", class: "button button--danger", "data-testid": "cancel-button" }, "Cancel job");
    const requeueButton = h("button", { type: "button", class: "button", hidden: true, "data-testid": "requeue-button" }, "Requeue");
    const deleteButton = h("button", { type: "button", class: "button button--danger", "data-testid": "delete-button" }, "Delete job");
    // Hidden until the job is loaded, so that what a button asks ("Cancel the job NAME?") and
    // whether it applies (an ended job has no cancel) are the job's, never a guess from its id.
    const actions = h("div", { class: "page__actions", hidden: true }, priorityForm, cancelButton, requeueButton, deleteButton);
    const notice = h("div", { class: "notice-area" });
    // Why a failed job failed, at the top of the page: the failure kind's label and the error.
    const failureKind = h("strong", { class: "banner__kind", "data-testid": "failure-kind" });
    const failureMessage = h("span", { class: "banner__message", "data-testid": "failure-message" });
    const failureBanner = h("div", { class: "notice notice--error banner", role: "alert", "data-testid": "failure-banner", hidden: true }, failureKind, failureMessage);
    function showNotice(kind, message) {
        notice.replaceChildren(h("div", { class: `notice notice--${kind}`, role: kind === "error" ? "alert" : "status" }, message));
    }
    priorityInput.addEventListener("input", () => {
        priorityDirty = true;
    });
    priorityForm.addEventListener("submit", async (ev) => {
        ev.preventDefault();
        const value = Number(priorityInput.value);
        if (!Number.isInteger(value) || value < -1000 || value > 1000) {
            showNotice("error", "Priority must be a whole number from -1000 to 1000.");
            return;
        }
        priorityButton.disabled = true;
        try {
            const res = await api.setPriority(id, value);
            priorityDirty = false;
            applyJob(res.job);
            showNotice("success", `Priority set to ${res.job.priority ?? 0}.`);
        }
        catch (err) {
            showNotice("error", `Could not set the priority: ${errorMessage(err)}`);
        }
        finally {
            priorityButton.disabled = job ? jobEnded(job) : false;
        }
    });
    cancelButton.addEventListener("click", async () => {
        const name = job?.displayName || id;
        if (!window.confirm(`Cancel the job ${name}? Its running tasks stop, and a cancelled job cannot be resumed.`))
            return;
        cancelButton.disabled = true;
        try {
            const res = await api.cancel(id);
            applyJob(res.job);
            showNotice("success", "The job was cancelled.");
        }
        catch (err) {
            showNotice("error", `Could not cancel the job: ${errorMessage(err)}`);
            cancelButton.disabled = job ? jobEnded(job) : false;
        }
    });
    requeueButton.addEventListener("click", async () => {
        requeueButton.disabled = true;
        try {
            reopened((await api.requeue(id)).job);
            showNotice("success", "The job was requeued: its unfinished tasks are queued again.");
        }
        catch (err) {
            showNotice("error", `Could not requeue the job: ${errorMessage(err)}`);
        }
        finally {
            requeueButton.disabled = false;
        }
    });
    deleteButton.addEventListener("click", async () => {
        const name = job?.displayName || id;
        const running = job && !jobEnded(job) ? " It is cancelled first." : "";
        if (!window.confirm(`Delete the job ${name}? It and its tasks are removed for good.${running}`))
            return;
        deleteButton.disabled = true;
        try {
            await api.deleteJob(id);
            deleted();
            location.hash = "#/";
        }
        catch (err) {
            showNotice("error", `Could not delete the job: ${errorMessage(err)}`);
            deleteButton.disabled = false;
        }
    });
    /** Queues a failed task again (its job reopens with it). */
    async function retryTask(taskId, button) {
        button.disabled = true;
        try {
            const res = await api.retry(id, taskId);
            upsertTask(res.task);
            reopened(res.job);
            showNotice("success", `Task ${taskId} was queued again.`);
        }
        catch (err) {
            showNotice("error", `Could not retry ${taskId}: ${errorMessage(err)}`);
            button.disabled = false;
        }
    }
    /** Unblocks one worker, after asking: its failures on this job are forgiven. */
    function unblockButton(workerId) {
        const button = h("button", { type: "button", class: "button", "data-testid": "unblock-button" }, "Unblock");
        button.addEventListener("click", async () => {
            const name = workerName(workerId);
            if (!window.confirm(`Unblock ${name}? It may lease this job's tasks again, after it failed them.`))
                return;
            button.disabled = true;
            try {
                applyJob((await api.unblock(id, workerId)).job);
                showNotice("success", `${name} was unblocked.`);
            }
            catch (err) {
                showNotice("error", `Could not unblock ${name}: ${errorMessage(err)}`);
                button.disabled = false;
            }
        });
        return button;
    }
    // ---- stats strip
    const progress = progressBar(0, "0%", { "data-testid": "job-progress", "aria-label": "Progress of the current round" });
    const sRound = stat("Round");
    const sElapsed = stat("Elapsed");
    const sEta = stat("ETA");
    const sPhotons = stat("Photons");
    const sSpp = stat("Samples / pixel");
    const sError = stat("Estimated error");
    const sRef = stat("Reference RMSE");
    const stats = h("dl", { class: "stats" }, h("div", { class: "stat stat--wide" }, h("dt", { class: "stat__label" }, "Progress"), h("dd", { class: "stat__value" }, progress)), sRound.element, sElapsed.element, sEta.element, sPhotons.element, sSpp.element, sError.element, sRef.element);
    // ---- image, phases, plan, chart, workers
    const mosaic = new Mosaic();
    const viewer = new ImageViewer();
    const finalImage = h("div", { class: "final", hidden: true });
    const finalCard = card("Final image", finalImage);
    finalCard.hidden = true;
    const phases = new PhaseList();
    const plan = h("ul", { class: "plan" });
    const chart = new ErrorChart();
    const blocked = h("ul", { class: "blocked" });
    // ---- task table
    const stateSelect = h("select", { id: "task-state-filter", class: "input", "data-testid": "task-state-filter" }, h("option", { value: "" }, "All states"), ...TASK_STATES.map((s) => h("option", { value: s }, taskStateLabel(s))));
    const phaseSelect = h("select", { id: "task-phase-filter", class: "input" }, h("option", { value: "" }, "All phases"));
    const tableInfo = h("p", { class: "muted table-info", "aria-live": "polite", "data-testid": "task-table-info" });
    const moreButton = h("button", { type: "button", class: "button", hidden: true, "data-testid": "tasks-more" }, "Show more");
    stateSelect.addEventListener("change", () => {
        stateFilter = stateSelect.value;
        limit = PAGE_ROWS;
        render.schedule();
    });
    phaseSelect.addEventListener("change", () => {
        phaseFilter = phaseSelect.value;
        limit = PAGE_ROWS;
        render.schedule();
    });
    moreButton.addEventListener("click", () => {
        limit += PAGE_ROWS;
        if (next)
            void loadPage();
        render.schedule();
    });
    const taskTable = new DataTable({
        caption: "Tasks in plan order",
        captionHidden: true,
        className: "table--tasks table--compact",
        key: (t) => t.id,
        rowAttrs: (t) => ({ "data-testid": "task-row", "data-state": t.state ?? "TASK_STATE_UNSPECIFIED" }),
        empty: "No tasks match.",
        columns: [
            { header: "Task", className: "mono", text: (t) => t.id },
            { header: "Phase", text: (t) => phaseShort(t.phase) },
            { header: "Round", className: "num", text: (t) => String(t.round ?? "") },
            {
                header: "State",
                sig: (t) => t.state ?? "",
                render: (t, td) => badgeCell(td, taskStateLabel(t.state), enumKey(t.state, "TASK_STATE_")),
            },
            { header: "Attempts", className: "num", text: (t) => String(t.attempts ?? 0) },
            { header: "Worker", text: (t) => workerName(t.workerId) },
            {
                header: "Error",
                className: "col-error",
                sig: (t) => t.error ?? "",
                render: (t, td) => {
                    td.textContent = t.error ?? "";
                    setAttr(td, "title", t.error || null);
                },
            },
            { header: "Log", sig: logSig, render: logButtons },
            {
                header: "",
                sig: (t) => (t.state === "TASK_STATE_FAILED" ? t.id : ""),
                render: (t, td) => {
                    if (t.state !== "TASK_STATE_FAILED") {
                        td.replaceChildren();
                        return;
                    }
                    const button = h("button", { type: "button", class: "button button--small", "data-testid": "retry-button" }, "Retry");
                    button.addEventListener("click", () => void retryTask(t.id, button));
                    td.replaceChildren(button);
                },
            },
        ],
    });
    const taskLog = new TaskLogPanel();
    taskLog.attach(taskTable.element);
    const tasksCard = h("section", { class: "card", "aria-labelledby": "card-tasks" }, h("div", { class: "card__header" }, h("h2", { id: "card-tasks", class: "card__title" }, "Tasks"), h("div", { class: "filters" }, h("label", { for: "task-state-filter", class: "visually-hidden" }, "Filter by state"), stateSelect, h("label", { for: "task-phase-filter", class: "visually-hidden" }, "Filter by phase"), phaseSelect)), tableInfo, h("div", { class: "table-wrap" }, taskTable.element), h("div", { class: "table-more" }, moreButton), taskLog.element);
    const body = h("div", { class: "job__body", hidden: true }, stats, h("div", { class: "job__grid" }, h("div", { class: "job__main" }, finalCard, card("Image so far", mosaic.element), card("Error against time", chart.element)), h("div", { class: "job__side" }, card("Phases", phases.element), card("Plan", plan), card("Blocked workers", blocked))), tasksCard);
    const missing = h("div", { class: "card empty-state", hidden: true });
    const element = h("section", { class: "page job", "aria-labelledby": "job-title" }, h("nav", { class: "breadcrumb", "aria-label": "Breadcrumb" }, h("a", { href: "#/" }, "Jobs"), h("span", { "aria-hidden": "true" }, " / "), h("span", null, id)), h("div", { class: "page__header" }, h("div", { class: "job__heading" }, h("div", { class: "job__title-row", id: "job-title" }, title, stateBadge), idLine), actions), failureBanner, notice, missing, body);
    title.id = "job-title-text";
    // ---- state updates
    function applyJob(j) {
        job = j;
        render.schedule();
    }
    function setTasks(list) {
        tasks.length = 0;
        byId.clear();
        for (const t of list) {
            byId.set(t.id, tasks.length);
            tasks.push(t);
        }
    }
    /** A job and the first page of its tasks (the job event, GET /api/jobs/{id}): the list starts again. */
    function firstPage(page) {
        generation++;
        loading = false;
        setTasks(page.tasks ?? []);
        next = page.nextPageToken ?? "";
        if (tasks.length < AUTO_LOAD_TASKS)
            void loadPage();
    }
    /** Reads the next page of tasks, and more while under AUTO_LOAD_TASKS. */
    async function loadPage() {
        if (!next || loading)
            return;
        const gen = generation;
        loading = true;
        try {
            const page = await api.tasks(id, next);
            if (gen !== generation)
                return;
            for (const t of page.tasks ?? []) {
                if (!byId.has(t.id)) {
                    byId.set(t.id, tasks.length);
                    tasks.push(t);
                }
            }
            next = page.nextPageToken ?? "";
            render.schedule();
        }
        catch (err) {
            showNotice("error", `Could not read the job's tasks: ${errorMessage(err)}`);
            return;
        }
        finally {
            if (gen === generation)
                loading = false;
        }
        if (tasks.length < AUTO_LOAD_TASKS)
            void loadPage();
    }
    function upsertTask(t) {
        const i = byId.get(t.id);
        if (i !== undefined) {
            tasks[i] = t;
            return;
        }
        // A task of a page not read yet comes with that page.
        if (next)
            return;
        // New tasks (a new round) come after the others in plan order.
        const last = tasks[tasks.length - 1];
        if (!last || (last.index ?? 0) <= (t.index ?? 0)) {
            byId.set(t.id, tasks.length);
            tasks.push(t);
        }
        else {
            setTasks([...tasks, t].sort((a, b) => (a.index ?? 0) - (b.index ?? 0)));
        }
    }
    let planSig = "";
    let blockedSig = "";
    let finalSig = "";
    let phaseOptions = "";
    function renderJob(j) {
        const ended = jobEnded(j);
        const name = j.displayName || "(unnamed scene)";
        actions.hidden = false;
        setText(title, name);
        document.title = `${name} · Photon farm`;
        updateBadge(stateBadge, jobStateLabel(j.state), enumKey(j.state, "JOB_STATE_"));
        setAttr(stateBadge, "data-state", j.state ?? "");
        if (!priorityDirty && document.activeElement !== priorityInput)
            priorityInput.value = String(j.priority ?? 0);
        priorityInput.disabled = ended;
        priorityButton.disabled = ended;
        cancelButton.disabled = ended;
        setAttr(cancelButton, "title", ended ? "The job has ended" : null);
        cancelButton.hidden = ended;
        requeueButton.hidden = !ended || j.state === "JOB_STATE_SUCCEEDED";
        const failed = j.state === "JOB_STATE_FAILED";
        failureBanner.hidden = !failed;
        setAttr(failureBanner, "data-kind", failed ? (j.failureKind ?? "FAILURE_KIND_UNSPECIFIED") : null);
        setText(failureKind, failed ? `${failureLabel(j.failureKind)}:` : "");
        setText(failureMessage, failed ? (j.error ?? "") : "");
        const p = jobProgress(j);
        updateProgressBar(progress, p.fraction, progressLabel(j));
        setText(sRound.value, ended ? `${p.roundsDone} done` : `${p.round}${p.roundsDone ? ` (${p.roundsDone} done)` : ""}`);
        setText(sElapsed.value, formatDuration(jobElapsed(j, now)));
        setText(sEta.value, ended ? "—" : formatEta(jobEta(j, now)));
        const last = j.rounds?.[j.rounds.length - 1];
        setText(sPhotons.value, last ? formatCompact(last.photons) : "—");
        setText(sSpp.value, last ? formatCompact(last.samplesPerPixel) : "—");
        setText(sError.value, formatEstimate(last?.errorEstimate, last?.errorEstimateLow, last?.errorEstimateHigh));
        setText(sRef.value, formatError(last?.referenceRmse));
        sRef.element.hidden = !(j.rounds ?? []).some((r) => r.referenceRmse !== undefined);
        phases.update(j);
        chart.update(j);
        const ps = JSON.stringify(j.plan?.passes ?? []);
        if (ps !== planSig) {
            planSig = ps;
            const passes = j.plan?.passes ?? [];
            plan.replaceChildren(...(passes.length
                ? passes.map((pass) => h("li", { class: `plan__pass ${pass.enabled ? "is-on" : "is-off"}` }, h("span", { class: "plan__mark", "aria-hidden": "true" }, pass.enabled ? "✓" : "–"), h("div", null, h("span", { class: "plan__name" }, pass.name ?? ""), h("span", { class: "visually-hidden" }, pass.enabled ? " (runs)" : " (skipped)"), pass.reason ? h("span", { class: "plan__reason" }, pass.reason) : null)))
                : [h("li", { class: "empty" }, "No plan reported.")]));
        }
        const bs = JSON.stringify(j.blockedWorkers ?? []);
        if (bs !== blockedSig) {
            blockedSig = bs;
            const list = j.blockedWorkers ?? [];
            blocked.replaceChildren(...(list.length
                ? list.map((b) => h("li", { class: "blocked__item", "data-testid": "blocked-worker" }, h("span", { title: b.workerId ?? null }, workerName(b.workerId)), h("span", { class: "blocked__reason" }, b.reason ?? ""), timeElement(b.blockTime, (ms) => formatRelative(ms, now), { class: "muted" }), unblockButton(b.workerId ?? "")))
                : [h("li", { class: "empty" }, "No worker is blocked.")]));
        }
        const preview = j.state === "JOB_STATE_SUCCEEDED" ? artifact(j.outputs, ARTIFACT.PREVIEW_PNG) : undefined;
        const exr = artifact(j.outputs, ARTIFACT.IMAGE_EXR);
        const fs = `${preview?.digest}|${exr?.digest}`;
        if (fs !== finalSig) {
            finalSig = fs;
            const shown = Boolean(preview?.digest && exr?.digest);
            finalCard.hidden = !shown;
            finalImage.hidden = !shown;
            if (shown) {
                void viewer.load(blobUrl(exr.digest, ARTIFACT.IMAGE_EXR));
                finalImage.replaceChildren(viewer.element, h("p", { class: "final__links" }, h("a", { href: blobUrl(preview.digest, ARTIFACT.PREVIEW_PNG), download: `${name}.png`, class: "button" }, "Download PNG"), h("a", { href: blobUrl(exr.digest, ARTIFACT.IMAGE_EXR), download: `${name}.exr`, class: "button" }, "Download EXR")));
            }
        }
    }
    function renderTasks() {
        const counts = new Map();
        const phasesSeen = [];
        let filtered = [];
        for (const t of tasks) {
            const s = t.state ?? "";
            counts.set(s, (counts.get(s) ?? 0) + 1);
            const ph = t.phase ?? "";
            if (!phasesSeen.includes(ph))
                phasesSeen.push(ph);
            if ((!stateFilter || s === stateFilter) && (!phaseFilter || ph === phaseFilter))
                filtered.push(t);
        }
        const options = stateSelect.options;
        for (let i = 1; i < options.length; i++) {
            const opt = options[i];
            setText(opt, `${taskStateLabel(opt.value)} (${counts.get(opt.value) ?? 0})`);
        }
        setText(options[0], `All states (${tasks.length})`);
        const po = phasesSeen.join(",");
        if (po !== phaseOptions) {
            phaseOptions = po;
            phaseSelect.replaceChildren(h("option", { value: "" }, "All phases"), ...phasesSeen.map((ph) => h("option", { value: ph }, phaseShort(ph))));
            phaseSelect.value = phasesSeen.includes(phaseFilter) ? phaseFilter : "";
        }
        const total = filtered.length;
        if (total > limit)
            filtered = filtered.slice(0, limit);
        taskTable.update(filtered, now);
        const loaded = next ? ` (the first ${tasks.length} read; more to read)` : "";
        setText(tableInfo, (total === tasks.length
            ? `${tasks.length} ${tasks.length === 1 ? "task" : "tasks"}${total > limit ? `, showing the first ${limit}` : ""}`
            : `${total} of ${tasks.length} tasks match${total > limit ? `, showing the first ${limit}` : ""}`) + loaded);
        moreButton.hidden = total <= limit && !next;
        setText(moreButton, total > limit ? `Show ${Math.min(PAGE_ROWS, total - limit)} more` : "Read more tasks");
    }
    const render = frameScheduler(() => {
        if (!job)
            return;
        body.hidden = false;
        renderJob(job);
        mosaic.update(job, tasks, !next);
        renderTasks();
    });
    // Names arriving after a render: the blocked list's signature does not hold them.
    const stopNames = onWorkerNames(() => {
        blockedSig = "";
        render.schedule();
    });
    /** The page says the job is gone (or was never there, or is not ours). */
    function gone(heading, ...why) {
        stream?.close();
        feed?.close();
        body.hidden = true;
        missing.hidden = false;
        failureBanner.hidden = true;
        setText(title, heading);
        stateBadge.hidden = true;
        priorityForm.hidden = true;
        cancelButton.hidden = true;
        requeueButton.hidden = true;
        deleteButton.hidden = true;
        missing.replaceChildren(h("p", { "data-testid": "job-missing" }, ...why), h("p", null, h("a", { href: "#/" }, "Back to the jobs")));
    }
    function deleted() {
        gone("Job deleted", `The job ${job?.displayName || id} (${id}) was deleted.`);
    }
    /** The job ended: follow the job list for a requeue, a retry or a delete made anywhere. */
    function followEnded() {
        feed?.close();
        // The list is polled, so it may show a job that was reopened and ended again since
        // (never running in between), or be older than what the page has: compare update times.
        const seen = (jobs) => {
            const j = jobs?.find((x) => x.id === id);
            if (!j)
                return false;
            const t = Date.parse(j.updateTime ?? "");
            const mine = Date.parse(job?.updateTime ?? "");
            // Older than the page's job: the list was polled before the job ended (a running
            // job deleted at once still shows running there). Not newer (equal to the ms): its
            // own stream tells, at the cost of one stream opened.
            if (t < mine)
                return true;
            if (!jobEnded(j))
                reopened(j);
            else if (t > mine) {
                api.job(id).then((res) => {
                    firstPage(res);
                    applyJob(res.job);
                }, () => { });
            }
            return true;
        };
        feed = new LiveStream("api/events", {
            events: {
                // The whole list: a job missing from it may have been deleted before the feed
                // began (a delete cancels a running job first, which ended its stream): ask.
                jobs: (data) => {
                    if (seen(data.jobs))
                        return;
                    api.job(id).then((res) => reopened(res.job), (err) => {
                        if (err instanceof ApiError && err.status === 404)
                            deleted();
                    });
                },
                "jobs-changed": (data) => {
                    if (data.removed?.includes(id))
                        deleted();
                    else
                        seen(data.jobs);
                },
            },
            probe: () => api.job(id),
            onFatal: () => deleted(),
        });
    }
    /** The job runs again (requeued, a task retried): watch its events anew. */
    function reopened(j) {
        applyJob(j);
        if (jobEnded(j) || streaming)
            return;
        feed?.close();
        feed = null;
        watch();
    }
    let stream = null;
    let feed = null;
    let streaming = false; // the job's own stream is open: the job has not ended
    function watch() {
        streaming = true;
        stream = new LiveStream(`api/jobs/${encodeURIComponent(id)}/events`, {
            events: {
                job: (data) => {
                    firstPage(data);
                    now = Date.now();
                    applyJob(data.job);
                },
                task: (data) => {
                    upsertTask(data.task);
                    now = Date.now();
                    applyJob(data.job);
                },
                end: (data) => {
                    stream?.close();
                    streaming = false;
                    now = Date.now();
                    applyJob(data.job);
                    // The last task changes may have been coalesced away: read the final tasks once.
                    api.job(id).then((res) => {
                        firstPage(res);
                        applyJob(res.job);
                    }, () => { });
                    followEnded();
                },
            },
            probe: () => api.job(id),
            onFatal: (err) => {
                streaming = false;
                // Job ids are never reused: a job this page has shown and is now unknown was deleted.
                if (err.status === 404 && job)
                    deleted();
                else if (err.status === 404)
                    gone("Job not found", `There is no job ${id}.`);
                else
                    gone("Not allowed", err.message);
            },
        });
    }
    watch();
    return {
        element,
        title: "Job",
        tick(t) {
            now = t;
            if (job && !jobEnded(job))
                render.schedule();
        },
        destroy() {
            stream?.close();
            feed?.close();
            stopNames();
            render.cancel();
        },
    };
}
