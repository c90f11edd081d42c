// Formatting of durations, times, numbers and enum names for display.

import { FAILURE_KINDS, PHASES } from "./contract.gen.js";
import type { FailureKind, JobState, Phase, TaskState, WorkerState } from "./types.js";

/** Milliseconds since the epoch of an RFC 3339 timestamp, or undefined. */
export function parseTime(ts: string | undefined): number | undefined {
  if (!ts) return undefined;
  const ms = Date.parse(ts);
  return Number.isNaN(ms) ? undefined : ms;
}

/** "850 ms", "12.3 s", "4 m 05 s", "2 h 03 m", "3 d 4 h". */
export function formatDuration(seconds: number | undefined): string {
  if (seconds === undefined || !Number.isFinite(seconds)) return "—";
  const s = Math.max(0, seconds);
  if (s < 1) return `${Math.round(s * 1000)} ms`;
  if (s < 10) return `${s.toFixed(1)} s`;
  if (s < 60) return `${Math.floor(s)} s`;
  const pad = (n: number) => String(n).padStart(2, "0");
  const m = Math.floor(s / 60);
  if (m < 60) return `${m} m ${pad(Math.floor(s % 60))} s`;
  const hrs = Math.floor(m / 60);
  if (hrs < 24) return `${hrs} h ${pad(m % 60)} m`;
  return `${Math.floor(hrs / 24)} d ${hrs % 24} h`;
}

/** An estimate of time left: "~40 s", or "—" when there is none. */
export function formatEta(seconds: number | undefined): string {
  if (seconds === undefined || !Number.isFinite(seconds)) return "—";
  if (seconds < 1) return "< 1 s";
  return `~${formatDuration(seconds)}`;
}

const integer = new Intl.NumberFormat("en-US", { maximumFractionDigits: 0 });
const compact = new Intl.NumberFormat("en-US", { notation: "compact", maximumFractionDigits: 1 });

/** 12,345 (accepts protojson's 64-bit strings). */
export function formatNumber(n: number | string | undefined): string {
  if (n === undefined || n === "") return "0";
  const v = typeof n === "string" ? Number(n) : n;
  return Number.isFinite(v) ? integer.format(v) : String(n);
}

/** 1.2M, 35K. */
export function formatCompact(n: number | string | undefined): string {
  const v = typeof n === "string" ? Number(n) : (n ?? 0);
  return Number.isFinite(v) ? compact.format(v) : String(n);
}

/** An error value (RMSE) with 3 significant digits. */
export function formatError(v: number | undefined): string {
  if (v === undefined || !Number.isFinite(v)) return "—";
  if (v === 0) return "0";
  if (Math.abs(v) < 1e-3 || Math.abs(v) >= 1e4) return v.toExponential(2);
  return v.toPrecision(3);
}

/** An estimated error with its 95% interval: "0.0123 (95%: 0.0101–0.0163)"; the estimate
 * alone when the round reported no interval. */
export function formatEstimate(v: number | undefined, low: number | undefined, high: number | undefined): string {
  const e = formatError(v);
  if (v === undefined || low === undefined || high === undefined) return e;
  return `${e} (95%: ${formatError(low)}–${formatError(high)})`;
}

/** "just now", "12 s ago", "3 min ago", "2 h ago", "4 d ago". */
export function formatRelative(ms: number | undefined, now: number): string {
  if (ms === undefined) return "never";
  const s = Math.round((now - ms) / 1000);
  if (s < 3) return "just now";
  if (s < 60) return `${s} s ago`;
  if (s < 3600) return `${Math.floor(s / 60)} min ago`;
  if (s < 86400) return `${Math.floor(s / 3600)} h ago`;
  return `${Math.floor(s / 86400)} d ago`;
}

const timeOnly = new Intl.DateTimeFormat(undefined, { hour: "2-digit", minute: "2-digit", second: "2-digit" });
const dateTime = new Intl.DateTimeFormat(undefined, {
  month: "short",
  day: "numeric",
  hour: "2-digit",
  minute: "2-digit",
});
const full = new Intl.DateTimeFormat(undefined, { dateStyle: "medium", timeStyle: "medium" });

/** A timestamp: the time alone if it is today, else the date and time. */
export function formatTimestamp(ms: number | undefined, now: number): string {
  if (ms === undefined) return "—";
  const d = new Date(ms);
  return d.toDateString() === new Date(now).toDateString() ? timeOnly.format(d) : dateTime.format(d);
}

export function formatFullTimestamp(ms: number | undefined): string {
  return ms === undefined ? "" : full.format(new Date(ms));
}

/** "JOB_STATE_RUNNING" → "Running". */
function enumLabel(value: string | undefined, prefix: string): string {
  if (!value) return "Unknown";
  const rest = value.startsWith(prefix) ? value.slice(prefix.length) : value;
  const words = rest.toLowerCase().replace(/_/g, " ");
  return words.charAt(0).toUpperCase() + words.slice(1);
}

/** "JOB_STATE_RUNNING" → "running": a CSS class suffix. */
export function enumKey(value: string | undefined, prefix: string): string {
  if (!value) return "unspecified";
  return (value.startsWith(prefix) ? value.slice(prefix.length) : value).toLowerCase();
}

export const jobStateLabel = (s: JobState | undefined) => enumLabel(s, "JOB_STATE_");
export const taskStateLabel = (s: TaskState | undefined) => enumLabel(s, "TASK_STATE_");
export const workerStateLabel = (s: WorkerState | undefined) => enumLabel(s, "WORKER_STATE_");

/** A phase's label in the contract ("Render tiles"). */
export function phaseLabel(p: Phase | undefined): string {
  return PHASES.find((ph) => ph.phase === p)?.label ?? enumLabel(p, "PHASE_");
}

/** A failure kind's label in the contract, capitalised ("Bad input"); "Failed" when unknown. */
export function failureLabel(k: FailureKind | undefined): string {
  if (!k || k === "FAILURE_KIND_UNSPECIFIED" || !(k in FAILURE_KINDS)) return "Failed";
  const label = FAILURE_KINDS[k].label;
  return label.charAt(0).toUpperCase() + label.slice(1);
}

/** A short phase name for table cells. */
export function phaseShort(p: Phase | undefined): string {
  return enumLabel(p, "PHASE_");
}
