package integration

import (
	"bytes"
	"context"
	"io"
	"net/http"
	"regexp"
	"slices"
	"strconv"
	"strings"
	"sync"
	"syscall"
	"testing"
	"time"

	"photonfarm/client"
	"photonfarm/coordinator/blobstore/s3test"
	"photonfarm/coordinator/store/redisstore/redistest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// Coordinator replicas (issue 17): two `farm coordinator` processes on one redis-server and
// one SeaweedFS bucket serve the same jobs; workers are given both addresses.

// replicaScene is scenes/test-small.json at 96x64 in 24 tiles, long enough on two
// one-thread workers for a replica to be killed while tiles are still to render.
func replicaScene(t *testing.T, f *farmtest.Farm) *pb.Scene {
	return f.TestScene(t, 96, 64, 16, 2)
}

// watchEvents follows WatchJob on c until the job ends, keeping every event.
type watchEvents struct {
	mu     sync.Mutex
	events []*pb.WatchJobResponse
	done   chan struct{}
	job    *pb.Job
	err    error
}

func watch(c *client.Client, jobID string, timeout time.Duration) *watchEvents {
	w := &watchEvents{done: make(chan struct{})}
	go func() {
		defer close(w.done)
		ctx, cancel := context.WithTimeout(context.Background(), timeout)
		defer cancel()
		w.job, w.err = c.Watch(ctx, jobID, func(ev *pb.WatchJobResponse) {
			w.mu.Lock()
			w.events = append(w.events, ev)
			w.mu.Unlock()
		})
	}()
	return w
}

// succeededTasks is the set of tasks whose success an event told of.
func (w *watchEvents) succeededTasks() map[string]bool {
	w.mu.Lock()
	defer w.mu.Unlock()
	seen := map[string]bool{}
	for _, ev := range w.events {
		if ev.GetKind() == pb.JobEventKind_JOB_EVENT_KIND_TASK_UPDATED && ev.GetTask().GetState() == pb.TaskState_TASK_STATE_SUCCEEDED {
			seen[ev.GetTask().GetId()] = true
		}
	}
	return seen
}

// workerNames lists the names of the workers c's replica knows, sorted.
func workerNames(t *testing.T, c *client.Client) []string {
	t.Helper()
	ws, err := c.ListWorkers(context.Background())
	if err != nil {
		t.Fatalf("list workers: %v", err)
	}
	var names []string
	for _, w := range ws {
		if w.GetState() != pb.WorkerState_WORKER_STATE_LOST {
			names = append(names, w.GetHostname())
		}
	}
	slices.Sort(names)
	return names
}

var metricsLine = regexp.MustCompile(`metrics on (http://\S+/metrics)`)

// leasesGranted is what coordinator p's farm_leases_granted_total counters add up to.
func leasesGranted(t *testing.T, p *farmtest.Proc) float64 {
	t.Helper()
	m := metricsLine.FindStringSubmatch(p.LogTail(1 << 20))
	if m == nil {
		t.Fatalf("%s did not say where its metrics are", p.Name)
	}
	resp, err := http.Get(m[1])
	if err != nil {
		t.Fatal(err)
	}
	defer resp.Body.Close()
	body, err := io.ReadAll(resp.Body)
	if err != nil {
		t.Fatal(err)
	}
	var sum float64
	for _, line := range strings.Split(string(body), "\n") {
		if rest, ok := strings.CutPrefix(line, "farm_leases_granted_total{"); ok {
			_, value, _ := strings.Cut(rest, "} ")
			n, err := strconv.ParseFloat(value, 64)
			if err != nil {
				t.Fatalf("%s: metrics line %q: %v", p.Name, line, err)
			}
			sum += n
		}
	}
	return sum
}

// TestReplicaKilledMidJobTheOtherFinishesItBitIdentical submits to replica A, has two
// workers spread their calls over A and B (and a client of both watch the job), SIGKILLs A once a quarter of the tiles are
// rendered, and checks that B finishes the job with the image a one-coordinator farm
// renders, that B's WatchJob (opened before the kill) told of every task's success,
// those A handled included, and that both replicas listed both workers.
func TestReplicaKilledMidJobTheOtherFinishesItBitIdentical(t *testing.T) {
	one := farmtest.StartFarm(t, nil)
	one.StartWorker(t)
	want := one.Output(t, one.Render(t, replicaScene(t, one), 2*time.Minute), "image.exr")

	rs := redistest.Start(t)
	f := farmtest.StartFarm(t, []string{"--redis", "redis://" + rs.Addr(), "--blobs", s3test.Shared(t).TestURL(t), "--metrics-listen", "127.0.0.1:0"})
	addrB, procB := f.StartReplica(t)
	both := f.Addr + "," + addrB
	workers := []*farmtest.Proc{f.StartWorker(t, "--coordinator", both), f.StartWorker(t, "--coordinator", both)}
	for _, w := range workers {
		w.WorkerID(t, 15*time.Second)
	}
	b, err := client.Dial(addrB)
	if err != nil {
		t.Fatal(err)
	}
	defer b.Close()
	for _, c := range []struct {
		name string
		c    *client.Client
	}{{"A", f.Client}, {"B", b}} {
		if got := workerNames(t, c.c); !slices.Equal(got, []string{"worker-1", "worker-2"}) {
			t.Errorf("ListWorkers on replica %s: %v, want both workers", c.name, got)
		}
	}

	job := f.Submit(t, replicaScene(t, f))
	events := watch(b, job.GetId(), 3*time.Minute)
	// A client given both replicas, as `farm watch` with --coordinator A,B: its stream,
	// on whichever replica, goes on to the job's end.
	ab, err := client.Dial(both)
	if err != nil {
		t.Fatal(err)
	}
	defer ab.Close()
	eitherEvents := watch(ab, job.GetId(), 3*time.Minute)
	for deadline := time.Now().Add(2 * time.Minute); ; time.Sleep(20 * time.Millisecond) {
		tiles := farmtest.TasksOf(f.Tasks(t, job.GetId()), pb.Phase_PHASE_RENDER)
		done := 0
		for _, task := range tiles {
			if task.GetState() == pb.TaskState_TASK_STATE_SUCCEEDED {
				done++
			}
		}
		if len(tiles) > 0 && done*4 >= len(tiles) {
			if done == len(tiles) {
				t.Fatal("every tile was rendered before the kill: the scene is too small for this machine")
			}
			t.Logf("killing replica A with %d of %d tiles rendered", done, len(tiles))
			break
		}
		if time.Now().After(deadline) {
			t.Fatalf("a quarter of the tiles was not rendered within 2 minutes: %v", tiles)
		}
	}
	// Both replicas granted leases: the workers' calls went to each.
	for _, r := range []struct {
		name string
		p    *farmtest.Proc
	}{{"A", f.Coordinator()}, {"B", procB}} {
		if n := leasesGranted(t, r.p); n == 0 {
			t.Errorf("replica %s granted no lease before the kill: the workers did not talk to it", r.name)
		} else {
			t.Logf("replica %s granted %v leases before the kill", r.name, n)
		}
	}
	f.Coordinator().Kill(syscall.SIGKILL)
	<-f.Coordinator().Done()

	<-events.done
	if events.err != nil || events.job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		t.Fatalf("replica B's WatchJob ended with %v, %v: %s", events.job.GetState(), events.err, events.job.GetError())
	}
	<-eitherEvents.done
	if eitherEvents.err != nil || eitherEvents.job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		t.Errorf("WatchJob through a client of both replicas ended with %v, %v", eitherEvents.job.GetState(), eitherEvents.err)
	}
	if got := farmtest.WithoutRenderTime(f.OutputFrom(t, b, events.job, "image.exr")); !bytes.Equal(got, farmtest.WithoutRenderTime(want)) {
		t.Errorf("the EXR the replicas rendered (%d bytes) differs from the one-coordinator render (%d bytes)", len(got), len(want))
	}
	tasks, err := b.ListTasks(context.Background(), job.GetId())
	if err != nil {
		t.Fatal(err)
	}
	seen := events.succeededTasks()
	for _, task := range tasks {
		if !seen[task.GetId()] {
			t.Errorf("replica B's WatchJob never told that task %s (%v) succeeded", task.GetId(), task.GetPhase())
		}
	}
	t.Logf("replica B's WatchJob told of %d task successes, %d tasks in the job", len(seen), len(tasks))
	if got := workerNames(t, b); !slices.Equal(got, []string{"worker-1", "worker-2"}) {
		t.Errorf("ListWorkers on replica B after the kill: %v, want both workers", got)
	}
	for _, w := range workers {
		if w.Exited() {
			t.Errorf("%s exited: %v", w.Name, w.Err())
		}
	}
}
