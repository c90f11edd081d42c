package main

import (
	"context"
	"errors"
	"fmt"
	"slices"
	"sync"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/credentials/insecure"
	"google.golang.org/grpc/status"
	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// stats collects the simulated workers' figures.
type stats struct {
	mu       sync.Mutex
	lease    []time.Duration // LeaseTask calls that granted a lease
	empty    int             // LeaseTask calls that came back empty
	complete []time.Duration
	// done counts completions by task: two replicas that leased one task twice would
	// show as a task completed twice.
	done   map[string]int
	errors map[string]int
}

func (s *stats) add(list *[]time.Duration, d time.Duration) {
	s.mu.Lock()
	*list = append(*list, d)
	s.mu.Unlock()
}

func (s *stats) fail(what string, err error) {
	// The run's context is every call's only deadline: a call it cuts off at the end
	// (the server may say so before the client's timer fires) is not an error.
	if errors.Is(err, context.DeadlineExceeded) || status.Code(err) == codes.DeadlineExceeded {
		return
	}
	s.mu.Lock()
	if s.errors == nil {
		s.errors = map[string]int{}
	}
	s.errors[fmt.Sprintf("%s: %v", what, err)]++
	s.mu.Unlock()
}

// percentile is the p-th percentile (0 < p < 100) of d, sorted in place.
func percentile(d []time.Duration, p float64) time.Duration {
	if len(d) == 0 {
		return 0
	}
	slices.Sort(d)
	return d[int(float64(len(d)-1)*p/100)]
}

// simWorker does what farm-worker does for a render tile, without rendering: register,
// lease (long poll), heartbeat the lease, upload a tiny tile (one of its own, or with
// upload false the same one every time, which the store has already), complete. A composite (the
// end of a job, which would read real tiles) is failed as unsupported, ending that job.
func simWorker(ctx context.Context, addr string, i int, upload bool, st *stats) {
	conn, err := grpc.NewClient(addr, grpc.WithTransportCredentials(insecure.NewCredentials()),
		client.WorkerSecrets(), client.CallLimits())
	if err != nil {
		st.fail("dial", err)
		return
	}
	defer conn.Close()
	w := pb.NewWorkerServiceClient(conn)
	blobs := client.New(conn)
	reg, err := w.RegisterWorker(ctx, &pb.RegisterWorkerRequest{Hostname: fmt.Sprintf("sim-%d", i), Cores: 1, Version: "loadsim"})
	if err != nil {
		st.fail("RegisterWorker", err)
		return
	}
	id := reg.GetWorkerId()
	for ctx.Err() == nil {
		t0 := time.Now()
		resp, err := w.LeaseTask(ctx, &pb.LeaseTaskRequest{WorkerId: id, WaitTimeout: durationpb.New(time.Second)})
		d := time.Since(t0)
		if ctx.Err() != nil {
			return
		}
		if err != nil {
			st.fail("LeaseTask", err)
			time.Sleep(100 * time.Millisecond)
			continue
		}
		lease := resp.GetLease()
		if lease == nil {
			st.mu.Lock()
			st.empty++
			st.mu.Unlock()
			continue
		}
		st.add(&st.lease, d)
		if resp.GetTask().GetRenderTile() == nil {
			_, err := w.FailTask(ctx, &pb.FailTaskRequest{WorkerId: id, TaskId: lease.GetTaskId(), Epoch: lease.GetEpoch(),
				Error: "the load simulation renders no composite", Kind: pb.FailureKind_FAILURE_KIND_UNSUPPORTED})
			if err != nil && ctx.Err() == nil {
				st.fail("FailTask", err)
			}
			continue
		}
		if _, err := w.Heartbeat(ctx, &pb.HeartbeatRequest{WorkerId: id,
			Leases: []*pb.HeldLease{{TaskId: lease.GetTaskId(), Epoch: lease.GetEpoch(), Progress: 1}}}); err != nil {
			if ctx.Err() == nil {
				st.fail("Heartbeat", err)
			}
			continue
		}
		// Without upload every tile is the same blob, uploaded once: the coordinator's
		// blob writes are then out of the figures.
		tile := []byte("loadsim tile")
		if upload {
			tile = []byte("loadsim tile " + lease.GetTaskId())
		}
		digest, err := blobs.UploadBytes(ctx, tile)
		if err != nil {
			if ctx.Err() == nil {
				st.fail("UploadBlob", err)
			}
			continue
		}
		t0 = time.Now()
		_, err = w.CompleteTask(ctx, &pb.CompleteTaskRequest{WorkerId: id, TaskId: lease.GetTaskId(), Epoch: lease.GetEpoch(),
			Outputs: []*pb.Artifact{{Name: "tile.exr", Digest: digest, SizeBytes: int64(len(tile))}}})
		if err != nil {
			if ctx.Err() == nil {
				st.fail("CompleteTask", err)
			}
			continue
		}
		st.mu.Lock()
		st.complete = append(st.complete, time.Since(t0))
		if st.done == nil {
			st.done = map[string]int{}
		}
		st.done[lease.GetTaskId()]++
		st.mu.Unlock()
	}
}
