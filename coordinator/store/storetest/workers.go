package storetest

import (
	"context"
	"fmt"
	"testing"
	"time"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// NewWorkersFunc returns an empty registry for one test.
type NewWorkersFunc func(t *testing.T) store.Workers

// lost is the silence after which the suite's workers are LOST.
const lost = 10 * time.Second

// RunWorkers runs the behavioural suite every store.Workers must pass.
func RunWorkers(t *testing.T, newWorkers NewWorkersFunc) {
	t0 := time.Unix(1_700_000_000, 0)
	ctx := context.Background()
	add := func(t *testing.T, r store.Workers, id string, at time.Time) {
		t.Helper()
		if err := r.Add(ctx, store.Worker{ID: id, Hostname: "host-" + id, Cores: 8, Version: "v1", Registered: at, LastSeen: at}, lost); err != nil {
			t.Fatalf("Add %s: %v", id, err)
		}
	}
	list := func(t *testing.T, r store.Workers, now time.Time, n int) []*pb.WorkerInfo {
		t.Helper()
		var all []*pb.WorkerInfo
		for token := ""; ; {
			page, next, err := r.List(ctx, now, lost, n, token)
			if err != nil {
				t.Fatal(err)
			}
			if len(page) > n {
				t.Fatalf("a page of %d holds %d workers", n, len(page))
			}
			all = append(all, page...)
			if token = next; token == "" {
				return all
			}
		}
	}
	one := func(t *testing.T, r store.Workers, now time.Time, id string) *pb.WorkerInfo {
		t.Helper()
		for _, w := range list(t, r, now, 100) {
			if w.GetId() == id {
				return w
			}
		}
		t.Fatalf("worker %s is not listed", id)
		return nil
	}
	wantKind := func(t *testing.T, what string, err error, k errs.Kind) {
		t.Helper()
		if !errs.Is(err, k) {
			t.Errorf("%s: %v, want %v", what, err, k)
		}
	}

	t.Run("ListsInRegistrationOrderInPages", func(t *testing.T) {
		r := newWorkers(t)
		var ids []string
		for i := range 5 {
			ids = append(ids, fmt.Sprintf("w-%d", 5-i)) // ids out of order: the listing is by registration
			add(t, r, ids[i], t0.Add(time.Duration(i)*time.Millisecond))
		}
		all := list(t, r, t0, 2)
		if len(all) != len(ids) {
			t.Fatalf("%d workers listed, want %d", len(all), len(ids))
		}
		for i, w := range all {
			if w.GetId() != ids[i] || w.GetHostname() != "host-"+ids[i] || w.GetCores() != 8 || w.GetVersion() != "v1" ||
				w.GetState() != pb.WorkerState_WORKER_STATE_IDLE || !w.GetRegisterTime().AsTime().Equal(t0.Add(time.Duration(i)*time.Millisecond)) {
				t.Errorf("worker %d = %v, want %s, idle, registered at +%d ms", i, w, ids[i], i)
			}
		}
		_, _, err := r.List(ctx, t0, lost, 2, "forged")
		wantKind(t, "a forged page token", err, errs.InvalidArgument)
	})

	t.Run("CountsWhatWorkersDo", func(t *testing.T) {
		r := newWorkers(t)
		add(t, r, "w-a", t0)
		step := func(what string, err error) {
			t.Helper()
			if err != nil {
				t.Fatalf("%s: %v", what, err)
			}
		}
		want := func(what string, state pb.WorkerState, current string, done, failed uint64) {
			t.Helper()
			w := one(t, r, t0, "w-a")
			if w.GetState() != state || w.GetCurrentTaskId() != current || w.GetTasksDone() != done || w.GetTasksFailed() != failed {
				t.Errorf("%s: %v %q done %d failed %d; want %v %q %d %d", what, w.GetState(), w.GetCurrentTaskId(),
					w.GetTasksDone(), w.GetTasksFailed(), state, current, done, failed)
			}
		}
		step("lease", r.Leased(ctx, "w-a", "j.1"))
		want("leased", pb.WorkerState_WORKER_STATE_BUSY, "j.1", 0, 0)
		step("complete", r.Ended(ctx, "w-a", "j.1", true))
		want("completed", pb.WorkerState_WORKER_STATE_IDLE, "", 1, 0)
		step("lease", r.Leased(ctx, "w-a", "j.2"))
		step("expire", r.Expired(ctx, "j.2"))
		want("its lease expired", pb.WorkerState_WORKER_STATE_IDLE, "", 1, 1)
		step("expire again", r.Expired(ctx, "j.2"))
		want("an expiry of a lease it no longer holds", pb.WorkerState_WORKER_STATE_IDLE, "", 1, 1)
		step("lease", r.Leased(ctx, "w-a", "j.3"))
		step("release", r.Dropped(ctx, "w-a", "j.3"))
		want("released", pb.WorkerState_WORKER_STATE_IDLE, "", 1, 1)
		step("lease", r.Leased(ctx, "w-a", "j.4"))
		step("fail", r.Ended(ctx, "w-a", "j.4", false))
		want("failed", pb.WorkerState_WORKER_STATE_IDLE, "", 1, 2)
		step("lease", r.Leased(ctx, "w-a", "j.5"))
		step("a stale report of an earlier task", r.Dropped(ctx, "w-a", "j.3"))
		want("still holding j.5", pb.WorkerState_WORKER_STATE_BUSY, "j.5", 1, 2)
		for _, err := range []error{r.Leased(ctx, "builder", "j.6"), r.Ended(ctx, "builder", "j.6", true), r.Dropped(ctx, "builder", "j.6"), r.Expired(ctx, "j.7")} {
			step("a report about a worker that never registered", err)
		}
	})

	t.Run("SilentWorkersAreLostThenForgotten", func(t *testing.T) {
		r := newWorkers(t)
		add(t, r, "w-silent", t0)
		add(t, r, "w-alive", t0)
		later := t0.Add(lost + time.Second)
		if err := r.Touch(ctx, "w-alive", later); err != nil {
			t.Fatal(err)
		}
		wantKind(t, "touching a worker never registered", r.Touch(ctx, "w-never", later), errs.NotFound)
		if w := one(t, r, later, "w-silent"); w.GetState() != pb.WorkerState_WORKER_STATE_LOST {
			t.Errorf("silent for longer than lost: %v, want LOST", w.GetState())
		}
		if w := one(t, r, later, "w-alive"); w.GetState() != pb.WorkerState_WORKER_STATE_IDLE || !w.GetLastHeartbeat().AsTime().Equal(later) {
			t.Errorf("heard from: %v last heard %v, want IDLE at %v", w.GetState(), w.GetLastHeartbeat().AsTime(), later)
		}
		live, err := r.Live(ctx, later, lost)
		if err != nil || len(live) != 1 || live[0] != "w-alive" {
			t.Errorf("Live = %v, %v; want [w-alive]", live, err)
		}
		n, err := r.ForgetSilent(ctx, later, lost)
		if err != nil || n != 1 {
			t.Fatalf("ForgetSilent = %d, %v; want 1", n, err)
		}
		if all := list(t, r, later, 10); len(all) != 1 || all[0].GetId() != "w-alive" {
			t.Errorf("after forgetting: %v, want only w-alive", all)
		}
		wantKind(t, "touching a forgotten worker", r.Touch(ctx, "w-silent", later), errs.NotFound)
		if err := r.Remove(ctx, "w-alive"); err != nil {
			t.Fatal(err)
		}
		wantKind(t, "removing a worker twice", r.Remove(ctx, "w-alive"), errs.NotFound)
		if all := list(t, r, later, 10); len(all) != 0 {
			t.Errorf("after removing the last: %v", all)
		}
	})

	t.Run("IsBounded", func(t *testing.T) {
		r := newWorkers(t)
		for i := range store.MaxWorkers {
			add(t, r, fmt.Sprintf("w-%05d", i), t0.Add(time.Duration(i)*time.Microsecond))
		}
		err := r.Add(ctx, store.Worker{ID: "w-extra", Registered: t0.Add(time.Second), LastSeen: t0.Add(time.Second)}, lost)
		wantKind(t, "a registration past the limit while all are live", err, errs.ResourceExhausted)
		later := t0.Add(lost + time.Minute)
		if err := r.Touch(ctx, "w-00000", later); err != nil {
			t.Fatal(err)
		}
		add(t, r, "w-newcomer", later)
		all := list(t, r, later, 1000)
		if len(all) != store.MaxWorkers || all[0].GetId() != "w-00000" || all[1].GetId() != "w-00002" || all[len(all)-1].GetId() != "w-newcomer" {
			t.Errorf("%d workers, first %s %s, last %s; want %d: w-00000 (heard from), w-00002 (w-00001 was the longest silent), w-newcomer",
				len(all), all[0].GetId(), all[1].GetId(), all[len(all)-1].GetId(), store.MaxWorkers)
		}
	})
}
