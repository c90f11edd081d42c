// The dashboard's browser test (issue 6's acceptance), run by tests/dashboard/dashboard_test.go
// against a real farm (a coordinator with tokens, two workers, `farm dashboard`). A plain
// Node script: playwright-core drives Debian's /usr/bin/chromium; no test runner, no
// downloaded browser. Exit status 0 when every step passed, 1 otherwise; each step prints
// one line, and a failure prints what was seen and saves SCREENSHOT_DIR/failure.png.
//
// Environment:
//   DASHBOARD_URL   where `farm dashboard` serves, e.g. http://127.0.0.1:40123/
//   FARM_TOKEN      the coordinator's client token (the dashboard's login)
//   SCENE_PATH      a self-contained scene JSON that renders in several seconds
//   SCREENSHOT_DIR  where job-page.png, job-page-running.png, job-page-done.png,
//                   failed-job-page.png (and failure.png) go
//   CHROMIUM        the browser, /usr/bin/chromium unless set
//   FAILED_JOB_ID   a job that failed as bad input before the test (a worker reported it)
//   FAILED_REASON   the error that worker reported
//   WORKER_FAILED_JOB_ID, WORKER_FAILED_REASON  a job a real farm-worker failed (its
//                   composite, as bad input), and the reason it reported
//   REQUEUE_JOB_ID  another job failed so, to requeue (FAILED_JOB_ID's failed task is retried)
//   BLOCKED_JOB_ID, BLOCKED_WORKER_ID  a long low-priority job and a worker blocked from it

import fs from 'node:fs';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { startCrossOriginSite } from './cross-origin.mjs';
import {
  WORKER_LAYERS, canvasPixels, compareExposure, hashPixels, nearestNeighbourMismatches, normalLengths, setExposure, setLayer, setZoom,
} from './viewer.mjs';

const env = (name, fallback) => {
  const v = process.env[name] ?? fallback;
  if (!v) {
    console.error(`dashboard.spec: ${name} is not set`);
    process.exit(1);
  }
  return v;
};
const baseURL = env('DASHBOARD_URL').replace(/\/?$/, '/');
const token = env('FARM_TOKEN');
const scenePath = env('SCENE_PATH');
const shotDir = env('SCREENSHOT_DIR');
const browserPath = env('CHROMIUM', '/usr/bin/chromium');
const failedJobId = env('FAILED_JOB_ID');
const workerFailedJob = env('WORKER_FAILED_JOB_ID');
const workerFailedReason = env('WORKER_FAILED_REASON');
const blockedJob = env('BLOCKED_JOB_ID'); // submitted before the test, a worker blocked from it
const blockedWorker = env('BLOCKED_WORKER_ID');
const requeueJobId = env('REQUEUE_JOB_ID');
// The jobs there are before the test submits any.
const jobsBefore = [failedJobId, workerFailedJob, requeueJobId, blockedJob].sort();
const sameJobs = (ids, want) => JSON.stringify([...ids].sort()) === JSON.stringify(want);
const failedReason = env('FAILED_REASON');

const api = (p) => new URL(p.replace(/^\//, ''), baseURL).toString();
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const started = Date.now();
const clock = () => `${((Date.now() - started) / 1000).toFixed(1).padStart(5)}s`;
const tid = (id) => `[data-testid="${id}"]`;

// "JOB_STATE_RUNNING", "running", "Running" all mean running.
const norm = (s) => (s ?? '').trim().toLowerCase().replace(/^job_state_/, '').replace(/^worker_state_/, '');
const ended = (s) => ['succeeded', 'failed', 'cancelled', 'canceled'].includes(norm(s));

class Failure extends Error {}
function check(cond, message) {
  if (!cond) throw new Failure(message);
}

// Polls fn until it returns a truthy value, which it returns; throws naming `what` (and
// the last value seen, from describe) after timeoutMs.
async function waitFor(what, timeoutMs, fn, describe) {
  const deadline = Date.now() + timeoutMs;
  let last;
  for (;;) {
    try {
      last = await fn();
      if (last) return last;
    } catch (e) {
      last = `error: ${e.message}`;
    }
    if (Date.now() > deadline) {
      const seen = describe ? await describe().catch((e) => `error: ${e.message}`) : last;
      throw new Failure(`${what}: not within ${timeoutMs / 1000}s (last seen: ${JSON.stringify(seen)})`);
    }
    await sleep(100);
  }
}

let current = '';
async function step(name, fn) {
  current = name;
  const t0 = Date.now();
  const result = await fn();
  console.log(`${clock()}  ok   ${name} (${((Date.now() - t0) / 1000).toFixed(1)}s)`);
  return result;
}

const sceneText = fs.readFileSync(scenePath, 'utf8');
const scene = JSON.parse(sceneText);
// The job to cancel: the same scene, far too long to finish during the test.
const longScene = structuredClone(scene);
longScene.name = `${scene.name}-long`;
longScene.film = { ...scene.film, width: 640, height: 480 };
longScene.sampling = { ...scene.sampling, samplesPerPixel: 256 };

fs.mkdirSync(shotDir, { recursive: true });
const browser = await chromium.launch({
  executablePath: browserPath,
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
const pages = [];
const browserLog = [];
const dialogs = [];
let dismissDialogs = false;
async function newPage() {
  const p = await context.newPage();
  const n = pages.push(p);
  p.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') browserLog.push(`page ${n} console.${m.type()}: ${m.text()}`); });
  p.on('pageerror', (e) => browserLog.push(`page ${n} uncaught: ${e.message}`));
  p.on('response', (r) => { if (r.status() >= 400) browserLog.push(`page ${n} HTTP ${r.status()} ${r.request().method()} ${r.url()}`); });
  // A "really cancel?" confirm: recorded, and accepted unless a step said to dismiss it.
  p.on('dialog', (d) => {
    dialogs.push({ page: n, type: d.type(), message: d.message() });
    return dismissDialogs ? d.dismiss() : d.accept();
  });
  return p;
}

// Submits a scene through the jobs page's file input and returns the new job's id. The
// dashboard's POST must answer 200; the id is the one job /api/jobs lists that it did not
// list before (the response body is not read: Chromium keeps it only if the page reads it).
// Submits a scene file, and any other files ({name, buffer}) chosen with it, through the
// job list's file input, and returns the new job's id.
async function submitThroughFileInput(page, sceneJSON, fileName, others = []) {
  const before = new Set((await jobs(page)).map((j) => j.id));
  await page.goto(baseURL + '#/');
  const input = page.locator(tid('submit-file'));
  await waitFor('the submit-file input', 15000, () => input.count());
  const answered = page.waitForResponse((r) => r.request().method() === 'POST' && new URL(r.url()).pathname === '/api/jobs', { timeout: 30000 });
  await input.setInputFiles([{ name: fileName, mimeType: 'application/json', buffer: Buffer.from(sceneJSON) },
    ...others.map((f) => ({ mimeType: 'application/octet-stream', ...f }))]);
  const response = await answered;
  if (response.status() !== 200) {
    const body = await Promise.race([response.text(), sleep(2000).then(() => '(body not available)')]).catch(() => '');
    throw new Failure(`POST /api/jobs answered ${response.status()}: ${body}`);
  }
  const added = await waitFor('the submitted job in GET /api/jobs', 10000, async () =>
    (await jobs(page)).filter((j) => !before.has(j.id)));
  check(added.length === 1, `one submit made ${added.length} jobs: ${added.map((j) => j.id)}`);
  return added[0].id;
}

async function jobs(page) {
  const r = await page.request.get(api('/api/jobs'));
  check(r.status() === 200, `GET /api/jobs answered ${r.status()}: ${await r.text()}`);
  return (await r.json()).jobs ?? [];
}

async function workers(page) {
  const r = await page.request.get(api('/api/workers'));
  check(r.status() === 200, `GET /api/workers answered ${r.status()}: ${await r.text()}`);
  return (await r.json()).workers ?? [];
}

async function jobTasks(page, jobId) {
  const r = await page.request.get(api(`/api/jobs/${jobId}`));
  check(r.status() === 200, `GET /api/jobs/${jobId} answered ${r.status()}: ${await r.text()}`);
  return (await r.json()).tasks ?? [];
}

// Opens task t's log on page, the job's page, with its task-log-button (which: "done", the
// log among its outputs, or "failed", its last failed attempt's), and returns the text
// task-log-text shows, after checking that the log is served as plain text and shown as
// text, not markup.
async function openTaskLog(page, t, which) {
  const log = which === 'done' ? (t.outputs ?? []).find((a) => a.name === 'task.log') : t.log;
  check(log?.digest, `task ${t.id} has no ${which} log: ${JSON.stringify(t)}`);
  const r = await page.request.get(api(`/api/blobs/${log.digest}?name=task.log`));
  check(r.status() === 200, `GET the log of ${t.id} answered ${r.status()}`);
  const type = r.headers()['content-type'];
  const sniff = r.headers()['x-content-type-options'];
  check(type === 'text/plain; charset=utf-8' && sniff === 'nosniff', `the log of ${t.id} is served as ${type} (X-Content-Type-Options ${sniff})`);
  const body = await r.text();
  check(body.length === Number(log.sizeBytes), `the log of ${t.id} has ${body.length} bytes, the artifact says ${log.sizeBytes}`);
  const button = page.locator(`${tid('task-log-button')}[data-task-id="${t.id}"][data-which="${which}"]`);
  await waitFor(`a task-log-button (${which}) on task ${t.id}'s row`, 15000, () => button.count(),
    () => page.locator(tid('task-log-button')).evaluateAll((bs) => bs.slice(0, 5).map((b) => `${b.dataset.taskId}:${b.dataset.which}`)));
  await button.first().click();
  const panel = page.locator(`${tid('task-log')}[data-task-id="${t.id}"][data-ready="true"]`);
  await panel.waitFor({ state: 'visible', timeout: 15000 });
  const text = page.locator(`${tid('task-log')} ${tid('task-log-text')}`);
  check(await text.evaluate((el) => el.children.length) === 0, 'task-log-text holds elements: the log was shown as markup');
  const shown = await text.evaluate((el) => el.textContent);
  check(shown === body, `task-log-text shows ${JSON.stringify(shown.slice(0, 200))}, not the log served`);
  return shown;
}

// The lines of log whose msg is msg and whose task field is taskId.
const linesOf = (log, msg, taskId) => log.split('\n').filter((l) => l.includes(`msg="${msg}"`) && l.includes(` task=${taskId} `));

let exitCode = 0;
try {
  const list = await newPage();

  // (a) Without a token: actions and reads are refused, and the login form shows.
  await step('without a token, POST /api/jobs and GET /api/jobs answer 401 and the login form shows', async () => {
    await list.goto(baseURL);
    const post = await list.request.post(api('/api/jobs'), { data: sceneText, headers: { 'content-type': 'application/json' } });
    check(post.status() === 401, `POST /api/jobs without a token answered ${post.status()}: ${await post.text()}`);
    const get = await list.request.get(api('/api/jobs'));
    check(get.status() === 401, `GET /api/jobs without a token answered ${get.status()}`);
    const session = await (await list.request.get(api('/api/session'))).json();
    check(session.authenticated === false && session.authRequired === true, `GET /api/session: ${JSON.stringify(session)}`);
    await list.locator(tid('login-token')).waitFor({ state: 'visible', timeout: 15000 });
    const wrong = await list.request.post(api('/api/login'), { data: { token: 'not-the-token' } });
    check(wrong.status() === 401, `POST /api/login with a wrong token answered ${wrong.status()}`);
  });

  // (b) Log in through the form.
  await step('logging in with the token through the form', async () => {
    await list.locator(tid('login-token')).fill(token);
    await list.locator(tid('login-submit')).click();
    await list.locator(tid('login-token')).waitFor({ state: 'hidden', timeout: 15000 });
    const session = await (await list.request.get(api('/api/session'))).json();
    check(session.authenticated === true, `GET /api/session after login: ${JSON.stringify(session)}`);
    const jobs = await (await list.request.get(api('/api/jobs'))).json();
    const ids = (jobs.jobs ?? []).map((j) => j.id);
    check(sameJobs(ids, jobsBefore), `the refused POST made a job: ${JSON.stringify(ids)}, want only ${jobsBefore}`);
  });

  // (b2) Pages on another port of the same host (the same site, so SameSite=Strict cookies
  // go with their requests) post text/plain forms to the login and the submit: both are
  // refused, the browser is not logged in and no job is made.
  const site = await startCrossOriginSite(baseURL, token, sceneText);
  await step(`text/plain forms posted from ${site.origin} to the login and the submit are refused`, async () => {
    const formPost = async (ctx, page, endpoint) => {
      const p = await ctx.newPage();
      try {
        const answered = p.waitForResponse((r) => r.request().method() === 'POST' && new URL(r.url()).pathname === endpoint, { timeout: 15000 });
        await p.goto(`${site.origin}${page}`);
        const r = await answered;
        const sent = r.request().headers()['content-type'] ?? '';
        check(sent.startsWith('text/plain'), `the form sent ${sent}, not text/plain`);
        check(r.status() === 403 || r.status() === 415, `the form post to ${endpoint} from ${site.origin} was answered ${r.status()}: ${await r.text().catch(() => '')}`);
        return r.status();
      } finally {
        await p.close();
      }
    };
    const stranger = await browser.newContext();
    try {
      const status = await formPost(stranger, '/login', '/api/login');
      const session = await (await stranger.request.get(api('/api/session'))).json();
      check(session.authenticated === false, `after the cross-port login form, the browser's session: ${JSON.stringify(session)}`);
      console.log(`             login form: ${status}`);
    } finally {
      await stranger.close();
    }
    const status = await formPost(context, '/submit', '/api/jobs');
    const ids = (await jobs(list)).map((j) => j.id);
    check(sameJobs(ids, jobsBefore), `the cross-port submit form made a job: ${JSON.stringify(ids)}`);
    console.log(`             submit form (logged-in browser): ${status}`);
  });
  site.close();

  // The job that failed as bad input opens with a banner saying so, above everything else.
  await step('a job that failed as bad input shows the failure kind and the reason in a banner at the top', async () => {
    await list.goto(`${baseURL}#/jobs/${failedJobId}`);
    const banner = list.locator(tid('failure-banner'));
    await banner.waitFor({ state: 'visible', timeout: 15000 });
    const kind = await banner.getAttribute('data-kind');
    check(kind === 'FAILURE_KIND_BAD_INPUT', `failure-banner data-kind = ${kind}`);
    const label = (await list.locator(tid('failure-kind')).innerText()).trim();
    check(label === 'Bad input:', `failure-kind says ${JSON.stringify(label)}, want "Bad input:"`);
    const message = await list.locator(tid('failure-message')).innerText();
    check(message.includes(failedReason) && message.includes(`task ${failedJobId}.`),
      `failure-message says ${JSON.stringify(message)}, want the task and ${JSON.stringify(failedReason)}`);
    await waitFor('job-state to say failed', 10000, async () =>
      /failed/i.test(await list.locator(tid('job-state')).first().innerText()));
    // At the top: above the progress figures and the tile mosaic.
    const top = (await banner.boundingBox()).y;
    const mosaic = (await list.locator(tid('mosaic')).boundingBox()).y;
    const progress = (await list.locator(tid('job-progress')).first().boundingBox()).y;
    check(top < progress && top < mosaic, `the banner (y ${top}) is not above the progress (y ${progress}) and the mosaic (y ${mosaic})`);
    await list.screenshot({ path: path.join(shotDir, 'failed-job-page.png') });
  });

  // A scene naming a mesh file submits with the file chosen beside it; alone, it is
  // refused, naming the file it lacks.
  const withFile = structuredClone(scene);
  withFile.name = `${scene.name}-with-mesh`;
  withFile.film = { ...scene.film, width: 48, height: 32, tileSize: 16 };
  withFile.progressive = { maxRounds: 1 };
  withFile.shapes = [...withFile.shapes, { name: 'm', material: withFile.shapes[0].material, mesh: { path: 'meshes/octahedron.obj' } }];
  await step('a scene naming a mesh file, chosen alone, is refused naming the file it lacks', async () => {
    await list.goto(baseURL + '#/');
    const input = list.locator(tid('submit-file'));
    await waitFor('the submit-file input', 15000, () => input.count());
    const answered = list.waitForResponse((r) => r.request().method() === 'POST' && new URL(r.url()).pathname === '/api/jobs', { timeout: 30000 });
    await input.setInputFiles({ name: 'with-mesh.json', mimeType: 'application/json', buffer: Buffer.from(JSON.stringify(withFile)) });
    const response = await answered;
    check(response.status() === 400, `POST /api/jobs of a scene naming a mesh file answered ${response.status()}`);
    const text = await waitFor('submit-error', 10000, async () => {
      const el = list.locator(tid('submit-error'));
      return (await el.count()) ? el.innerText() : null;
    });
    for (const want of ['with-mesh.json was refused, nothing was queued', 'names the file meshes/octahedron.obj, which was not sent with the scene']) {
      check(text.includes(want), `submit-error says ${JSON.stringify(text)}, want ${JSON.stringify(want)}`);
    }
  });
  await step('a scene submits from the browser with its mesh file and renders', async () => {
    const mesh = fs.readFileSync(new URL('../../../scenes/meshes/octahedron.obj', import.meta.url));
    const id = await submitThroughFileInput(list, JSON.stringify(withFile), 'with-mesh.json', [{ name: 'octahedron.obj', buffer: mesh }]);
    const job = await waitFor(`job ${id} to succeed`, 60000, async () => {
      const r = await list.request.get(api(`/api/jobs/${id}`));
      const j = (await r.json()).job;
      check(!['JOB_STATE_FAILED', 'JOB_STATE_CANCELLED'].includes(j.state), `the job with a mesh ended ${j.state}: ${j.error}`);
      return j.state === 'JOB_STATE_SUCCEEDED' ? j : null;
    });
    console.log(`             job ${job.id} (with meshes/octahedron.obj) succeeded`);
  });

  // (c) Submit the scene through the file input.
  const jobId = await step('submitting the scene through the submit-file input', () =>
    submitThroughFileInput(list, sceneText, path.basename(scenePath)));
  console.log(`             job ${jobId}`);

  // (d) + (e): the list page shows the job's progress rising, while a second page on the
  // job shows tiles arriving in the mosaic, both before the job ends.
  const row = list.locator(`${tid('job-row')}[data-job-id="${jobId}"]`);
  await step('the job appears in the job list', () =>
    waitFor(`a job-row with data-job-id=${jobId}`, 15000, () => row.count(),
      () => list.locator(tid('job-row')).evaluateAll((rs) => rs.map((r) => r.dataset.jobId))));

  const jobPage = await newPage();
  await jobPage.goto(`${baseURL}#/jobs/${jobId}`);

  // The mosaic is the mean of every round so far: what it showed once each round's
  // composite had been read (its pixels, checked against the final image below), and how
  // much of the canvas it had painted at each sample.
  const mosaicCanvas = jobPage.locator(tid('mosaic-canvas'));
  const mosaicState = () => mosaicCanvas.evaluate((c) => {
    const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let painted = 0;
    for (let i = 3; i < px.length; i += 4) if (px[i] > 0) painted++;
    return { base: Number(c.dataset.baseRound ?? 0), reading: Number(c.dataset.reading ?? 0), painted, px: Array.from(px) };
  });
  const byRound = new Map(); // base round -> the mosaic's RGBA once that round was read
  const runningShot = path.join(shotDir, 'job-page-running.png');
  fs.rmSync(runningShot, { force: true }); // one from an earlier run must not count
  const samples = []; // {state, percent, painted}
  await step('watching the job run (list progress, job page mosaic)', () =>
    waitFor('the job to end', 300000, async () => {
      const state = await row.getAttribute('data-state', { timeout: 2000 });
      // The row's progress bar; the job page's if the row has none.
      const inRow = row.locator(tid('job-progress'));
      const bar = (await inRow.count()) ? inRow.first() : jobPage.locator(tid('job-progress')).first();
      const pct = await bar.getAttribute('data-percent', { timeout: 2000 });
      const m = await mosaicState();
      if (m.base > 0 && m.reading === 0 && !byRound.has(m.base)) byRound.set(m.base, m.px);
      // The job page mid-job, for people to look at (the README's picture).
      if (m.base >= 2 && norm(state) === 'running' && !fs.existsSync(runningShot)) await jobPage.screenshot({ path: runningShot });
      const s = { state: norm(state), percent: pct === null ? NaN : Number(pct), painted: m.painted };
      const last = samples[samples.length - 1];
      if (!last || last.state !== s.state || last.percent !== s.percent || last.painted !== s.painted) samples.push(s);
      return ended(state);
    }, () => samples.slice(-5)));
  const pretty = samples.map((s) => `${s.state}:${s.percent}%/${s.painted}px`).join(' ');
  console.log(`             seen (state:percent/painted pixels): ${pretty}`);

  await step('progress rose while the job ran', () => {
    const final = samples[samples.length - 1];
    check(final.state === 'succeeded', `the job ended ${final.state}`);
    const percents = samples.map((s) => s.percent);
    check(percents.every((p) => Number.isFinite(p) && p >= 0 && p <= 100), `data-percent values out of [0, 100]: ${percents}`);
    for (let i = 1; i < percents.length; i++) {
      check(percents[i] >= percents[i - 1], `data-percent fell from ${percents[i - 1]} to ${percents[i]}`);
    }
    const during = [...new Set(samples.filter((s) => !ended(s.state) && s.percent > 0 && s.percent < 100).map((s) => s.percent))];
    check(during.length >= 2, `want at least two distinct data-percent values in (0, 100) before the job ended, saw ${JSON.stringify(during)}`);
    check(final.percent === 100, `the succeeded job shows ${final.percent}%, want 100`);
  });

  await step('the mosaic painted tiles as they finished, before the job ended', () => {
    const before = samples.filter((s) => !ended(s.state)).map((s) => s.painted);
    const all = scene.film.width * scene.film.height;
    const partial = [...new Set(before.filter((n) => n > 0 && n < all))];
    check(partial.length >= 2, `want the mosaic to paint at least two partial areas of the first round tile by tile, painted pixel counts: ${before}`);
    console.log(`             partial paintings of round 1: ${partial.join(', ')} of ${all} pixels`);
  });
  // (f) The final image.
  await step('the final image shows once the job succeeded', async () => {
    const canvas = jobPage.locator(tid('final-canvas'));
    await canvas.waitFor({ state: 'visible', timeout: 15000 });
    const size = await waitFor('final-canvas to draw image.exr', 15000, () =>
      canvas.evaluate((el) => (el.dataset.layer ? [el.width, el.height] : null)),
    () => jobPage.locator(tid('viewer-status')).innerText());
    check(size[0] === scene.film.width && size[1] === scene.film.height,
      `final-canvas is ${size[0]}x${size[1]}, want ${scene.film.width}x${scene.film.height}`);
    await waitFor('job-state to say succeeded', 10000, async () =>
      /succeeded/i.test(await jobPage.locator(tid('job-state')).first().innerText()),
    () => jobPage.locator(tid('job-state')).first().innerText());
    check(!(await jobPage.locator(tid('failure-banner')).isVisible()), 'a succeeded job shows a failure banner');
  });

  // (f0) The mosaic converges to the final image: its error against the final image (both
  // shown as clipped sRGB at 0 EV) falls as rounds complete, and once the last round is read
  // it is the final image.
  await step('the mosaic\'s error against the final image fell as rounds completed', async () => {
    const rounds = scene.progressive.maxRounds;
    const last = await waitFor(`the mosaic to read round ${rounds}'s composite`, 15000, async () => {
      const m = await mosaicState();
      return m.base === rounds && m.reading === 0 ? m : null;
    }, async () => { const { px, ...m } = await mosaicState(); return m; });
    byRound.set(rounds, last.px);
    const final = await canvasPixels(jobPage);
    const rmse = (px) => {
      let sum = 0;
      let n = 0;
      for (let i = 0; i < px.length; i++) {
        if (i % 4 === 3) continue;
        sum += (px[i] - final[i]) ** 2;
        n++;
      }
      return Math.sqrt(sum / n);
    };
    const seen = [...byRound.keys()].sort((a, b) => a - b);
    const errors = seen.map((r) => rmse(byRound.get(r)));
    console.log(`             RMSE against the final image (8-bit) after rounds ${seen.join(', ')}: ${errors.map((e) => e.toFixed(2)).join(', ')}`);
    check(seen.length >= 3, `the mosaic was seen after only rounds ${seen} of ${rounds}: want three`);
    for (let i = 1; i < errors.length; i++) {
      check(errors[i] < errors[i - 1], `the error rose from ${errors[i - 1].toFixed(3)} (round ${seen[i - 1]}) to ${errors[i].toFixed(3)} (round ${seen[i]})`);
    }
    check(errors[0] > 0.5, `after round ${seen[0]} the mosaic is already the final image (RMSE ${errors[0]}): the rounds are not noisy enough to show convergence`);
    const worst = last.px.reduce((m, v, i) => (i % 4 === 3 ? m : Math.max(m, Math.abs(v - final[i]))), 0);
    check(worst <= 1, `after the last round the mosaic differs from the final image by up to ${worst} levels`);
  });

  // (f0) Task logs: a render tile's log, from the worker that ran it, among its outputs.
  await step('a completed task shows the log its worker uploaded with it', async () => {
    const tile = (await jobTasks(jobPage, jobId)).find((t) => t.phase === 'PHASE_RENDER' && t.state === 'TASK_STATE_SUCCEEDED');
    check(tile, 'no succeeded render task');
    const log = await openTaskLog(jobPage, tile, 'done');
    check(linesOf(log, 'task started', tile.id).length === 1 && linesOf(log, 'task done', tile.id).length === 1,
      `the log of ${tile.id} does not have its "task started" and "task done" lines:\n${log}`);
    check(log.split('\n').filter(Boolean).every((l) => /^time=\S+ level=(DEBUG|INFO|WARN|ERROR) msg=/.test(l)), `a line of ${tile.id}'s log is not a log line:\n${log}`);
    // The same button again closes it.
    await jobPage.locator(`${tid('task-log-button')}[data-task-id="${tile.id}"]`).first().click();
    await jobPage.locator(tid('task-log')).waitFor({ state: 'hidden', timeout: 5000 });
    console.log(`             ${tile.id}: ${log.split('\n').filter(Boolean).length} lines`);
  });

  // A task a real worker failed: its log, sent with the failure report, is the task's log.
  await step('a failed task shows the log its worker sent with the failure', async () => {
    const failedPage = await newPage();
    await failedPage.goto(`${baseURL}#/jobs/${workerFailedJob}`);
    const failed = (await jobTasks(failedPage, workerFailedJob)).find((t) => t.state === 'TASK_STATE_FAILED');
    check(failed, `job ${workerFailedJob} has no failed task`);
    const log = await openTaskLog(failedPage, failed, 'failed');
    const lines = linesOf(log, 'task failed', failed.id);
    check(linesOf(log, 'task started', failed.id).length === 1 && lines.length === 1 && lines[0].includes(workerFailedReason) &&
      lines[0].includes('kind="bad input"'), `the log of ${failed.id} does not say it started and failed with ${JSON.stringify(workerFailedReason)}:\n${log}`);
    await failedPage.screenshot({ path: path.join(shotDir, 'failed-task-log.png'), fullPage: true });
    await failedPage.close();
  });

  // (f1) Workers by name: the task table and the tiles' titles say the --name each worker
  // registered with (farmtest names them worker-1, worker-2), never its id; the photon map's
  // build and merge run in the coordinator, as "coordinator-builder".
  await step('tasks and tiles name their workers, not worker ids', async () => {
    const ids = (await workers(list)).map((w) => w.id);
    check(ids.length === 2, `want two workers, got ${JSON.stringify(ids)}`);
    const shown = await waitFor('every succeeded task row to name its worker', 10000, async () => {
      const cells = await jobPage.locator(`${tid('task-row')}[data-state="TASK_STATE_SUCCEEDED"]`).evaluateAll((rows) => {
        const heads = [...rows[0].closest('table').querySelectorAll('thead th')].map((th) => th.textContent.trim());
        const col = heads.indexOf('Worker');
        return rows.map((r) => r.children[col]?.textContent.trim() ?? '');
      });
      return cells.some((c) => /^worker-[12]$/.test(c)) && cells.every((c) => /^(worker-[12]|coordinator-builder)$/.test(c)) ? cells : null;
    }, () => jobPage.locator(`${tid('task-row')}[data-state="TASK_STATE_SUCCEEDED"]`).allInnerTexts());
    check(!shown.some((c) => ids.includes(c)), `a task row shows a worker id: ${shown}`);
    const titles = await jobPage.locator('.mosaic__slot').evaluateAll((ss) => ss.map((s) => s.title));
    check(titles.length > 0 && titles.every((t) => / · worker-[12]$/.test(t)), `tile titles ${JSON.stringify(titles.slice(0, 3))}: want each to end with its worker's name`);
    check(!titles.some((t) => ids.some((id) => t.includes(id))), 'a tile title shows a worker id');
    console.log(`             ${shown.length} task rows by ${[...new Set(shown)].sort().join(', ')}`);
  });

  // (f2) The viewer's controls: exposure, layers, zoom (viewer.mjs).
  await step('the exposure slider scales the shown pixels by 2^EV in linear light', async () => {
    const at0 = await canvasPixels(jobPage);
    for (const ev of [2, -1]) {
      await setExposure(jobPage, ev);
      const shown = await canvasPixels(jobPage);
      check(hashPixels(shown) !== hashPixels(at0), `the canvas did not change at ${ev} EV`);
      const { compared, wrong } = compareExposure(at0, shown, ev);
      check(compared > 1000 && wrong === 0, `at ${ev} EV, ${wrong} of ${compared} unclipped channels are not 2^${ev} times those at 0 EV`);
      console.log(`             ${ev} EV: ${compared} channels are 2^${ev} times their 0 EV value`);
    }
    await setExposure(jobPage, 0);
    check(hashPixels(await canvasPixels(jobPage)) === hashPixels(at0), 'back at 0 EV the canvas is not what it was');
  });

  await step('the layer switcher shows each of the EXR\'s layers, each different', async () => {
    const names = await jobPage.locator(`${tid('layer-select')} option`).evaluateAll((os) => os.map((o) => o.value));
    check(JSON.stringify(names) === JSON.stringify(WORKER_LAYERS), `layers ${names}, want ${WORKER_LAYERS}`);
    // The scene's materials are all Lambertian (no specular path: the caustic layer is 0),
    // it sets its edge pixels' samples (antialiasing.edge_samples) no higher than every
    // pixel's, so no pixel is supersampled (the edge mask is 0), and it has no medium (the
    // volume layer is 0); every other layer has light.
    const ZERO_LAYERS = ['caustic', 'edge', 'volume'];
    check(scene.materials.every((m) => m.lambert || m.emissive) &&
      scene.antialiasing?.edgeSamples > 0 && scene.antialiasing.edgeSamples <= scene.sampling.samplesPerPixel &&
      !scene.medium && scene.shapes.every((s) => !s.interiorMedium),
    'the scene now has specular materials, edge supersampling or media: update ZERO_LAYERS');
    const seen = new Map();
    for (const name of names) {
      await setLayer(jobPage, name);
      check(await jobPage.locator(tid('final-canvas')).getAttribute('data-layer') === name, `the canvas does not show ${name}`);
      const px = await canvasPixels(jobPage);
      const black = px.every((v, i) => i % 4 === 3 || v === 0);
      if (ZERO_LAYERS.includes(name)) {
        check(black, `layer ${name} is not black, but the scene makes it zero`);
        continue;
      }
      check(!black, `layer ${name} is all black`);
      const h = hashPixels(px);
      check(!seen.has(h), `layer ${name} shows the same pixels as ${seen.get(h)}`);
      seen.set(h, name);
      if (name === 'normal') {
        const { surface, unit } = normalLengths(px);
        check(surface > 1000 && unit / surface > 0.95, `normal layer: ${unit} of ${surface} surface pixels decode to unit vectors`);
        console.log(`             normal: ${unit} of ${surface} surface pixels are unit vectors`);
      }
      if (name === 'depth') {
        const grey = px.every((v, i) => i % 4 === 3 || v === px[i - (i % 4)]);
        const max = px.reduce((m, v, i) => (i % 4 === 3 ? m : Math.max(m, v)), 0);
        check(grey && max === 255, `depth layer: grey ${grey}, brightest ${max} (want grey, the farthest pixel 255)`);
      }
      if (name === 'samples') {
        // No pixel is supersampled and sampling is not adaptive: every pixel drew the
        // same samples, so every one is the largest, white.
        const white = px.every((v, i) => i % 4 === 3 || v === 255);
        check(white, 'samples layer: want every pixel white (the same samples everywhere, shown over the largest)');
      }
    }
    await setLayer(jobPage, 'beauty');
  });

  await step('zoom 1:1 shows one image pixel per CSS pixel, 2x and 4x square pixels without smoothing', async () => {
    const canvas = jobPage.locator(tid('final-canvas'));
    for (const z of [1, 2, 4]) {
      await setZoom(jobPage, String(z));
      const box = await canvas.evaluate((el) => [el.getBoundingClientRect().width, el.getBoundingClientRect().height]);
      check(box[0] === scene.film.width * z && box[1] === scene.film.height * z,
        `zoom ${z}: the canvas is ${box[0]}x${box[1]} CSS pixels, want ${scene.film.width * z}x${scene.film.height * z}`);
    }
    await setZoom(jobPage, '2');
    await canvas.scrollIntoViewIfNeeded();
    const shown = await canvas.screenshot();
    const blank = await context.newPage();
    const { checked, bad, width, height, shift } = await nearestNeighbourMismatches(blank, shown, await canvasPixels(jobPage), scene.film.width, 2);
    await blank.close();
    check(checked > 10000 && bad === 0, `zoom 2: ${bad} of ${checked} screen pixels (of ${width}x${height}) are not their image pixel's colour`);
    console.log(`             zoom 2: ${checked} screen pixels of ${width}x${height} (shifted ${shift}) match their image pixel`);
    await setZoom(jobPage, 'fit');
  });

  // (h) The job page, for people to look at.
  const shot = path.join(shotDir, 'job-page.png');
  await step(`screenshot of the job page to ${shot}`, async () => {
    await jobPage.screenshot({ path: shot, fullPage: true });
    // The viewport from the top (the zoom steps scrolled the viewer): the README's picture.
    await jobPage.evaluate(() => window.scrollTo(0, 0));
    await jobPage.screenshot({ path: path.join(shotDir, 'job-page-done.png') });
    check(fs.existsSync(runningShot), `no screenshot of the job page while it ran (${runningShot}): the mosaic never showed round 2 of a running job`);
  });

  // (g) Both workers are listed.
  await step('the workers page lists both workers', async () => {
    await list.goto(`${baseURL}#/workers`);
    await waitFor('two worker-row elements', 15000, async () => (await list.locator(tid('worker-row')).count()) === 2,
      () => list.locator(tid('worker-row')).allInnerTexts());
  });

  // (h) Unblock, from one of two pages open on the job: it asks first, and both pages
  // see the worker leave the blocked list (the job's changes reach every watcher).
  await step('unblock-button asks first, then unblocks the worker on every open page', async () => {
    await list.goto(`${baseURL}#/jobs/${blockedJob}`);
    await jobPage.goto(`${baseURL}#/jobs/${blockedJob}`);
    for (const p of [list, jobPage]) {
      await waitFor('the blocked worker listed', 15000, async () => (await p.locator(tid('blocked-worker')).count()) === 1,
        () => p.locator(tid('blocked-worker')).allInnerTexts());
    }
    // The worker unregistered, so no name is known for it: its id is shown.
    check((await list.locator(tid('blocked-worker')).innerText()).includes(blockedWorker), 'the blocked worker item does not name the worker');
    dismissDialogs = true;
    let before = dialogs.length;
    await list.locator(tid('unblock-button')).click({ timeout: 15000 });
    await waitFor('a confirm dialog', 5000, () => dialogs.length > before);
    dismissDialogs = false;
    await sleep(1000);
    check((await jobPage.locator(tid('blocked-worker')).count()) === 1, 'a dismissed unblock still unblocked the worker');
    before = dialogs.length;
    await list.locator(tid('unblock-button')).click({ timeout: 15000 });
    check(dialogs.length > before && dialogs[dialogs.length - 1].message.includes('Unblock'), 'the unblock did not ask first');
    for (const p of [list, jobPage]) {
      await waitFor('no blocked worker on both pages', 10000, async () => (await p.locator(tid('blocked-worker')).count()) === 0,
        () => p.locator(tid('blocked-worker')).allInnerTexts());
    }
    const r = await list.request.get(api(`/api/jobs/${blockedJob}`));
    check(((await r.json())?.job?.blockedWorkers ?? []).length === 0, 'GET /api/jobs says a worker is still blocked');
    const c = await list.request.post(api(`/api/jobs/${blockedJob}/cancel`), { data: {} });
    check(c.status() === 200, `cancelling the blocked job answered ${c.status()}`);
  });

  // (i) A long job, cancelled from its page: the state turns cancelled and the workers
  // come back to idle.
  const longId = await step('submitting a long job', () =>
    submitThroughFileInput(list, JSON.stringify(longScene), 'long.json'));
  console.log(`             job ${longId}`);
  await jobPage.goto(`${baseURL}#/jobs/${longId}`);
  await step('the long job keeps a worker busy', () =>
    waitFor('a busy worker', 60000, async () => (await workers(list)).some((w) => norm(w.state) === 'busy' && w.currentTaskId),
      () => workers(list)));
  await step('cancel-button asks first: dismissed, the job runs on', async () => {
    dismissDialogs = true;
    const before = dialogs.length;
    await jobPage.locator(tid('cancel-button')).click({ timeout: 15000 });
    await waitFor('a confirm dialog', 5000, () => dialogs.length > before);
    dismissDialogs = false;
    const d = dialogs[dialogs.length - 1];
    check(d.type === 'confirm' && d.message.includes(longScene.name), `dialog ${JSON.stringify(d)}: want a confirm naming ${longScene.name}`);
    await sleep(1000);
    const r = await list.request.get(api(`/api/jobs/${longId}`));
    const state = norm((await r.json())?.job?.state);
    check(!ended(state), `the dismissed cancel still ended the job: ${state}`);
  });
  const cancelledAt = await step('cancel-button cancels it once confirmed', async () => {
    const before = dialogs.length;
    await jobPage.locator(tid('cancel-button')).click({ timeout: 15000 });
    check(dialogs.length > before, 'the cancel did not ask first');
    await waitFor('job-state to say cancelled', 10000, async () =>
      /cancel/i.test(await jobPage.locator(tid('job-state')).first().innerText()),
    () => jobPage.locator(tid('job-state')).first().innerText());
    const r = await list.request.get(api(`/api/jobs/${longId}`));
    const state = norm((await r.json())?.job?.state);
    check(state === 'cancelled', `GET /api/jobs/${longId} says ${state}`);
    return Date.now();
  });
  await step('the workers are idle within 10 s of the cancel', async () => {
    await waitFor('every worker idle', 10000, async () => {
      const ws = await workers(list);
      return ws.length === 2 && ws.every((w) => norm(w.state) === 'idle' && !w.currentTaskId);
    }, () => workers(list));
    console.log(`             idle ${((Date.now() - cancelledAt) / 1000).toFixed(1)}s after the job showed cancelled`);
  });

  // (j) A job of more tasks than a page: its page reads them a page at a time (no answer
  // holds them all), draws every tile, shows 500 rows and 500 more on "Show more".
  await step('a job of more than 500 tasks: its page reads them in pages of 500 and shows them 500 rows at a time', async () => {
    const many = structuredClone(scene);
    many.name = `${scene.name}-many-tiles`;
    many.film = { ...scene.film, tileSize: 8 }; // 32 x 24 tiles
    const r = await list.request.post(api('/api/jobs'), { data: JSON.stringify(many), headers: { 'content-type': 'application/json' } });
    check(r.status() === 200, `POST /api/jobs answered ${r.status()}: ${await r.text()}`);
    const { job } = await r.json();
    await list.request.post(api(`/api/jobs/${job.id}/cancel`), { data: {} });
    const total = (job.phases ?? []).reduce((n, p) => n + (p.tasksTotal ?? 0), 0);
    const tiles = (job.phases ?? []).find((p) => p.phase === 'PHASE_RENDER')?.tasksTotal ?? 0;
    check(tiles === 768 && total > 500, `the job has ${tiles} tiles and ${total} tasks, want 768 tiles`);
    const sizes = [];
    const onResponse = async (res) => {
      const p = new URL(res.url()).pathname;
      if (p === `/api/jobs/${job.id}` || p === `/api/jobs/${job.id}/tasks`) {
        const body = await res.json().catch(() => ({}));
        sizes.push((body.tasks ?? []).length);
      }
    };
    jobPage.on('response', onResponse);
    try {
      await jobPage.goto(`${baseURL}#/jobs/${job.id}`);
      await waitFor(`${tiles} tile slots in the mosaic`, 20000,
        async () => (await jobPage.locator(`${tid('mosaic')} .mosaic__slot`).count()) === tiles,
        () => jobPage.locator(`${tid('mosaic')} .mosaic__slot`).count());
      const rows = () => jobPage.locator(tid('task-row')).count();
      await waitFor('500 task rows', 10000, async () => (await rows()) === 500, rows);
      await jobPage.locator(tid('tasks-more')).click();
      await waitFor(`${Math.min(total, 1000)} task rows after Show more`, 10000, async () => (await rows()) === Math.min(total, 1000), rows);
      check(sizes.length >= 2 && sizes.every((n) => n <= 500), `task pages read: ${JSON.stringify(sizes)}, want pages of at most 500`);
      console.log(`             ${total} tasks read in pages of ${JSON.stringify(sizes)}`);
    } finally {
      jobPage.off('response', onResponse);
    }
  });

  // (k) Retry and requeue, each from one of two pages open on the job: the job runs again
  // and succeeds, and both pages follow it (an ended job's page watches the job list).
  const bothSucceed = async (id) => {
    for (const p of [list, jobPage]) {
      await waitFor(`job-state to say succeeded on ${p.url()}`, 60000, async () =>
        /succeeded/i.test(await p.locator(tid('job-state')).first().innerText()),
      () => p.locator(tid('job-state')).first().innerText());
      check(await p.locator(tid('failure-banner')).isHidden(), `the failure banner still shows on ${p.url()}`);
    }
    const r = await list.request.get(api(`/api/jobs/${id}`));
    const state = norm((await r.json())?.job?.state);
    check(state === 'succeeded', `GET /api/jobs/${id} says ${state}`);
  };
  await step('retry-button on the failed task queues it again: the job succeeds on both open pages', async () => {
    for (const p of [list, jobPage]) {
      await p.goto(`${baseURL}#/jobs/${failedJobId}`);
      await waitFor('one retry-button, on the failed task', 15000, async () => (await p.locator(tid('retry-button')).count()) === 1,
        () => p.locator(tid('task-row')).evaluateAll((rs) => rs.map((r) => r.dataset.state)));
    }
    await list.locator(tid('retry-button')).click();
    await bothSucceed(failedJobId);
    check((await jobPage.locator(tid('retry-button')).count()) === 0, 'a retry-button is left after the job succeeded');
  });
  await step('requeue-button on a failed job reopens it: it succeeds on both open pages', async () => {
    for (const p of [list, jobPage]) {
      await p.goto(`${baseURL}#/jobs/${requeueJobId}`);
      await p.locator(tid('requeue-button')).waitFor({ state: 'visible', timeout: 15000 });
    }
    await jobPage.locator(tid('requeue-button')).click();
    await bothSucceed(requeueJobId);
    check(await list.locator(tid('requeue-button')).isHidden(), 'the requeue-button still shows on a succeeded job');
  });

  // (l) Delete, from a job page, with two other pages open: the job list and the job. A
  // dismissed confirm changes nothing; a confirmed one removes the job everywhere.
  const listRow = (id) => list.locator(`${tid('job-row')}[data-job-id="${id}"]`);
  const third = await newPage();
  await step('delete-button asks first: dismissed, the job stays', async () => {
    await list.goto(baseURL + '#/');
    await jobPage.goto(`${baseURL}#/jobs/${longId}`);
    await third.goto(`${baseURL}#/jobs/${longId}`);
    await waitFor('the long job in the list', 15000, () => listRow(longId).count());
    await third.locator(tid('delete-button')).waitFor({ state: 'visible', timeout: 15000 });
    dismissDialogs = true;
    const before = dialogs.length;
    await jobPage.locator(tid('delete-button')).click({ timeout: 15000 });
    await waitFor('a confirm dialog', 5000, () => dialogs.length > before);
    dismissDialogs = false;
    const d = dialogs[dialogs.length - 1];
    check(d.type === 'confirm' && d.message.includes('Delete') && d.message.includes(longScene.name), `dialog ${JSON.stringify(d)}: want a confirm naming ${longScene.name}`);
    await sleep(1500);
    const r = await list.request.get(api(`/api/jobs/${longId}`));
    check(r.status() === 200, `after a dismissed delete, GET /api/jobs/${longId} answered ${r.status()}`);
    check((await listRow(longId).count()) === 1, 'after a dismissed delete the job left the list');
  });
  await step('delete-button deletes once confirmed: the job vanishes from every open page and GET /api/jobs', async () => {
    const before = dialogs.length;
    await jobPage.locator(tid('delete-button')).click({ timeout: 15000 });
    check(dialogs.length > before, 'the delete did not ask first');
    await waitFor('the deleting page back on the job list', 10000, () => new URL(jobPage.url()).hash === '#/', () => jobPage.url());
    await waitFor('the job gone from the list on both list pages', 10000, async () =>
      (await listRow(longId).count()) === 0 &&
      (await jobPage.locator(`${tid('job-row')}[data-job-id="${longId}"]`).count()) === 0 &&
      (await jobPage.locator(tid('job-row')).count()) > 0);
    const said = await waitFor('the third page to say the job was deleted', 10000, async () => {
      const el = third.locator(tid('job-missing'));
      return (await el.count()) && /deleted/.test(await el.innerText()) ? el.innerText() : null;
    });
    console.log(`             third page: ${said}`);
    const ids = (await jobs(list)).map((j) => j.id);
    check(!ids.includes(longId), `GET /api/jobs still lists ${longId}`);
    const r = await list.request.get(api(`/api/jobs/${longId}`));
    check(r.status() === 404, `GET /api/jobs/${longId} after the delete answered ${r.status()}`);
  });
  await step('a running job deleted elsewhere: its open page says it was deleted', async () => {
    const r = await list.request.post(api('/api/jobs'), { data: JSON.stringify(longScene), headers: { 'content-type': 'application/json' } });
    check(r.status() === 200, `POST /api/jobs answered ${r.status()}: ${await r.text()}`);
    const { job } = await r.json();
    await third.goto(`${baseURL}#/jobs/${job.id}`);
    await waitFor('the job running on its page', 30000, async () =>
      /running/i.test(await third.locator(tid('job-state')).first().innerText()));
    const d = await list.request.post(api(`/api/jobs/${job.id}/delete`), { data: {} });
    check(d.status() === 200 && norm((await d.json())?.job?.state) === 'cancelled', `POST delete of the running job answered ${d.status()}`);
    await waitFor('its page to say the job was deleted', 10000, async () => {
      const el = third.locator(tid('job-missing'));
      return (await el.count()) && /deleted/.test(await el.innerText());
    }, () => third.locator(tid('job-state')).first().innerText());
    await waitFor('every worker idle', 10000, async () => (await workers(list)).every((w) => norm(w.state) === 'idle'), () => workers(list));
  });

  console.log(`${clock()}  PASS dashboard.spec (screenshot: ${shot})`);
} catch (e) {
  exitCode = 1;
  console.log(`${clock()}  FAIL ${current}`);
  console.log(`             ${e instanceof Failure ? e.message : e.stack}`);
  for (const [i, p] of pages.entries()) {
    const shot = path.join(shotDir, `failure-page${i + 1}.png`);
    try {
      await p.screenshot({ path: shot, fullPage: true, timeout: 5000 });
      console.log(`             page ${i + 1} (${p.url()}) saved to ${shot}`);
    } catch { /* the page may be gone */ }
  }
} finally {
  if (browserLog.length) {
    console.log('browser log (errors, warnings, HTTP >= 400; the 401s before login are expected):');
    // Identical lines (a re-render repeating one error) are counted, not repeated.
    const counts = new Map();
    for (const l of browserLog) {
      const key = l.length > 300 ? `${l.slice(0, 300)}…` : l;
      counts.set(key, (counts.get(key) ?? 0) + 1);
    }
    for (const [l, n] of [...counts].slice(-40)) console.log(`  ${n > 1 ? `(${n}x) ` : ''}${l}`);
  }
  await browser.close().catch(() => {});
}
process.exit(exitCode);
