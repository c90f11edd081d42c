// Package limits runs a job at each size limit of docs/limits.md that bounds memory or a
// blob, on a real farm (`farm coordinator` and `farm-worker` processes from $FARM_BIN_DIR),
// and prints what it cost: time, peak resident memory of the coordinator and the worker,
// blob sizes. By default (make test) each runs reduced; `-limits.full` (make limits) runs
// them at the limits themselves. See tests/README.md, "Limits".
package limits
