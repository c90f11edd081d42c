package main

import (
	"fmt"
	"strings"
	"time"

	"photonfarm/coordinator/retention"
	"photonfarm/coordinator/service"
	"photonfarm/coordinator/store/redisstore"
)

// storeSteps is the table of what bounds one store call, from the store's and the
// service's constants.
func storeSteps() string {
	round := largestRound()
	return table("What | Limit", [][2]string{
		{"a lease", "O(log n) in the queued tasks and the jobs in both stores (ready jobs in per-phase heaps or sorted sets; a stage's never-leased tasks a range): p99 under 10 ms with a million tasks queued (`TestLeaseWithAMillionTasksQueued`: 34 to 53 µs in memory, 2.6 to 7.3 ms in Redis here, with 11 to 14 processes runnable on two cores)"},
		{"creating a job, appending a round (Redis)", fmt.Sprintf("%d tasks or %d KiB of arguments a script (`redisstore.StageChunk`, `StageChunkBytes`), then one script that makes the job (or round) visible: a job of %d tasks is about %d scripts of at most a few milliseconds of Redis's CPU (`TestLargestRoundNeverBlocksRedis` bounds each at 20 ms; the longest took 3.8 ms here); a job being created is seen by no read, listing or lease",
			redisstore.StageChunk, redisstore.StageChunkBytes>>10, round, ceilDiv(round, redisstore.StageChunk)+2)},
		{"a coordinator that dies while creating a job (Redis)", fmt.Sprintf("the half-made job is finished by a retry of the submission with the same `request_id` (a different scene under it is `FAILED_PRECONDITION`), else deleted after %s (Retention)", span(retention.DefaultAbandoned))},
		{"opening a stage, ending a job", "O(1) in Redis (a range; an ended job's unfinished tasks read as cancelled), O(the stage or the round) in memory"},
		{"reopening a job (`RequeueJob`, `RetryTask`)", "O(the tasks of its stage leased since the stage opened) in Redis, one script; O(the rest of the round, and the tasks in backoff) in memory. Deleting one (`DeleteJob`) is one step that hides it, then the purge steps of Retention"},
		{"tasks in backoff moved back at a lease", fmt.Sprintf("at most %d a lease (Redis: `redisstore.PromoteBatch`)", redisstore.PromoteBatch)},
		{"expired leases requeued by one script", fmt.Sprintf("%d (`redisstore.ExpireBatch`); the sweep repeats until none is left", redisstore.ExpireBatch)},
		{"an answer lost after Redis ran the call", fmt.Sprintf("every Redis call runs as an operation whose answer is kept %s (`redisstore.OpTTL`): a repeat of the call (go-redis's own retries, or the store's, for up to %s: `RetryWindow`) gets the first run's answer, so a submit makes one job and a report is not refused as a lost lease; past that the store says the outcome is unknown (`UNAVAILABLE`) and a retry with the same `request_id` is safe",
			span(redisstore.OpTTL), span(redisstore.RetryWindow))},
		{"a repeated task report", "`CompleteTask` again under the same lease succeeds only with the same outputs (and, for a round's composite, the same error estimate with its bias part and interval, reference RMSE and layer RMSEs); otherwise `FAILED_PRECONDITION`: `lease epoch E was already completed with other outputs` (or `metrics`)"},
		{"the tasks a lease reads to fill a spec", fmt.Sprintf("only those it needs: the stage before it (tiles, shards, irradiance shards) or one task (a snapshot, the previous round's composite), %d a read (`service.ReadPage`); a round costs the same however many rounds came before it (`TestARoundCostsTheSameHoweverManyCameBefore`: 18 tasks read in round 2 and in round 300)", service.ReadPage)},
	})
}

// retentionTable is the table of what is deleted when, from package retention's defaults.
func retentionTable() string {
	return fmt.Sprintf("Nothing is kept for ever (`coordinator/retention`); the coordinator sweeps when it starts and every %s (`retention.DefaultInterval`).\n\n", span(retention.DefaultInterval)) +
		table("What | Default", [][2]string{
			{"ended job (succeeded, failed, cancelled)", fmt.Sprintf("deleted with its tasks, round reports and request id %s after it ended (`--retention`, `coordinator.Config.Retention`); a `request_id` of a deleted job makes a new job", span(retention.DefaultRetention))},
			{"job deleted (`DeleteJob`: `farm delete`, the dashboard's Delete)", fmt.Sprintf("cancelled if it has not ended, and gone for every read at once; its tasks and round reports are deleted by up to %d purge steps run then (`service.DeletePurgeSteps`; the next sweep finishes a larger job). Its blobs are left to the row below: once no other job refers to them they are deleted after the blob grace, not at once, since another job (a resubmission of the same scene) may share them", service.DeletePurgeSteps)},
			{"blob no job refers to", fmt.Sprintf("deleted once it has been neither written nor touched for %s (`--blob-grace`, `coordinator.Config.BlobGrace`). A job refers to its scene, the files the scene names (scene.Files: mesh files and parts, textures, the reference image), and the outputs of its tasks and of itself (shards, snapshots, irradiance shards, tiles, images). A submit touches the blobs its scene names, and a completion its outputs, before recording them, so a blob uploaded for a submit or a completion in flight is never collected; a blob that is collected the moment a client decided not to upload it again makes that submit fail with `upload the file first`", span(retention.DefaultBlobGrace))},
			{"half-made job (Redis: a coordinator died while creating it)", fmt.Sprintf("deleted once it has not grown for %s (`retention.DefaultAbandoned`); a retry of the submission with the same `request_id` before then finishes it", span(retention.DefaultAbandoned))},
			{"deletion step", fmt.Sprintf("at most %d task records a step (`retention.PurgeBudget`): one Redis script of about a millisecond; a job of %d tasks takes about %d steps", retention.PurgeBudget, largestRound(), ceilDiv(largestRound(), retention.PurgeBudget))},
		})
}

// table is a Markdown table of two columns under header ("A | B").
func table(header string, rows [][2]string) string {
	var b strings.Builder
	fmt.Fprintf(&b, "| %s |\n|---|---|\n", header)
	for _, r := range rows {
		fmt.Fprintf(&b, "| %s | %s |\n", r[0], r[1])
	}
	return b.String()
}

// span writes a whole number of hours, minutes or seconds ("168 h", "2 min").
func span(d time.Duration) string {
	switch {
	case d%time.Hour == 0:
		return fmt.Sprintf("%d h", d/time.Hour)
	case d%time.Minute == 0:
		return fmt.Sprintf("%d min", d/time.Minute)
	}
	return d.String()
}

func ceilDiv(a, b int) int { return (a + b - 1) / b }
