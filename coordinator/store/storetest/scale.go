package storetest

import (
	"context"
	"fmt"
	"slices"
	"sync"
	"sync/atomic"
	"testing"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Scale measurements shared by the stores' own tests (reduced counts) and tests/fault (the
// issue's figures): how LeaseTask behaves with many tasks queued.

// Fill queues about n render tasks in s, in jobs of at most perJob tiles (a round has at
// most about 95,500 tasks, so a million queued tasks are several jobs), and returns the
// jobs.
func Fill(t testing.TB, s store.Store, n, perJob int) []*pb.Job {
	t.Helper()
	var jobs []*pb.Job
	for left := n; left > 0; left -= perJob {
		j, err := s.CreateJob(context.Background(), TileJob(fmt.Sprint("backlog", len(jobs)), min(left, perJob)))
		if err != nil {
			t.Fatalf("CreateJob: %v", err)
		}
		jobs = append(jobs, j)
	}
	return jobs
}

// Latencies are measured durations, with their percentiles.
type Latencies []time.Duration

// Pct is the p-th percentile (nearest rank), 0 if there is none.
func (l Latencies) Pct(p int) time.Duration {
	if len(l) == 0 {
		return 0
	}
	s := slices.Clone(l)
	slices.Sort(s)
	return s[max((len(s)*p+99)/100-1, 0)]
}

func (l Latencies) String() string {
	return fmt.Sprintf("p50 %v, p99 %v, max %v (%d calls)", l.Pct(50).Round(time.Microsecond),
		l.Pct(99).Round(time.Microsecond), l.Pct(100).Round(time.Microsecond), len(l))
}

// Worker is a fake worker: it leases any task and completes it after taskTime (with an
// output named as the contract expects of its phase), timing every LeaseTask.
type Worker struct {
	S        store.Store
	ID       string
	TaskTime time.Duration
}

// Run leases and completes tasks until stop says so, and returns its LeaseTask latencies.
// stop is asked after every LeaseTask (with the zero Change) and every completion (with
// its Change). Errors are reported with t.Errorf (Run may run on a goroutine of its own).
func (w Worker) Run(t testing.TB, stop func(store.Change) bool) Latencies {
	ctx := context.Background()
	var lat Latencies
	for {
		t0 := time.Now()
		l, err := w.S.LeaseTask(ctx, w.ID, store.WorkerPhases)
		lat = append(lat, time.Since(t0))
		if err != nil {
			t.Errorf("%s: LeaseTask: %v", w.ID, err)
			return lat
		}
		if stop(store.Change{}) {
			return lat
		}
		if l == nil {
			time.Sleep(time.Millisecond)
			continue
		}
		time.Sleep(w.TaskTime)
		name := "tile.exr"
		if l.Task.GetComposite() != nil {
			name = "image.exr"
		}
		c, err := w.S.CompleteTask(ctx, store.LeaseRef{WorkerID: w.ID, TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch},
			[]*pb.Artifact{artifact(name, l.Lease.TaskId)})
		if err != nil {
			t.Errorf("%s: CompleteTask(%s): %v", w.ID, l.Lease.TaskId, err)
			return lat
		}
		if stop(c) {
			return lat
		}
	}
}

// crew runs n Workers on s until stop says so and returns all their latencies.
func crew(t testing.TB, s store.Store, name string, n int, taskTime time.Duration, stop func(store.Change) bool) Latencies {
	var (
		mu  sync.Mutex
		all Latencies
		wg  sync.WaitGroup
	)
	for i := range n {
		wg.Add(1)
		go func() {
			defer wg.Done()
			lat := Worker{S: s, ID: fmt.Sprint(name, "-", i), TaskTime: taskTime}.Run(t, stop)
			mu.Lock()
			all = append(all, lat...)
			mu.Unlock()
		}()
	}
	wg.Wait()
	return all
}

// Leases has `workers` fake workers lease and complete tasks of s, each held taskTime,
// until they have made n LeaseTask calls between them, and returns their latencies.
func Leases(t testing.TB, s store.Store, workers, n int, taskTime time.Duration) Latencies {
	var calls atomic.Int64
	return crew(t, s, "busy-worker", workers, taskTime, func(c store.Change) bool {
		return c.Job == nil && calls.Add(1) >= int64(n)
	})
}

// UrgentJob times a job of `tiles` tiles at the highest priority from submission to
// success, run by `workers` fake workers taking taskTime a task while the rest of s waits,
// and returns how long it took and every LeaseTask latency its workers saw.
func UrgentJob(t testing.TB, s store.Store, tiles, workers int, taskTime time.Duration) (time.Duration, Latencies) {
	t.Helper()
	nj := TileJob("urgent", tiles)
	nj.Priority = store.MaxPriority
	start := time.Now()
	j, err := s.CreateJob(context.Background(), nj)
	if err != nil {
		t.Fatalf("CreateJob: %v", err)
	}
	var done atomic.Bool
	deadline := start.Add(10 * time.Minute)
	lat := crew(t, s, "urgent-worker", workers, taskTime, func(c store.Change) bool {
		if c.Job.GetId() == j.Id && c.Job.GetState() == pb.JobState_JOB_STATE_SUCCEEDED {
			done.Store(true)
		}
		return done.Load() || time.Now().After(deadline)
	})
	if !done.Load() {
		t.Errorf("the urgent job did not finish in 10 minutes")
	}
	return time.Since(start), lat
}

// LargestRound is round r of the largest plan scene validation allows (docs/limits.md,
// "Planning"): per map max_shards_per_map emission shards for the global, the caustic and
// the volume map, a build, max_shards_per_map precompute tasks, a merge, max_tiles_per_round tiles
// and a composite, indexed from 0.
func LargestRound(r uint32) []*pb.Task {
	shards, tiles := int(rules.Scene.GetMaxShardsPerMap()), int(rules.Scene.GetMaxTilesPerRound())
	var ts []*pb.Task
	add := func(n int, t func(i int) *pb.Task) {
		for i := range n {
			task := t(i)
			task.Index, task.Round = uint32(len(ts)), r
			task.Phase = tasks.PhaseOf(task)
			ts = append(ts, task)
		}
	}
	maps := []pb.PhotonMapKind{pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL, pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC, pb.PhotonMapKind_PHOTON_MAP_KIND_VOLUME}
	add(len(maps)*shards, func(i int) *pb.Task {
		kind := maps[i/shards]
		return &pb.Task{Spec: &pb.Task_EmitPhotons{EmitPhotons: &pb.EmitPhotonsSpec{Map: kind, FirstPhoton: uint64(1000 * (i % shards)),
			PhotonCount: 1000, TotalPhotons: uint64(1000 * shards)}}}
	})
	add(1, func(int) *pb.Task {
		return &pb.Task{Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{}}}
	})
	add(shards, func(int) *pb.Task {
		return &pb.Task{Spec: &pb.Task_PrecomputeIrradiance{PrecomputeIrradiance: &pb.PrecomputeIrradianceSpec{RadiusScale: 1}}}
	})
	add(1, func(int) *pb.Task {
		return &pb.Task{Spec: &pb.Task_MergeIrradiance{MergeIrradiance: &pb.MergeIrradianceSpec{}}}
	})
	add(tiles, func(i int) *pb.Task {
		return &pb.Task{Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{
			Rect: &pb.PixelRect{X: uint32(64 * (i % 256)), Y: uint32(64 * (i / 256)), Width: 64, Height: 64}, RadiusScale: 1}}}
	})
	add(1, func(int) *pb.Task { return &pb.Task{Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}} })
	return ts
}

// CountState counts the tasks of ts in state st.
func CountState(ts []*pb.Task, st pb.TaskState) int {
	n := 0
	for _, t := range ts {
		if t.GetState() == st {
			n++
		}
	}
	return n
}
