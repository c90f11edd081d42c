// The job list (#/): every job with its state, priority, progress, elapsed time and ETA,
// live from /api/events ("jobs" on connect, then "jobs-changed"), and the "Submit scene"
// upload.
import { ApiError, LiveStream, api } from "../api.js";
import { badgeCell, progressBar, timeElement, updateProgressBar } from "../components/widgets.js";
import { DataTable } from "../components/table.js";
import { frameScheduler, h, setText } from "../dom.js";
import { enumKey, formatDuration, formatEta, formatTimestamp, jobStateLabel, parseTime, } from "../format.js";
import { jobElapsed, jobEta, jobProgress } from "../progress.js";
import { jobHref } from "../router.js";
import { readSubmission } from "../submission.js";
import { jobEnded } from "../types.js";
export function progressLabel(job) {
    const p = jobProgress(job);
    const pct = `${Math.round(p.fraction * 100)}%`;
    if (job.state === "JOB_STATE_QUEUED")
        return "Queued";
    return p.rounds > 1 ? `${pct} · round ${p.round} of ${p.rounds}` : pct;
}
/** The job-state badge cell. */
function renderState(job, td) {
    badgeCell(td, jobStateLabel(job.state), enumKey(job.state, "JOB_STATE_"), { "data-testid": "job-state" });
}
function renderProgress(job, td) {
    const el = td.firstElementChild;
    const p = jobProgress(job);
    const label = progressLabel(job);
    if (el)
        updateProgressBar(el, p.fraction, label);
    else
        td.append(progressBar(p.fraction, label, { "data-testid": "job-progress", "aria-label": `Progress of ${job.displayName ?? job.id}` }));
}
function renderName(job, td) {
    td.replaceChildren(h("a", { href: jobHref(job.id), class: "table__primary" }, job.displayName || "(unnamed scene)"), h("span", { class: "table__secondary mono" }, job.id));
}
/** What went wrong with a "Submit scene", for people: a headline and the server's reason. */
function submitRefusal(fileName, err) {
    const message = err instanceof Error ? err.message : String(err);
    if (!(err instanceof ApiError))
        return [`Could not submit ${fileName}: `, message];
    switch (err.status) {
        case 400:
            return [`${fileName} was refused, nothing was queued: `, message];
        case 413:
            return [`${fileName} is too large to submit from the browser: `, message];
        case 403:
            return [`Your token may not submit jobs: `, message];
        case 503:
            return [`The farm is not reachable now; try again: `, message];
    }
    return [`Could not submit ${fileName}: `, message];
}
/**
 * The list after a jobs-changed event: changed jobs replace theirs in place, new ones
 * (the newest, as the event lists them first) lead, removed ones go.
 */
export function mergeJobs(list, changed, removed) {
    const fresh = new Map(changed.map((j) => [j.id, j]));
    const gone = new Set(removed);
    const kept = list.filter((j) => !gone.has(j.id)).map((j) => fresh.get(j.id) ?? j);
    const known = new Set(list.map((j) => j.id));
    return [...changed.filter((j) => !known.has(j.id) && !gone.has(j.id)), ...kept];
}
export function jobsPage() {
    let jobs = [];
    let received = false;
    let now = Date.now();
    const table = new DataTable({
        caption: "Jobs, newest first",
        captionHidden: true,
        className: "table--jobs",
        key: (j) => j.id,
        rowAttrs: (j) => ({ "data-testid": "job-row", "data-job-id": j.id, "data-state": j.state ?? "JOB_STATE_UNSPECIFIED" }),
        rowHref: (j) => jobHref(j.id),
        empty: "Loading jobs…",
        columns: [
            { header: "Name", sig: (j) => `${j.displayName}`, render: renderName },
            { header: "State", sig: (j) => j.state ?? "", render: renderState },
            { header: "Priority", className: "num", text: (j) => String(j.priority ?? 0) },
            { header: "Progress", className: "col-progress", sig: (j) => `${j.state}|${progressLabel(j)}|${jobProgress(j).fraction}`, render: renderProgress },
            { header: "Elapsed", className: "num", text: (j, t) => formatDuration(jobElapsed(j, t)) },
            { header: "ETA", className: "num", text: (j, t) => (jobEnded(j) ? "—" : formatEta(jobEta(j, t))) },
            {
                header: "Created",
                className: "num",
                sig: (j, t) => formatTimestamp(parseTime(j.createTime), t),
                render: (j, td, t) => td.replaceChildren(timeElement(j.createTime, (ms) => formatTimestamp(ms, t))),
            },
        ],
    });
    const summary = h("p", { class: "page__summary muted", "aria-live": "polite" }, "Loading jobs…");
    const notice = h("div", { class: "notice-area" });
    // The scene and its files (meshes, textures), chosen together or as the folder that
    // holds them: the scene is the one .json file among them (scene.ts).
    const fileInput = h("input", {
        type: "file",
        id: "submit-file",
        multiple: true,
        class: "visually-hidden",
        "data-testid": "submit-file",
    });
    const folderInput = h("input", {
        type: "file",
        id: "submit-folder",
        webkitdirectory: true,
        class: "visually-hidden",
        "data-testid": "submit-folder",
    });
    const uploadLabel = h("label", { for: "submit-file", class: "button button--primary", title: "Choose a scene .json and the files it names" }, "Submit scene");
    const folderLabel = h("label", { for: "submit-folder", class: "button", title: "Choose the folder that holds a scene .json and its files" }, "Submit folder");
    const onChosen = (input) => async () => {
        const chosen = [...(input.files ?? [])];
        if (chosen.length === 0)
            return;
        uploadLabel.classList.add("is-busy");
        notice.replaceChildren();
        let name = chosen[0].name;
        try {
            const { scene, files } = await readSubmission(chosen);
            name = scene.name;
            const { job } = await api.submit(await scene.text(), files);
            notice.replaceChildren(h("div", { class: "notice notice--success", role: "status" }, "Submitted ", h("a", { href: jobHref(job.id) }, job.displayName || job.id), Object.keys(files).length ? ` with ${Object.keys(files).length} ${Object.keys(files).length === 1 ? "file" : "files"}.` : "."));
            if (!jobs.some((j) => j.id === job.id)) {
                jobs = [job, ...jobs];
                render.schedule();
            }
        }
        catch (err) {
            const [headline, message] = submitRefusal(name, err);
            notice.replaceChildren(h("div", { class: "notice notice--error", role: "alert", "data-testid": "submit-error" }, h("strong", null, headline), message));
        }
        finally {
            uploadLabel.classList.remove("is-busy");
            input.value = "";
        }
    };
    fileInput.addEventListener("change", onChosen(fileInput));
    folderInput.addEventListener("change", onChosen(folderInput));
    const element = h("section", { class: "page", "aria-labelledby": "jobs-title" }, h("div", { class: "page__header" }, h("div", null, h("h1", { id: "jobs-title" }, "Jobs"), summary), h("div", { class: "page__actions" }, fileInput, uploadLabel, folderInput, folderLabel)), notice, h("div", { class: "card card--flush table-wrap" }, table.element));
    const render = frameScheduler(() => {
        table.update(jobs, now);
        if (!received)
            return;
        table.setEmptyText("No jobs yet. Submit a scene to start rendering.");
        const counts = new Map();
        for (const j of jobs)
            counts.set(j.state ?? "", (counts.get(j.state ?? "") ?? 0) + 1);
        const parts = [`${jobs.length} ${jobs.length === 1 ? "job" : "jobs"}`];
        for (const s of ["JOB_STATE_RUNNING", "JOB_STATE_QUEUED", "JOB_STATE_FAILED"]) {
            const n = counts.get(s);
            if (n)
                parts.push(`${n} ${jobStateLabel(s).toLowerCase()}`);
        }
        setText(summary, parts.join(" · "));
    });
    const stream = new LiveStream("api/events", {
        events: {
            jobs: (data) => {
                jobs = data.jobs ?? [];
                received = true;
                now = Date.now();
                render.schedule();
            },
            "jobs-changed": (data) => {
                jobs = mergeJobs(jobs, data.jobs ?? [], data.removed ?? []);
                now = Date.now();
                render.schedule();
            },
        },
        probe: () => api.jobs(),
    });
    render.schedule();
    return {
        element,
        title: "Jobs",
        tick(t) {
            now = t;
            if (jobs.some((j) => !jobEnded(j)))
                render.schedule();
        },
        destroy() {
            stream.close();
            render.cancel();
        },
    };
}
