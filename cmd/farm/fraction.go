package main

import (
	"time"

	pb "photonfarm/proto/renderfarm/v1"
)

// jobFraction folds a job's rounds and the phases of each round into one fraction done,
// and estimates the time left from it.
//
// A round's phases are weighted by their expected cost: before any round has finished,
// by their task counts (a task as dear as any other); once one has, by the seconds each
// phase took in the finished rounds (their mean), measured from the events' times. The
// job is rounds equal rounds: fraction = (finished rounds + fraction of the current
// round) / rounds. A job that stops early (target error, time budget) jumps to 1 when it
// ends. The fraction shown never goes backwards: a new weighting may estimate less than
// the last one did, and the larger stands.
//
// The ETA is the job's total time estimated as elapsed / fraction, smoothed over
// etaSmoothing of event time (rounds' fixed costs and uneven tiles make it jitter),
// minus the time elapsed.
type jobFraction struct {
	rounds int // planned; 0 if unknown: the rounds seen so far, plus the one running

	finished   int                    // rounds finished when last observed
	roundStart time.Time              // when the current round began
	completed  map[pb.Phase]time.Time // when each phase of the current round completed
	spent      map[pb.Phase]time.Duration
	measured   int        // rounds whose phase times are in spent
	stale      bool       // the job's phases are still the finished round's
	phases     []pb.Phase // of the current round, in order

	shown    float64
	total    time.Duration // smoothed estimate of the job's run time
	lastSeen time.Time
}

const etaSmoothing = 5 * time.Second

func newJobFraction(rounds int) *jobFraction {
	return &jobFraction{rounds: rounds, completed: map[pb.Phase]time.Time{}, spent: map[pb.Phase]time.Duration{}}
}

// observe takes the job as it stood at time at (the event's time) and returns the
// fraction done.
func (f *jobFraction) observe(job *pb.Job, at time.Time) float64 {
	start := at
	if t := job.GetCreateTime(); t != nil {
		start = t.AsTime()
	}
	if f.roundStart.IsZero() {
		f.roundStart = start
	}
	if f.stale && !allComplete(job.GetPhases()) {
		f.stale = false // the next round has opened
	}
	if len(job.GetRounds()) > f.finished {
		f.finishRound(job, start, at)
	}
	if !f.stale {
		// This round's phases, those completed stamped with the event's time.
		f.phases = f.phases[:0]
		for _, ph := range job.GetPhases() {
			f.phases = append(f.phases, ph.GetPhase())
			if _, seen := f.completed[ph.GetPhase()]; !seen && ph.GetTasksTotal() > 0 && ph.GetTasksSucceeded() >= ph.GetTasksTotal() {
				f.completed[ph.GetPhase()] = at
			}
		}
	}
	f.shown = max(f.shown, f.estimate(job))
	f.smooth(at.Sub(start), at)
	return f.shown
}

// finishRound records the phase times of the round that just finished (if the events
// saw it whole) and starts the next.
func (f *jobFraction) finishRound(job *pb.Job, start, at time.Time) {
	rounds := job.GetRounds()
	end := at
	if s := rounds[len(rounds)-1].GetElapsedSeconds(); s > 0 {
		end = start.Add(time.Duration(s * float64(time.Second)))
	}
	// The phases whose completion no event showed (the last, whose completion ended
	// the round, and any the events skipped) completed by the round's end.
	for _, p := range f.phases {
		if _, ok := f.completed[p]; !ok {
			f.completed[p] = end
		}
	}
	// Only one round finished since the last event, and its phases were seen: the
	// phase times of the round are differences of completion times.
	if len(rounds) == f.finished+1 && len(f.phases) > 0 {
		prev := f.roundStart
		for _, p := range f.phases { // phases run in this order
			f.spent[p] += f.completed[p].Sub(prev)
			prev = f.completed[p]
		}
		f.measured++
	}
	f.finished = len(rounds)
	f.roundStart = end
	clear(f.completed)
	// Until the next round opens, the job's phases are those of the finished one.
	f.stale = allComplete(job.GetPhases())
}

func allComplete(phases []*pb.PhaseProgress) bool {
	for _, ph := range phases {
		if ph.GetTasksSucceeded() < ph.GetTasksTotal() {
			return false
		}
	}
	return true
}

// estimate is the fraction done by the current weights, not yet held monotonic.
func (f *jobFraction) estimate(job *pb.Job) float64 {
	if job.GetState() == pb.JobState_JOB_STATE_SUCCEEDED {
		return 1
	}
	rounds := f.rounds
	if rounds < f.finished+1 {
		rounds = f.finished + 1
	}
	var done, all float64
	for _, ph := range job.GetPhases() {
		w := float64(ph.GetTasksTotal())
		if f.measured > 0 {
			w = f.spent[ph.GetPhase()].Seconds() / float64(f.measured)
		}
		if ph.GetTasksTotal() > 0 {
			done += w * min(1, float64(ph.GetTasksSucceeded())/float64(ph.GetTasksTotal()))
		}
		all += w
	}
	round := 0.0
	if all > 0 {
		round = done / all
	}
	if f.stale {
		round = 0
	}
	return min(1, (float64(f.finished)+round)/float64(rounds))
}

// smooth updates the estimate of the job's run time at time at, elapsed into the job.
func (f *jobFraction) smooth(elapsed time.Duration, at time.Time) {
	if f.shown <= 0 || elapsed <= 0 {
		return
	}
	total := time.Duration(float64(elapsed) / f.shown)
	if f.total == 0 {
		f.total, f.lastSeen = total, at
		return
	}
	weight := min(1, float64(at.Sub(f.lastSeen))/float64(etaSmoothing))
	f.total += time.Duration(weight * float64(total-f.total))
	f.lastSeen = at
}

// eta is the time left when elapsed into the job; ok is false while there is nothing
// to go on.
func (f *jobFraction) eta(elapsed time.Duration) (time.Duration, bool) {
	if f.total == 0 {
		return 0, false
	}
	return max(0, f.total-elapsed), true
}
