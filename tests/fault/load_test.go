package fault

import (
	"context"
	"flag"
	"sync"
	"testing"
	"time"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// Issue 5's load: 100 jobs submitted at once by 10 clients.
var (
	loadJobs    = flag.Int("load-jobs", 100, "jobs the load test submits (issue 5: 100)")
	loadClients = flag.Int("load-clients", 10, "concurrent clients the load test submits from, each with its own connection (issue 5: 10)")
)

// TestManyJobsFromConcurrentClientsAllSucceed has -load-clients goroutines, each with a
// client connection of its own, submit -load-jobs tiny jobs between them at once to a
// coordinator on Redis with two workers, then watch their jobs: every job must succeed.
func TestManyJobsFromConcurrentClientsAllSucceed(t *testing.T) {
	f := startRedisFarm(t)
	f.StartWorker(t)
	f.StartWorker(t)
	scenes := make([]*pb.Scene, *loadJobs)
	for i := range scenes {
		scenes[i] = tinyScene(t, f, uint64(i+1)) // a seed each, so the jobs differ
	}

	start := time.Now()
	var wg sync.WaitGroup
	submitted := make(chan time.Duration, *loadClients)
	for c := range *loadClients {
		var mine []*pb.Scene
		for i := c; i < len(scenes); i += *loadClients {
			mine = append(mine, scenes[i])
		}
		wg.Add(1)
		go func() {
			defer wg.Done()
			submitted <- runClient(t, f.Addr, c, mine)
		}()
	}
	wg.Wait()
	close(submitted)
	var lastSubmit time.Duration
	for d := range submitted {
		lastSubmit = max(lastSubmit, d)
	}
	t.Logf("%d jobs from %d clients: all submitted within %s, all ended after %s",
		*loadJobs, *loadClients, lastSubmit.Round(time.Millisecond), time.Since(start).Round(time.Millisecond))

	jobs, err := f.Client.ListJobs(context.Background())
	if err != nil {
		t.Fatal(err)
	}
	if len(jobs) != *loadJobs {
		t.Errorf("ListJobs has %d jobs, want %d", len(jobs), *loadJobs)
	}
}

// runClient is client number c: it dials the coordinator, submits scenes one after the
// other as fast as it can, then watches each job to its end and reports (with t.Errorf:
// it runs on a goroutine of its own) any that did not succeed. It returns how long after
// its start its last job was accepted.
func runClient(t *testing.T, addr string, c int, scenes []*pb.Scene) time.Duration {
	start := time.Now()
	cl, err := client.Dial(addr)
	if err != nil {
		t.Errorf("client %d: %v", c, err)
		return 0
	}
	defer cl.Close()
	ctx, cancel := context.WithTimeout(context.Background(), 5*time.Minute)
	defer cancel()
	var ids []string
	for _, sc := range scenes {
		job, err := cl.Submit(ctx, sc)
		if err != nil {
			t.Errorf("client %d: submit: %v", c, err)
			continue
		}
		ids = append(ids, job.GetId())
	}
	accepted := time.Since(start)
	for _, id := range ids {
		job, err := cl.Watch(ctx, id, nil)
		if err != nil {
			t.Errorf("client %d: job %s: %v", c, id, err)
			continue
		}
		if job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
			t.Errorf("client %d: job %s ended %v: %s", c, id, job.GetState(), job.GetError())
		}
	}
	return accepted
}
