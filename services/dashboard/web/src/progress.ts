// A job's progress and ETA, from the phase counts of its current round (job.phases holds
// the latest round's) and the rounds it has finished.

import { parseTime } from "./format.js";
import type { Job } from "./types.js";
import { jobEnded } from "./types.js";

export interface Progress {
  /** In [0, 1]: tasks succeeded over tasks planned, in the current round. */
  fraction: number;
  succeeded: number;
  total: number;
  /** The round under way (from 1), or the last one once the job ended. */
  round: number;
  /** Rounds finished. */
  roundsDone: number;
}

export function jobProgress(job: Job): Progress {
  let succeeded = 0;
  let total = 0;
  for (const p of job.phases ?? []) {
    succeeded += p.tasksSucceeded ?? 0;
    total += p.tasksTotal ?? 0;
  }
  const roundsDone = job.rounds?.length ?? 0;
  const ended = jobEnded(job);
  let fraction = total > 0 ? succeeded / total : 0;
  if (job.state === "JOB_STATE_SUCCEEDED") fraction = 1;
  return {
    fraction: Math.min(1, Math.max(0, fraction)),
    succeeded,
    total,
    round: ended ? Math.max(1, roundsDone) : roundsDone + 1,
    roundsDone,
  };
}

/** Seconds from the job's creation to its end, or to now while it runs. */
export function jobElapsed(job: Job, now: number): number | undefined {
  const start = parseTime(job.createTime);
  if (start === undefined) return undefined;
  const end = parseTime(job.endTime) ?? now;
  return Math.max(0, (end - start) / 1000);
}

/**
 * Seconds until the current round ends, at the rate the round has progressed so far:
 * undefined before any of its tasks succeeded, and for jobs not running.
 */
export function jobEta(job: Job, now: number): number | undefined {
  if (job.state !== "JOB_STATE_RUNNING") return undefined;
  const created = parseTime(job.createTime);
  if (created === undefined) return undefined;
  const p = jobProgress(job);
  if (p.fraction <= 0 || p.fraction >= 1) return undefined;
  const last = job.rounds?.[job.rounds.length - 1];
  const roundStart = created + (last?.elapsedSeconds ?? 0) * 1000;
  const spent = (now - roundStart) / 1000;
  if (spent <= 0) return undefined;
  return (spent * (1 - p.fraction)) / p.fraction;
}
