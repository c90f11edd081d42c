// The dashboard server's HTTP API (services/dashboard/API.md): JSON requests, server-sent
// event streams, and the login that any 401 answer leads to.
//
// Paths are relative ("api/jobs"), so the dashboard also works mounted under a prefix.
/** An API answer other than 2xx, with the server's {"error": "..."} message. */
export class ApiError extends Error {
    constructor(status, message) {
        super(message);
        this.status = status;
        this.name = "ApiError";
    }
}
let loginPrompt = () => Promise.reject(new Error("no login form"));
let pendingLogin = null;
export function setLoginPrompt(prompt) {
    loginPrompt = prompt;
}
/** Asks for a token once, however many requests were refused at the same time. */
export function requireLogin() {
    if (!pendingLogin) {
        pendingLogin = loginPrompt().finally(() => {
            pendingLogin = null;
        });
    }
    return pendingLogin;
}
async function readError(res) {
    const text = await res.text();
    try {
        const body = JSON.parse(text);
        if (typeof body.error === "string" && body.error)
            return body.error;
    }
    catch {
        // not JSON: fall through to the raw text
    }
    return text.trim() || `${res.status} ${res.statusText}`;
}
/**
 * Sends a request; a 401 shows the login form and, after a successful login, sends the
 * request again. Other errors throw ApiError.
 */
export async function request(method, path, body) {
    for (;;) {
        const init = { method, credentials: "same-origin", headers: { Accept: "application/json" } };
        if (body !== undefined) {
            init.body = typeof body === "string" ? body : JSON.stringify(body);
            init.headers = { Accept: "application/json", "Content-Type": "application/json" };
        }
        const res = await fetch(path, init);
        if (res.status === 401) {
            await requireLogin();
            continue;
        }
        if (!res.ok)
            throw new ApiError(res.status, await readError(res));
        return (await res.json());
    }
}
/** POST /api/login: throws ApiError (401) for a token the coordinator refuses. */
export async function login(token) {
    const res = await fetch("api/login", {
        method: "POST",
        credentials: "same-origin",
        headers: { "Content-Type": "application/json", Accept: "application/json" },
        body: JSON.stringify({ token }),
    });
    if (!res.ok)
        throw new ApiError(res.status, await readError(res));
}
export async function logout() {
    // Every state-changing endpoint takes JSON only (API.md, "Cross-origin requests").
    await fetch("api/logout", {
        method: "POST",
        credentials: "same-origin",
        headers: { "Content-Type": "application/json" },
        body: "{}",
    });
}
export async function getSession() {
    const res = await fetch("api/session", { credentials: "same-origin" });
    if (!res.ok)
        throw new ApiError(res.status, await readError(res));
    return (await res.json());
}
export const api = {
    jobs: () => request("GET", "api/jobs"),
    /** The job and the first page of its tasks. */
    job: (id) => request("GET", `api/jobs/${encodeURIComponent(id)}`),
    /** A page of the job's tasks in plan order; pageToken from the page before. */
    tasks: (id, pageToken) => request("GET", `api/jobs/${encodeURIComponent(id)}/tasks?pageToken=${encodeURIComponent(pageToken)}`),
    /** A page of workers, oldest first; pageToken from the page before ("" for the first). */
    workers: (pageToken = "") => request("GET", `api/workers${pageToken ? `?pageToken=${encodeURIComponent(pageToken)}` : ""}`),
    /**
     * The scene file's text, sent as it is (the server parses and validates it), with the
     * files it names (meshes, textures), base64 by their names or paths in a chosen folder.
     */
    submit: (sceneJson, files = {}) => request("POST", "api/jobs", Object.keys(files).length ? `{"scene": ${sceneJson}, "files": ${JSON.stringify(files)}}` : sceneJson),
    cancel: (id) => request("POST", `api/jobs/${encodeURIComponent(id)}/cancel`, {}),
    /** Takes the worker off the job's blocklist, so it can lease the job's tasks again. */
    unblock: (id, workerId) => request("POST", `api/jobs/${encodeURIComponent(id)}/unblock`, { workerId }),
    /** Reopens a failed or cancelled job where it stopped. */
    requeue: (id) => request("POST", `api/jobs/${encodeURIComponent(id)}/requeue`, {}),
    /** Queues a failed task of the job again, reopening the job. */
    retry: (id, taskId) => request("POST", `api/jobs/${encodeURIComponent(id)}/tasks/${encodeURIComponent(taskId)}/retry`, {}),
    /** Deletes the job (cancelling it if it runs); answers the job as it was deleted. */
    deleteJob: (id) => request("POST", `api/jobs/${encodeURIComponent(id)}/delete`, {}),
    setPriority: (id, priority) => request("POST", `api/jobs/${encodeURIComponent(id)}/priority`, { priority }),
};
/** The URL of a content-addressed blob (cacheable forever). */
export function blobUrl(digest, name) {
    return `api/blobs/${encodeURIComponent(digest)}?name=${encodeURIComponent(name)}`;
}
let statusListener = () => { };
/** Reports every stream's connection state (the header's "Live" indicator). */
export function onStreamStatus(listener) {
    statusListener = listener;
}
/**
 * An EventSource that survives logins and server restarts: reconnects with backoff,
 * and closes for good on close() (or when a handler calls it, e.g. after "end").
 */
export class LiveStream {
    constructor(url, opts) {
        this.url = url;
        this.opts = opts;
        this.source = null;
        this.closed = false;
        this.delay = 500;
        this.open();
    }
    open() {
        if (this.closed)
            return;
        const source = new EventSource(this.url, { withCredentials: true });
        this.source = source;
        for (const [name, handler] of Object.entries(this.opts.events)) {
            source.addEventListener(name, (ev) => {
                if (this.closed)
                    return;
                let data;
                try {
                    data = JSON.parse(ev.data);
                }
                catch (err) {
                    console.error(`bad ${name} event from ${this.url}`, err);
                    return;
                }
                handler(data);
            });
        }
        source.onopen = () => {
            this.delay = 500;
            statusListener("live");
        };
        source.onerror = () => {
            if (this.closed)
                return;
            statusListener("connecting");
            // CONNECTING: the browser retries by itself. CLOSED: the server answered with an
            // error status (401, 404, 503...): find out which, then reconnect ourselves.
            if (source.readyState === EventSource.CLOSED) {
                source.close();
                void this.recover();
            }
        };
    }
    async recover() {
        try {
            await this.opts.probe();
        }
        catch (err) {
            if (err instanceof ApiError && (err.status === 404 || err.status === 403) && this.opts.onFatal) {
                this.close();
                this.opts.onFatal(err);
                return;
            }
        }
        if (this.closed)
            return;
        this.timer = window.setTimeout(() => this.open(), this.delay);
        this.delay = Math.min(this.delay * 2, 10000);
    }
    close() {
        this.closed = true;
        window.clearTimeout(this.timer);
        this.source?.close();
        this.source = null;
    }
}
