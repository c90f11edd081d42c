package main

import (
	"math"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
)

// roundJob is a running job with finished rounds (the last ending at lastEnd seconds)
// whose current round has rendered render of 4 tiles and composite of 1.
func roundJob(finished int, lastEnd float64, render, composite uint32) *pb.Job {
	j := testJob(pb.JobState_JOB_STATE_RUNNING, phase(pb.Phase_PHASE_RENDER, 4, render), phase(pb.Phase_PHASE_COMPOSITE, 1, composite))
	for r := range finished {
		j.Rounds = append(j.Rounds, &pb.RoundReport{Round: uint32(r + 1), ElapsedSeconds: lastEnd})
	}
	return j
}

func TestJobFractionFoldsRoundsAndPhases(t *testing.T) {
	type step struct {
		at   float64 // seconds into the job
		job  *pb.Job
		want float64
	}
	ended := roundJob(1, 6, 4, 1)
	ended.State = pb.JobState_JOB_STATE_SUCCEEDED
	for _, tc := range []struct {
		name   string
		rounds int
		steps  []step
	}{
		{"task counts weigh the first round, the times it took the next", 2, []step{
			{0, roundJob(0, 0, 0, 0), 0},
			{4, roundJob(0, 0, 4, 0), 0.4},  // 4 of 5 tasks of round 1 of 2
			{5, roundJob(1, 5, 0, 0), 0.5},  // the next round opened with the report
			{7, roundJob(1, 5, 2, 0), 0.7},  // render took 4 s of 5: half of it is 0.4 of a round
			{9, roundJob(1, 5, 4, 0), 0.9}}, // 4 s of 5 done
		},
		{"a finished round's phases until the next opens", 2, []step{
			{4, roundJob(0, 0, 4, 0), 0.4},
			{5, roundJob(1, 5, 4, 1), 0.5}, // still round 1's phases: not a round and a half
			{6, roundJob(1, 5, 4, 1), 0.5},
			{6.5, roundJob(1, 5, 0, 0), 0.5},
			{7.5, roundJob(1, 5, 1, 0), 0.5 + 0.5*0.2}},
		},
		{"a job that stops early jumps to the end", 6, []step{
			{3, roundJob(0, 0, 4, 0), 0.8 / 6},
			{6, ended, 1}},
		},
		{"rounds not known: never backwards", 0, []step{
			{4, roundJob(0, 0, 4, 0), 0.8}, // as if the only round
			{5, roundJob(1, 5, 0, 0), 0.8}, // one of two now, held at 0.8
			{9, roundJob(1, 5, 4, 0), 0.9}},
		},
	} {
		f := newJobFraction(tc.rounds)
		for i, s := range tc.steps {
			got := f.observe(s.job, t0.Add(time.Duration(s.at*float64(time.Second))))
			if math.Abs(got-s.want) > 1e-9 {
				t.Errorf("%s: step %d (%gs): fraction %g, want %g", tc.name, i, s.at, got, s.want)
			}
		}
	}
}

func TestJobFractionETA(t *testing.T) {
	f := newJobFraction(2)
	if _, ok := f.eta(0); ok {
		t.Error("an ETA before anything is done")
	}
	// 40% in 4 s: 10 s in all, 6 left; then 50% at 5 s agrees with it.
	f.observe(roundJob(0, 0, 4, 0), t0.Add(4*time.Second))
	if eta, ok := f.eta(4 * time.Second); !ok || eta != 6*time.Second {
		t.Errorf("ETA %v, %v; want 6s", eta, ok)
	}
	// Still 40% at 5 s says 12.5 s in all; a second is a fifth of etaSmoothing, so the
	// estimate moves a fifth of the way: 10.5 s in all, 5.5 s left.
	f.observe(roundJob(0, 0, 4, 0), t0.Add(5*time.Second))
	if eta, _ := f.eta(5 * time.Second); (eta - 5500*time.Millisecond).Abs() > time.Millisecond {
		t.Errorf("smoothed ETA %v, want 5.5s", eta)
	}
}
