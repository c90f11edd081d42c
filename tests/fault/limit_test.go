package fault

import (
	"context"
	"flag"
	"math"
	"strings"
	"sync"
	"syscall"
	"testing"
	"time"

	"photonfarm/client"
	"photonfarm/contract/rules"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/photonmap"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// Issue 12's acceptance 2: a job at the limit on Redis.
var (
	limitTiles  = flag.Int("limit-tiles", 4096, "render tiles of TestJobAtTheLimitOnRedis's job, a square number (issue 12: 65536, make fault-full)")
	limitShards = flag.Int("limit-shards", 500, "emission shards per photon map of TestJobAtTheLimitOnRedis's job (issue 12: 10000, make fault-full)")
)

// limitScene is a scene of -limit-tiles tiles of 8 pixels (small tiles, so that the film of
// the most tiles stays within max_film_pixels: 65,536 tiles are a 2048x2048 film) and, for a global and a caustic
// photon map, -limit-shards emission shards of the fewest photons a shard may have, with
// final gathering: with the full flags, the largest round validation allows (95,539
// tasks: docs/limits.md, "Planning").
func limitScene(t *testing.T) *pb.Scene {
	side := uint32(math.Sqrt(float64(*limitTiles)))
	if int(side*side) != *limitTiles {
		t.Fatalf("-limit-tiles %d is not a square number", *limitTiles)
	}
	per := uint64(rules.Min(&pb.PhotonMapping{}, "photons_per_shard"))
	sc := scenetest.Valid(8*side, 8*side)
	sc.Name = "at the limit"
	sc.Film.TileSize = 8
	sc.Materials = append(sc.Materials, &pb.Material{Name: "mirror", Kind: &pb.Material_Mirror{Mirror: &pb.Mirror{Reflectance: &pb.Color{R: 0.9, G: 0.9, B: 0.9}}}})
	sc.Shapes = append(sc.Shapes, &pb.Shape{Name: "mirror ball", Material: "mirror", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: scenetest.V(1.5, 0.5, 0), Radius: 0.5}}})
	n := uint64(*limitShards) * per
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: n, CausticPhotons: n, PhotonsPerShard: per}
	return sc
}

// fakeOutputs makes what a fake worker reports for a task of the job at the limit: valid
// (empty) photon shards, since the coordinator's builder reads them, and one uploaded blob
// under the contract's names for everything else (not the precompute's: the real workers
// do it).
type fakeOutputs struct {
	f    *farmtest.Farm
	ctx  context.Context
	blob *pb.Artifact
}

func (o fakeOutputs) upload(t *testing.T, data []byte) *pb.Artifact {
	d, err := o.f.Client.UploadBytes(o.ctx, data)
	if err != nil {
		t.Errorf("upload: %v", err)
	}
	return &pb.Artifact{Digest: d, SizeBytes: int64(len(data))}
}

func (o fakeOutputs) of(t *testing.T, task *pb.Task) []*pb.Artifact {
	content := o.blob
	switch spec := task.GetSpec().(type) {
	case *pb.Task_EmitPhotons:
		e := spec.EmitPhotons
		content = o.upload(t, photonmap.EncodeShard(photonmap.Kind(e.GetMap()), e.GetFirstPhoton(), e.GetPhotonCount(), nil))
	}
	ph, _ := tasks.Phases.Of(task.GetPhase())
	var names []string
	for _, k := range ph.Outputs {
		names = append(names, tasks.ArtifactName(k))
	}
	return named(content, names...)
}

// waitForPhase waits until every task of the job's phase p (of its first round) has
// succeeded.
func waitForPhase(t *testing.T, ctx context.Context, f *farmtest.Farm, jobID string, p pb.Phase) {
	t.Helper()
	for {
		job, err := f.Client.GetJob(ctx, jobID)
		if err != nil {
			t.Fatalf("job %s: %v", jobID, err)
		}
		for _, ph := range job.GetPhases() {
			if ph.GetPhase() == p && ph.GetTasksTotal() > 0 && ph.GetTasksSucceeded() == ph.GetTasksTotal() {
				return
			}
		}
		select {
		case <-ctx.Done():
			t.Fatalf("job %s: %v before its %v phase ended (last seen: %v)", jobID, ctx.Err(), p, job)
		case <-time.After(100 * time.Millisecond):
		}
	}
}

// probe times a call every interval until ctx is done, and counts its errors by message.
// A call may return what to do after it (a release of what it leased), which is not timed.
type probe struct {
	mu     sync.Mutex
	lat    storetest.Latencies
	errors map[string]int
}

func (p *probe) run(ctx context.Context, interval time.Duration, call func() (after func() error, err error)) {
	p.errors = map[string]int{}
	for ctx.Err() == nil {
		t0 := time.Now()
		after, err := call()
		d := time.Since(t0)
		if err == nil && after != nil {
			err = after()
		}
		p.mu.Lock()
		if err != nil && ctx.Err() == nil {
			p.errors[err.Error()]++
		} else if err == nil {
			p.lat = append(p.lat, d)
		}
		p.mu.Unlock()
		time.Sleep(interval)
	}
}

// TestJobAtTheLimitOnRedis submits a job at the limit (-limit-tiles tiles and -limit-shards
// shards per map: the largest round validation allows with make fault-full's flags) to a
// coordinator on Redis, and a small job at priority 1000 beside it, rendered by two real
// workers; four fake workers (fakeOutputs) do the big job's tasks through the gRPC API and
// release the small job's and the big job's precompute parts (the real workers do those,
// and stop once the big job's merge is done). Meanwhile a Redis client PINGs every 5 ms and a registered
// worker calls LeaseTask (releasing what it gets) every 20 ms. Both jobs must succeed, no
// PING may see BUSY or any error, and the p99 of every LeaseTask (the probe's and the fake
// workers') must stay under 50 ms, the figure; it prints p50, p99 and max of each (the fake workers'
// by phase: the composite's lease carries every tile), of PING, the longest Redis
// command, the submit's time and the job's.
func TestJobAtTheLimitOnRedis(t *testing.T) {
	const leaseP99 = 50 * time.Millisecond
	rs := redistest.Start(t)
	rs.LogSlowCommands(time.Millisecond)
	f := farmtest.StartFarm(t, []string{"--redis", "redis://" + rs.Addr(), "--redis-prefix", "limit:", "--lease-duration", "10s"})
	ctx, cancel := context.WithTimeout(context.Background(), 25*time.Minute)
	defer cancel()
	probes, stopProbes := context.WithCancel(ctx)
	var wg sync.WaitGroup
	var ping, lease probe
	rdb := rs.Client()
	wg.Add(2)
	go func() {
		defer wg.Done()
		ping.run(probes, 5*time.Millisecond, func() (func() error, error) { return nil, rdb.Ping(probes).Err() })
	}()
	prober := fakeWorker(t, f.Addr, 99)
	defer prober.close()
	go func() {
		defer wg.Done()
		lease.run(probes, 20*time.Millisecond, func() (func() error, error) {
			resp, err := prober.ws.LeaseTask(probes, &pb.LeaseTaskRequest{WorkerId: prober.id})
			l := resp.GetLease()
			if err != nil || l == nil {
				return nil, err
			}
			return func() error {
				_, err := prober.ws.ReleaseTask(probes, &pb.ReleaseTaskRequest{WorkerId: prober.id, TaskId: l.GetTaskId(), Epoch: l.GetEpoch()})
				return err
			}, nil
		})
	}()

	blob := []byte("not really an image")
	digest, err := f.Client.UploadBytes(ctx, blob)
	if err != nil {
		t.Fatal(err)
	}
	outs := fakeOutputs{f: f, ctx: ctx, blob: &pb.Artifact{Digest: digest, SizeBytes: int64(len(blob))}}

	var workers []*farmtest.Proc
	for range 2 {
		workers = append(workers, f.StartWorker(t))
	}
	t0 := time.Now()
	big := f.Submit(t, limitScene(t))
	submitted := time.Since(t0)
	small := tinyScene(t, f, 7)
	smallJob, err := f.Client.Submit(ctx, small, client.WithPriority(store.MaxPriority))
	if err != nil {
		t.Fatal(err)
	}
	ended := make(chan struct{})
	go func() {
		defer close(ended)
		f.Client.Watch(ctx, big.GetId(), nil)
	}()
	var (
		mu      sync.Mutex
		leaseAt = map[pb.Phase]storetest.Latencies{}
		fakes   sync.WaitGroup
	)
	for w := range 4 {
		fakes.Add(1)
		go func() {
			defer fakes.Done()
			lw := fakeWorker(t, f.Addr, w)
			defer lw.close()
			cl := lw.run(t, ctx, ended, func(resp *pb.LeaseTaskResponse) []*pb.Artifact {
				// The small job's tasks are the real workers', and so are the big job's
				// precompute parts: how many irradiance sites the parts share is the
				// worker's rule (docs/photon-snapshot.md), which a fake cannot follow.
				if resp.GetTask().GetJobId() != big.GetId() || resp.GetTask().GetPrecomputeIrradiance() != nil {
					return nil
				}
				return outs.of(t, resp.GetTask())
			})
			mu.Lock()
			for i, d := range cl.leases {
				leaseAt[cl.phases[i]] = append(leaseAt[cl.phases[i]], d)
			}
			mu.Unlock()
		}()
	}
	f.Wait(t, smallJob.GetId(), 5*time.Minute)
	smallTook := time.Since(t0)
	waitForPhase(t, ctx, f, big.GetId(), pb.Phase_PHASE_MERGE)
	for _, w := range workers {
		w.Kill(syscall.SIGTERM) // before the big job's composite, which only fakes can do
	}
	done := f.Wait(t, big.GetId(), 20*time.Minute)
	took := time.Since(t0)
	fakes.Wait()
	stopProbes()
	wg.Wait()

	n := 0
	for _, ph := range done.GetPhases() {
		n += int(ph.GetTasksTotal())
	}
	t.Logf("job of %d tasks (%d tiles, %d shards per map): submitted in %v, rendered in %v; the small job beside it took %v",
		n, *limitTiles, *limitShards, submitted.Round(time.Millisecond), took.Round(time.Second), smallTook.Round(time.Millisecond))
	var all storetest.Latencies
	for _, ph := range tasks.Phases {
		if l := leaseAt[ph.Phase]; len(l) > 0 {
			t.Logf("fake workers' LeaseTask (%s): %v", strings.ToLower(ph.Label), l)
			all = append(all, l...)
		}
	}
	t.Logf("probe's LeaseTask: %v", lease.lat)
	t.Logf("PING: %v", ping.lat)
	// Printed, not bounded: the slow log times by the clock, which a loaded machine
	// stretches; redisstore's TestLargestRoundNeverBlocksRedis bounds the CPU a script
	// takes, and the clients' view is bounded above and below.
	slowest, cmd := rs.SlowestCommand()
	t.Logf("longest Redis command: %v (%s)", slowest, cmd)
	for msg, k := range ping.errors {
		t.Errorf("PING failed %d times: %s", k, msg)
	}
	for msg, k := range lease.errors {
		t.Errorf("the probe's LeaseTask failed %d times: %s", k, msg)
	}
	for what, l := range map[string]storetest.Latencies{"the fake workers'": all, "the probe's": lease.lat} {
		if p99 := l.Pct(99); p99 > leaseP99 {
			t.Errorf("%s LeaseTask p99 %v, want under %v", what, p99, leaseP99)
		}
	}
}
