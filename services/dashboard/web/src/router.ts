// Hash routes: #/ (jobs), #/jobs/{id} (a job), #/workers.

export type Route =
  | { name: "jobs" }
  | { name: "job"; id: string }
  | { name: "workers" }
  | { name: "notfound"; path: string };

export function parseRoute(hash: string): Route {
  const path = hash.replace(/^#/, "") || "/";
  if (path === "/" || path === "") return { name: "jobs" };
  if (path === "/workers") return { name: "workers" };
  const m = /^\/jobs\/([^/]+)$/.exec(path);
  if (m) return { name: "job", id: decodeURIComponent(m[1]!) };
  return { name: "notfound", path };
}

export function jobHref(id: string): string {
  return `#/jobs/${encodeURIComponent(id)}`;
}

/** A mounted page: its element, a once-a-second tick for relative times, and cleanup. */
export interface Page {
  element: HTMLElement;
  title: string;
  tick?(now: number): void;
  destroy(): void;
}

/** Calls render with the current route now and on every hash change. */
export function startRouter(render: (route: Route) => void): void {
  window.addEventListener("hashchange", () => render(parseRoute(location.hash)));
  render(parseRoute(location.hash));
}
