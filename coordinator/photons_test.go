package coordinator_test

import (
	"context"
	"testing"
	"time"

	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/client"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/photonmap"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestServeBuildsThePhotonMapBetweenEmitAndRender plays a worker over gRPC through the
// emission phase and checks that the coordinator's own builder turns the shards into the
// snapshot render tiles are given.
func TestServeBuildsThePhotonMapBetweenEmitAndRender(t *testing.T) {
	conn, stop := startServing(t, 2*time.Second)
	defer func() {
		if err := stop(); err != nil {
			t.Errorf("Serve: %v", err)
		}
	}()
	cl := client.New(conn)
	rpc, cancel := context.WithTimeout(context.Background(), 20*time.Second)
	defer cancel()

	sc := scenetest.Valid(16, 16)
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 2000, PhotonsPerShard: 1000}
	sc.Indirect = &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP} // no precompute
	if _, err := cl.Submit(rpc, sc); err != nil {
		t.Fatal(err)
	}
	workers := pb.NewWorkerServiceClient(conn)
	reg, err := workers.RegisterWorker(rpc, &pb.RegisterWorkerRequest{Hostname: "test"})
	if err != nil {
		t.Fatal(err)
	}
	lease := func() *pb.LeaseTaskResponse {
		t.Helper()
		r, err := workers.LeaseTask(rpc, &pb.LeaseTaskRequest{WorkerId: reg.WorkerId, WaitTimeout: durationpb.New(10 * time.Second)})
		if err != nil || r.GetLease() == nil {
			t.Fatalf("LeaseTask = %v, %v", r, err)
		}
		return r
	}
	for i := 0; i < 2; i++ {
		l := lease()
		spec := l.GetTask().GetEmitPhotons()
		if spec == nil {
			t.Fatalf("lease %d = %v, want an emission shard", i, l.Task)
		}
		shard := photonmap.EncodeShard(photonmap.Global, spec.FirstPhoton, spec.PhotonCount, []photonmap.ShardPhoton{
			{Position: [3]float32{float32(i), 0, 0}, Power: [3]float32{1, 1, 1}},
		})
		digest, err := cl.UploadBytes(rpc, shard)
		if err != nil {
			t.Fatal(err)
		}
		if _, err := workers.CompleteTask(rpc, &pb.CompleteTaskRequest{WorkerId: reg.WorkerId, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch,
			Outputs: []*pb.Artifact{{Name: "photons.shard", Digest: digest, SizeBytes: int64(len(shard))}}}); err != nil {
			t.Fatal(err)
		}
	}
	// The next task a worker gets is a tile, after the builder ran.
	tile := lease()
	snap := tile.GetTask().GetRenderTile().GetPhotonSnapshot()
	if snap.GetName() != "photons.snapshot" || snap.GetSizeBytes() == 0 {
		t.Fatalf("tile lease = %v, want a photon snapshot", tile.Task)
	}
	if ok, err := cl.BlobExists(rpc, snap.GetDigest()); err != nil || !ok {
		t.Errorf("snapshot blob %s: exists %v, %v", snap.GetDigest(), ok, err)
	}
}
