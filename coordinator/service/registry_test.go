package service_test

import (
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/protobuf/proto"

	"photonfarm/coordinator/service"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// allWorkers follows ListWorkers' pages of size n and returns the workers and the pages.
func (f *farm) allWorkers(n int32) ([]*pb.WorkerInfo, int) {
	f.t.Helper()
	var all []*pb.WorkerInfo
	token, pages := "", 0
	for {
		resp, err := f.jobs.ListWorkers(f.ctx, &pb.ListWorkersRequest{PageSize: n, PageToken: token})
		if err != nil {
			f.t.Fatalf("ListWorkers page %d: %v", pages+1, err)
		}
		pages++
		all = append(all, resp.GetWorkers()...)
		if token = resp.GetNextPageToken(); token == "" {
			return all, pages
		}
	}
}

func TestListWorkersPages(t *testing.T) {
	f := newFarm(t)
	var ids []string
	for range 250 {
		ids = append(ids, f.register())
	}
	all, pages := f.allWorkers(100)
	if pages != 3 || len(all) != len(ids) {
		t.Fatalf("%d workers in %d pages of 100, want %d in 3", len(all), pages, len(ids))
	}
	for i, w := range all {
		if w.GetId() != ids[i] {
			t.Fatalf("worker %d is %s, want %s (registration order)", i, w.GetId(), ids[i])
		}
	}
	resp, err := f.jobs.ListWorkers(f.ctx, &pb.ListWorkersRequest{})
	if err != nil || len(resp.GetWorkers()) != service.DefaultWorkersPage || resp.GetNextPageToken() == "" {
		t.Errorf("ListWorkers without a page size = %d workers, next %q, %v; want the first %d and a token",
			len(resp.GetWorkers()), resp.GetNextPageToken(), err, service.DefaultWorkersPage)
	}
	if _, err := f.jobs.ListWorkers(f.ctx, &pb.ListWorkersRequest{PageToken: "forged"}); err == nil {
		t.Error("a forged page token was accepted")
	} else {
		wantCode(t, "forged page token", err, codes.InvalidArgument, "page_token")
	}
	_, err = f.jobs.ListWorkers(f.ctx, &pb.ListWorkersRequest{PageSize: -1})
	wantCode(t, "negative page size", err, codes.InvalidArgument, "page_size")
}

// TestSilentWorkersAreForgotten: a worker not heard from for a lease duration is LOST; for
// ForgetAfterLeases lease durations, forgotten (and told NOT_FOUND, so it registers
// again); one that heartbeats stays.
func TestSilentWorkersAreForgotten(t *testing.T) {
	f := newFarm(t)
	silent, alive := f.register(), f.register()
	step := leaseDuration / 2
	for elapsed := time.Duration(0); elapsed <= service.ForgetAfterLeases*leaseDuration; elapsed += step {
		f.clock.Advance(step)
		if _, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: alive}); err != nil {
			t.Fatal(err)
		}
		if err := f.svc.ForgetSilentWorkers(f.ctx); err != nil {
			t.Fatal(err)
		}
		if elapsed == 2*leaseDuration {
			wantWorker(t, "silent for two lease durations", f.workerInfo(silent), pb.WorkerState_WORKER_STATE_LOST, "", 0, 0)
		}
	}
	all, _ := f.allWorkers(0)
	if len(all) != 1 || all[0].GetId() != alive {
		t.Fatalf("workers after %d lease durations = %v, want only %s", service.ForgetAfterLeases+1, all, alive)
	}
	_, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: silent})
	wantCode(t, "heartbeat of a forgotten worker", err, codes.NotFound, "worker_id")
	_, err = f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: silent})
	wantCode(t, "lease of a forgotten worker", err, codes.NotFound, "worker_id")
}

// TestRegistryIsBounded registers MaxWorkers workers: the next registration is refused
// while all of them are live, and takes the place of a lost one once some are.
func TestRegistryIsBounded(t *testing.T) {
	f := newFarm(t)
	first := f.register()
	for range store.MaxWorkers - 1 {
		f.register()
	}
	_, err := f.workers.RegisterWorker(f.ctx, &pb.RegisterWorkerRequest{Hostname: "one too many"})
	wantCode(t, "a registration past the limit", err, codes.ResourceExhausted, "")
	if err != nil && !strings.Contains(err.Error(), "10000 workers") {
		t.Errorf("the refusal %q does not name the limit", err)
	}

	f.clock.Advance(leaseDuration + time.Second) // every worker is LOST now
	if _, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: first}); err != nil {
		t.Fatal(err)
	}
	newcomer := f.register()
	resp, err := f.jobs.ListWorkers(f.ctx, &pb.ListWorkersRequest{PageSize: service.MaxWorkersPage})
	if err != nil {
		t.Fatal(err)
	}
	t.Logf("%d registrations keep %d workers; a ListWorkers page holds at most %d of them: %d bytes",
		store.MaxWorkers+1, store.MaxWorkers, len(resp.GetWorkers()), proto.Size(resp))
	all, _ := f.allWorkers(service.MaxWorkersPage)
	if len(all) != store.MaxWorkers {
		t.Fatalf("%d workers registered, want %d", len(all), store.MaxWorkers)
	}
	if all[0].GetId() != first || all[len(all)-1].GetId() != newcomer {
		t.Errorf("first %s and last %s; want %s (it heartbeat, so it stays) and the newcomer %s",
			all[0].GetId(), all[len(all)-1].GetId(), first, newcomer)
	}
}
