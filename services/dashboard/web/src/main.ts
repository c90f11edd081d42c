// The dashboard's entry point: the page shell (header, navigation, live indicator), the
// login hook for 401 answers, and the router that mounts one page at a time.

import { getSession, logout, onStreamStatus, requireLogin, setLoginPrompt, type StreamStatus } from "./api.js";
import { h } from "./dom.js";
import { showLogin } from "./login.js";
import { jobPage } from "./pages/job.js";
import { jobsPage } from "./pages/jobs.js";
import { workersPage } from "./pages/workers.js";
import { startRouter, type Page, type Route } from "./router.js";

setLoginPrompt(showLogin);

const navJobs = h("a", { href: "#/", class: "nav__link" }, "Jobs");
const navWorkers = h("a", { href: "#/workers", class: "nav__link" }, "Workers");
const status = h("span", { class: "live live--connecting", role: "status", "aria-live": "polite" }, "Connecting");
const logoutButton = h("button", { type: "button", class: "button button--ghost", hidden: true }, "Sign out");
const main = h("main", { id: "content", class: "content", tabindex: "-1" });

document.body.replaceChildren(
  h(
    "header",
    { class: "topbar" },
    h(
      "a",
      { href: "#/", class: "brand", "aria-label": "Photon farm, job list" },
      h("span", { class: "brand__mark", "aria-hidden": "true" }),
      "Photon farm",
    ),
    h("nav", { class: "nav", "aria-label": "Main" }, navJobs, navWorkers),
    h("div", { class: "topbar__end" }, status, logoutButton),
  ),
  main,
);

onStreamStatus((s: StreamStatus) => {
  status.className = `live live--${s}`;
  status.textContent = s === "live" ? "Live" : "Reconnecting…";
});

logoutButton.addEventListener("click", async () => {
  await logout();
  location.reload();
});

let page: Page | null = null;

function mount(route: Route): void {
  page?.destroy();
  switch (route.name) {
    case "jobs":
      page = jobsPage();
      break;
    case "job":
      page = jobPage(route.id);
      break;
    case "workers":
      page = workersPage();
      break;
    default:
      page = {
        title: "Not found",
        element: h(
          "section",
          { class: "page" },
          h("h1", null, "Page not found"),
          h("p", { class: "muted" }, `Nothing lives at ${route.path}. `, h("a", { href: "#/" }, "Back to the jobs")),
        ),
        destroy() {},
      };
  }
  const active = route.name === "workers" ? navWorkers : route.name === "notfound" ? null : navJobs;
  for (const link of [navJobs, navWorkers]) {
    if (link === active) link.setAttribute("aria-current", "page");
    else link.removeAttribute("aria-current");
  }
  document.title = `${page.title} · Photon farm`;
  main.replaceChildren(page.element);
  window.scrollTo(0, 0);
}

setInterval(() => page?.tick?.(Date.now()), 1000);

async function start(): Promise<void> {
  try {
    const session = await getSession();
    logoutButton.hidden = !session.authRequired;
    if (session.authRequired && !session.authenticated) {
      await requireLogin();
    }
  } catch (err) {
    // The server is unreachable: the pages' streams keep retrying and show it.
    console.warn("session check failed", err);
  }
  startRouter(mount);
}

void start();
