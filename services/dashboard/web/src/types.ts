// The coordinator's messages as the dashboard server sends them: protobuf's canonical JSON
// mapping of proto/renderfarm/v1/job.proto (lowerCamelCase, enums by name, 64-bit integers
// as strings, timestamps as RFC 3339 strings, unset fields omitted — hence the optionals).

export type JobState =
  | "JOB_STATE_UNSPECIFIED"
  | "JOB_STATE_QUEUED"
  | "JOB_STATE_RUNNING"
  | "JOB_STATE_SUCCEEDED"
  | "JOB_STATE_FAILED"
  | "JOB_STATE_CANCELLED";

export type TaskState =
  | "TASK_STATE_UNSPECIFIED"
  | "TASK_STATE_WAITING"
  | "TASK_STATE_QUEUED"
  | "TASK_STATE_LEASED"
  | "TASK_STATE_SUCCEEDED"
  | "TASK_STATE_FAILED"
  | "TASK_STATE_CANCELLED";

export type WorkerState =
  | "WORKER_STATE_UNSPECIFIED"
  | "WORKER_STATE_IDLE"
  | "WORKER_STATE_BUSY"
  | "WORKER_STATE_LOST";

import type { FailureKind, Phase } from "./contract.gen.js";

export type { FailureKind, Phase };

export interface Artifact {
  name?: string;
  digest?: string;
  sizeBytes?: string;
}

export interface PixelRect {
  x?: number;
  y?: number;
  width?: number;
  height?: number;
}

export interface PhaseProgress {
  phase?: Phase;
  tasksTotal?: number;
  tasksSucceeded?: number;
}

export interface PlannedPass {
  name?: string;
  enabled?: boolean;
  reason?: string;
}

export interface RoundReport {
  round?: number;
  elapsedSeconds?: number;
  photons?: string;
  samplesPerPixel?: string;
  errorEstimate?: number;
  errorEstimateBias?: number;
  errorEstimateLow?: number;
  errorEstimateHigh?: number;
  referenceRmse?: number;
  layerReferenceRmse?: Record<string, number>;
}

export interface BlockedWorker {
  workerId?: string;
  reason?: string;
  blockTime?: string;
}

export interface Job {
  id: string;
  displayName?: string;
  state?: JobState;
  createTime?: string;
  updateTime?: string;
  endTime?: string;
  sceneDigest?: string;
  width?: number;
  height?: number;
  phases?: PhaseProgress[];
  error?: string;
  failureKind?: FailureKind;
  outputs?: Artifact[];
  plan?: { passes?: PlannedPass[]; maxRounds?: number };
  rounds?: RoundReport[];
  priority?: number;
  blockedWorkers?: BlockedWorker[];
}

export interface Task {
  id: string;
  jobId?: string;
  index?: number;
  phase?: Phase;
  state?: TaskState;
  attempts?: number;
  workerId?: string;
  error?: string;
  failureKind?: FailureKind;
  renderTile?: { rect?: PixelRect };
  outputs?: Artifact[];
  /** The last failed attempt's log ("task.log"); a success's is among outputs. */
  log?: Artifact;
  round?: number;
  retryTime?: string;
}

export interface WorkerInfo {
  id: string;
  hostname?: string;
  cores?: number;
  version?: string;
  state?: WorkerState;
  currentTaskId?: string;
  tasksDone?: string;
  tasksFailed?: string;
  registerTime?: string;
  lastHeartbeat?: string;
}

/** A page of a job's tasks (/api/jobs/{id}/tasks, and the first with the job): nextPageToken is "" on the last. */
export interface TaskPage {
  tasks?: Task[];
  nextPageToken?: string;
}

/** A page of /api/workers and the workers event: nextPageToken is "" on the last. */
export interface WorkerPage {
  workers?: WorkerInfo[];
  nextPageToken?: string;
}

export interface Session {
  authenticated: boolean;
  authRequired: boolean;
}

export const ENDED_STATES: ReadonlySet<JobState> = new Set<JobState>([
  "JOB_STATE_SUCCEEDED",
  "JOB_STATE_FAILED",
  "JOB_STATE_CANCELLED",
]);

export function jobEnded(job: Job): boolean {
  return job.state !== undefined && ENDED_STATES.has(job.state);
}

export function artifact(list: Artifact[] | undefined, name: string): Artifact | undefined {
  return list?.find((a) => a.name === name && a.digest);
}
