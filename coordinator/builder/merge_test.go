package builder_test

import (
	"bytes"
	"io"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/photonmap"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// precompute completes every precompute task of the job as a worker would, with data(i,
// spec) as irradiance shard i, and returns the shards.
func (f *fixture) precompute(data func(i int, spec *pb.PrecomputeIrradianceSpec) []byte) [][]byte {
	f.t.Helper()
	return f.completeEach(pb.ArtifactKind_ARTIFACT_KIND_IRRADIANCE_SHARD, func(i int, t *pb.Task) []byte {
		if spec := t.GetPrecomputeIrradiance(); spec != nil {
			return data(i, spec)
		}
		return nil
	})
}

// mergeTask is the job's merge task once done says it is finished.
func (f *fixture) mergeTask(jobID string, done func(merge *pb.Task, job *pb.Job) bool) (*pb.Task, *pb.Job) {
	f.t.Helper()
	var merge *pb.Task
	_, job := f.waitFor(jobID, func(_ *pb.Task, job *pb.Job) bool {
		ts, _, err := f.st.ListTasks(f.ctx, jobID, 1000, "")
		if err != nil {
			f.t.Fatal(err)
		}
		for _, t := range ts {
			if t.GetMergeIrradiance() != nil && done(t, job) {
				merge = t
				return true
			}
		}
		return false
	})
	return merge, job
}

// irradianceShard is part i of a worker's irradiance that chose one site a part: site i.
func irradianceShard(i int, spec *pb.PrecomputeIrradianceSpec) []byte {
	return photonmap.EncodeIrradianceShard(uint64(spec.GetPart()), [][3]float32{{float32(i + 1), float32(spec.GetParts()), 0.25}})
}

// The merge streams the snapshot with irradiance into the blob store as it makes it: what
// is stored is photonmap.MergeIrradiance of the built snapshot and the shards, and the
// builds leave nothing in the scratch folder.
func TestBuilderStreamsTheMergedSnapshotIntoTheStore(t *testing.T) {
	f := newFixture(t, nil)
	j := f.createJobIn(3, pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER)
	f.emit(validShard)
	build, _ := f.waitFor(j.Id, func(b *pb.Task, _ *pb.Job) bool { return b.State == pb.TaskState_TASK_STATE_SUCCEEDED })
	irr := f.precompute(irradianceShard)
	if len(irr) != 3 {
		t.Fatalf("%d precompute tasks, want one a shard", len(irr))
	}
	merge, _ := f.mergeTask(j.Id, func(m *pb.Task, _ *pb.Job) bool { return m.State == pb.TaskState_TASK_STATE_SUCCEEDED })
	want, err := photonmap.MergeIrradiance(f.read(build.Outputs[0].Digest), irr)
	if err != nil {
		t.Fatal(err)
	}
	if got := f.read(merge.Outputs[0].Digest); !bytes.Equal(got, want) || merge.Outputs[0].SizeBytes != int64(len(want)) {
		t.Errorf("stored merged snapshot: %d bytes (artifact says %d), want MergeIrradiance's %d, equal", len(got), merge.Outputs[0].SizeBytes, len(want))
	}
	if left, _ := os.ReadDir(f.scratch); len(left) != 0 {
		t.Errorf("the scratch folder holds %d files after the build, want none", len(left))
	}
}

// A malformed irradiance shard (found by the merge's first pass over the shards, before it
// writes) fails the job as bad input naming the shard.
func TestBuilderFailsAMergeOfAMalformedIrradianceShardNamingIt(t *testing.T) {
	f := newFixture(t, nil)
	j := f.createJobIn(2, pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER)
	f.emit(validShard)
	f.waitFor(j.Id, func(b *pb.Task, _ *pb.Job) bool { return b.State == pb.TaskState_TASK_STATE_SUCCEEDED })
	f.precompute(func(i int, spec *pb.PrecomputeIrradianceSpec) []byte {
		b := irradianceShard(i, spec)
		if i == 1 {
			b[len(b)-1] = 0xff // the last record's exponent: a component far above the scale
		}
		return b
	})
	merge, job := f.mergeTask(j.Id, func(_ *pb.Task, job *pb.Job) bool { return store.Ended(job.State) })
	bad := pb.FailureKind_FAILURE_KIND_BAD_INPUT
	if job.State != pb.JobState_JOB_STATE_FAILED || merge.FailureKind != bad || !strings.Contains(merge.Error, "irradiance shard 1 of round 1") ||
		!strings.Contains(merge.Error, "irradiance_shards[1]") || len(merge.Outputs) != 0 {
		t.Fatalf("job %v, merge %v %q with outputs %v; want it failed as bad input naming irradiance shard 1", job.State, merge.FailureKind, merge.Error, merge.Outputs)
	}
}

// A snapshot damaged on disk is found at its end, when the merge has streamed all of it
// into the store: the job fails as lost input naming the snapshot, and the partial blob is
// dropped.
func TestBuilderFailsAMergeOfADamagedSnapshotAfterStreamingIt(t *testing.T) {
	f := newFixture(t, nil)
	j := f.createJobIn(2, pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER)
	f.emit(validShard)
	build, _ := f.waitFor(j.Id, func(b *pb.Task, _ *pb.Job) bool { return b.State == pb.TaskState_TASK_STATE_SUCCEEDED })
	f.precompute(func(i int, spec *pb.PrecomputeIrradianceSpec) []byte {
		if i == 1 { // the last precompute is leased; the merge waits for it
			snap := f.read(build.Outputs[0].Digest)
			snap[len(snap)-1] ^= 0x40 // the last photon's normal: parses, but not the blob's digest
			if err := os.WriteFile(blobstore.PathIn(f.dir, build.Outputs[0].Digest), snap, 0o644); err != nil {
				t.Fatal(err)
			}
		}
		return irradianceShard(i, spec)
	})
	merge, job := f.mergeTask(j.Id, func(_ *pb.Task, job *pb.Job) bool { return store.Ended(job.State) })
	lost := pb.FailureKind_FAILURE_KIND_LOST_INPUT
	want := "the photon snapshot of round 1: blob " + build.Outputs[0].Digest + " is damaged"
	if job.State != pb.JobState_JOB_STATE_FAILED || merge.FailureKind != lost || !strings.Contains(merge.Error, want) || len(merge.Outputs) != 0 {
		t.Fatalf("job %v %q, merge %v %q; want it failed as lost input with %q", job.State, job.Error, merge.FailureKind, merge.Error, want)
	}
	if left, _ := os.ReadDir(filepath.Join(f.dir, "tmp")); len(left) != 0 {
		t.Errorf("the blob store's tmp folder holds %d files after the failed merge, want none", len(left))
	}
}

func (f *fixture) read(digest string) []byte {
	f.t.Helper()
	r, _, err := f.blobs.Open(f.ctx, digest)
	if err != nil {
		f.t.Fatal(err)
	}
	defer r.Close()
	b, err := io.ReadAll(r)
	if err != nil {
		f.t.Fatal(err)
	}
	return b
}
