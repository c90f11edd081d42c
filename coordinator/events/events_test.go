package events_test

import (
	"context"
	"testing"
	"time"

	"photonfarm/coordinator/events"
	pb "photonfarm/proto/renderfarm/v1"
)

func ev(job string, state pb.JobState, n uint32) *pb.WatchJobResponse {
	return &pb.WatchJobResponse{Kind: pb.JobEventKind_JOB_EVENT_KIND_TASK_UPDATED,
		Job: &pb.Job{Id: job, State: state}, Task: &pb.Task{Index: n}}
}

func TestWatchersGetTheirJobsEventsInOrder(t *testing.T) {
	b := events.NewBroker(0)
	a1, a2, other := b.Watch("a"), b.Watch("a"), b.Watch("b")
	defer a1.Close()
	defer a2.Close()
	for i := uint32(0); i < 3; i++ {
		b.Publish(ev("a", pb.JobState_JOB_STATE_RUNNING, i))
	}
	ctx, cancel := context.WithTimeout(context.Background(), time.Second)
	defer cancel()
	for _, w := range []*events.Watcher{a1, a2} {
		for i := uint32(0); i < 3; i++ {
			e, err := w.Next(ctx)
			if err != nil || e.Task.Index != i {
				t.Fatalf("event %d = %v, %v", i, e, err)
			}
		}
	}
	short, cancel2 := context.WithTimeout(context.Background(), 20*time.Millisecond)
	defer cancel2()
	if e, err := other.Next(short); err == nil {
		t.Errorf("watcher of b got %v", e)
	}
	other.Close()
	if n := b.Watchers("b"); n != 0 {
		t.Errorf("closed watcher still subscribed (%d)", n)
	}
}

func TestSlowWatcherIsCoalescedAndSeesTheEnd(t *testing.T) {
	b := events.NewBroker(4)
	w := b.Watch("a")
	defer w.Close()
	done := make(chan struct{})
	go func() { // the publisher never blocks, even with nobody reading
		for i := uint32(0); i < 1000; i++ {
			b.Publish(ev("a", pb.JobState_JOB_STATE_RUNNING, i))
		}
		b.Publish(ev("a", pb.JobState_JOB_STATE_SUCCEEDED, 1000))
		close(done)
	}()
	select {
	case <-done:
	case <-time.After(5 * time.Second):
		t.Fatal("Publish blocked on a slow watcher")
	}
	ctx, cancel := context.WithTimeout(context.Background(), time.Second)
	defer cancel()
	var last *pb.WatchJobResponse
	n := 0
	for last == nil || last.Job.State != pb.JobState_JOB_STATE_SUCCEEDED {
		e, err := w.Next(ctx)
		if err != nil {
			t.Fatalf("after %d events: %v", n, err)
		}
		last = e
		n++
	}
	if n > 4 || w.Coalesced() == 0 {
		t.Errorf("read %d events, coalesced %d; want at most 4 and some coalesced", n, w.Coalesced())
	}
}

func TestNextRespectsContext(t *testing.T) {
	w := events.NewBroker(0).Watch("a")
	defer w.Close()
	ctx, cancel := context.WithCancel(context.Background())
	cancel()
	if _, err := w.Next(ctx); err != context.Canceled {
		t.Errorf("Next = %v, want context.Canceled", err)
	}
}
