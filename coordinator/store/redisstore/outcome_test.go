package redisstore_test

import (
	"context"
	"fmt"
	"testing"

	"github.com/redis/go-redis/v9"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestAnswersLostAfterTheScriptRanAreTheTruth puts a proxy between the store and Redis that
// lets a script run and drops its answer, closing the connection, as a network failure
// after the fact does. The store must answer what the script did: the call is sent again
// (by go-redis's retries, or, with those off, by the store itself) and answered from the
// first run. So a submit whose answer is lost at any of its steps makes one job and says
// so (not "job id is taken" or "i/o timeout"), a lease gives one task, a completion
// reports the stage it opened, a failure report is not refused as a lost lease, and a
// cancel does not find the job "already ended". What Redis holds is read through a
// connection of its own.
func TestAnswersLostAfterTheScriptRanAreTheTruth(t *testing.T) {
	for _, retries := range []int{0, -1} { // go-redis's default (3 retries), none
		t.Run(fmt.Sprint("go-redis MaxRetries ", retries), func(t *testing.T) {
			srv := redistest.Start(t)
			proxy := srv.Proxy()
			ctx := context.Background()
			s, err := redisstore.New(ctx, proxy.Client(&redis.Options{MaxRetries: retries}), "cut:", store.Options{})
			if err != nil {
				t.Fatal(err)
			}
			truth := newStore(t, srv, "cut:", store.Options{})
			// lose drops the answer to the nth script call fn makes.
			lose := func(what string, nth int, fn func() error) {
				t.Helper()
				before := proxy.Cuts()
				proxy.CutReplyTo("evalsha", nth)
				if err := fn(); err != nil {
					t.Fatalf("%s, answer %d lost: %v", what, nth, err)
				}
				if proxy.Cuts() != before+1 {
					t.Fatalf("%s: no answer was lost", what)
				}
			}

			// CreateJob runs three scripts: begin, stage (3 tiles and a composite), publish.
			var jobs []*pb.Job
			for nth := 1; nth <= 3; nth++ {
				lose("CreateJob", nth, func() error {
					j, err := s.CreateJob(ctx, storetest.TileJob(fmt.Sprint("cut", nth), 3))
					jobs = append(jobs, j)
					return err
				})
			}
			listed, _, err := truth.ListJobs(ctx, 100, "")
			if err != nil || len(listed) != 3 {
				t.Fatalf("ListJobs = %d jobs, %v; want the 3 submitted", len(listed), err)
			}
			for i, j := range listed {
				if want := jobs[2-i]; j.Id != want.GetId() || len(j.Phases) != 2 {
					t.Errorf("job %d = %v, want %v", i, j, want)
				}
			}

			var l *store.Leased
			lose("LeaseTask", 1, func() (err error) {
				l, err = s.LeaseTask(ctx, "w1", store.WorkerPhases)
				return err
			})
			ts, _, _ := truth.ListTasks(ctx, l.Task.JobId, 10, "")
			if leased := storetest.CountState(ts, pb.TaskState_TASK_STATE_LEASED); leased != 1 || ts[l.Task.Index].Attempts != 1 {
				t.Errorf("after a lease whose answer was lost: %d tasks leased, the one answered had %d attempts; want 1 and 1", leased, ts[l.Task.Index].Attempts)
			}
			ref := store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}
			var c store.Change
			lose("CompleteTask", 1, func() (err error) {
				c, err = s.CompleteTask(ctx, ref, nil)
				return err
			})
			if c.Task.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED || c.Job.GetPhases()[0].GetTasksSucceeded() != 1 {
				t.Errorf("CompleteTask answered %+v, want the task succeeded and counted", c)
			}

			l, _ = s.LeaseTask(ctx, "w1", store.WorkerPhases)
			lose("FailTask", 1, func() (err error) {
				c, err = s.FailTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}, store.Transient("flaky"))
				return err
			})
			if task, _ := truth.GetTask(ctx, l.Lease.TaskId); c.Task.GetRetryTime() == nil || task.GetError() != "flaky" || task.GetState() != pb.TaskState_TASK_STATE_QUEUED {
				t.Errorf("FailTask answered %+v; the task is %v", c, task)
			}

			lose("CancelJob", 1, func() (err error) {
				c, err = s.CancelJob(ctx, jobs[0].GetId())
				return err
			})
			if c.Job.GetState() != pb.JobState_JOB_STATE_CANCELLED || !c.JobStateChanged {
				t.Errorf("CancelJob answered %+v, want the job cancelled", c)
			}
		})
	}
}
