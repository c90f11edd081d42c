// Worker names (the --name a worker registered with, WorkerInfo.hostname) by worker id,
// for every page that shows a worker: tasks, tiles and blocked workers name workers by id
// only. The names are read from /api/workers (all pages) when a page asks for an id not
// known yet, at most once per REFRESH_MS, and pages are told when names arrive.
import { api } from "./api.js";
/** The least time between two reads of the worker list. */
const REFRESH_MS = 3000;
const names = new Map();
const listeners = new Set();
let lastRead = -Infinity;
let reading = false;
/** Stores the names of workers read elsewhere (the workers page's live list). */
export function rememberWorkers(workers) {
    let changed = false;
    for (const w of workers) {
        if (w.hostname && names.get(w.id) !== w.hostname) {
            names.set(w.id, w.hostname);
            changed = true;
        }
    }
    if (changed)
        for (const l of listeners)
            l();
}
async function readAll() {
    reading = true;
    lastRead = Date.now();
    try {
        const all = [];
        let token = "";
        do {
            const page = await api.workers(token);
            all.push(...(page.workers ?? []));
            token = page.nextPageToken ?? "";
        } while (token);
        rememberWorkers(all);
    }
    catch {
        // The id stays shown; the next unknown id asks again after REFRESH_MS.
    }
    finally {
        reading = false;
    }
}
/** The worker's name, or its id while the name is not known (a read is started). */
export function workerName(id) {
    if (!id)
        return "";
    const name = names.get(id);
    if (name)
        return name;
    if (!reading && Date.now() - lastRead >= REFRESH_MS)
        void readAll();
    return id;
}
/** Calls f whenever names arrive; returns the function that stops it. */
export function onWorkerNames(f) {
    listeners.add(f);
    return () => listeners.delete(f);
}
