// A job's progress and ETA: one fraction for the whole job, its rounds and the phases of
// each folded together (as the CLI's bar does, cmd/farm/fraction.go, there with phase
// times measured from events; here, stateless, phases weigh by their task counts):
// (rounds finished + the current round's tasks succeeded over its tasks) / the rounds the
// plan allows. A job that stops early (target error, time budget) jumps to 1 when it ends.
import { parseTime } from "./format.js";
import { jobEnded } from "./types.js";
export function jobProgress(job) {
    let succeeded = 0;
    let total = 0;
    for (const p of job.phases ?? []) {
        succeeded += p.tasksSucceeded ?? 0;
        total += p.tasksTotal ?? 0;
    }
    const roundsDone = job.rounds?.length ?? 0;
    const ended = jobEnded(job);
    const rounds = Math.max(job.plan?.maxRounds ?? 1, roundsDone + (ended ? 0 : 1), 1);
    // A finished round's phases, before the next round's tasks are listed, count as that
    // round (already in roundsDone), not as the next.
    const current = total > 0 && !(succeeded >= total && roundsDone > 0 && !ended) ? succeeded / total : 0;
    let fraction = (Math.min(roundsDone, rounds) + (roundsDone < rounds ? current : 0)) / rounds;
    if (job.state === "JOB_STATE_SUCCEEDED")
        fraction = 1;
    return {
        fraction: Math.min(1, Math.max(0, fraction)),
        succeeded,
        total,
        round: ended ? Math.max(1, roundsDone) : roundsDone + 1,
        roundsDone,
        rounds,
    };
}
/** Seconds from the job's creation to its end, or to now while it runs. */
export function jobElapsed(job, now) {
    const start = parseTime(job.createTime);
    if (start === undefined)
        return undefined;
    const end = parseTime(job.endTime) ?? now;
    return Math.max(0, (end - start) / 1000);
}
/**
 * Seconds until the job ends, at the rate it has progressed so far (elapsed / fraction):
 * undefined before any of its tasks succeeded, and for jobs not running.
 */
export function jobEta(job, now) {
    if (job.state !== "JOB_STATE_RUNNING")
        return undefined;
    const elapsed = jobElapsed(job, now);
    const p = jobProgress(job);
    if (elapsed === undefined || elapsed <= 0 || p.fraction <= 0 || p.fraction >= 1)
        return undefined;
    return (elapsed * (1 - p.fraction)) / p.fraction;
}
