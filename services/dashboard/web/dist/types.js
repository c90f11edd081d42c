// The coordinator's messages as the dashboard server sends them: protobuf's canonical JSON
// mapping of proto/renderfarm/v1/job.proto (lowerCamelCase, enums by name, 64-bit integers
// as strings, timestamps as RFC 3339 strings, unset fields omitted — hence the optionals).
export const ENDED_STATES = new Set([
    "JOB_STATE_SUCCEEDED",
    "JOB_STATE_FAILED",
    "JOB_STATE_CANCELLED",
]);
export function jobEnded(job) {
    return job.state !== undefined && ENDED_STATES.has(job.state);
}
export function artifact(list, name) {
    return list?.find((a) => a.name === name && a.digest);
}
