// Hash routes: #/ (jobs), #/jobs/{id} (a job), #/workers.
export function parseRoute(hash) {
    const path = hash.replace(/^#/, "") || "/";
    if (path === "/" || path === "")
        return { name: "jobs" };
    if (path === "/workers")
        return { name: "workers" };
    const m = /^\/jobs\/([^/]+)$/.exec(path);
    if (m)
        return { name: "job", id: decodeURIComponent(m[1]) };
    return { name: "notfound", path };
}
export function jobHref(id) {
    return `#/jobs/${encodeURIComponent(id)}`;
}
/** Calls render with the current route now and on every hash change. */
export function startRouter(render) {
    window.addEventListener("hashchange", () => render(parseRoute(location.hash)));
    render(parseRoute(location.hash));
}
