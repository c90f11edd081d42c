package photonmap

import (
	"bytes"
	"errors"
	"math"
	"math/rand/v2"
	"os"
	"path/filepath"
	"testing"
)

// buildToFile builds shards into a file with BuildTo's blocked writes, subtrees of at most
// block photons a level at a time, and returns the file's bytes.
func buildToFile(t *testing.T, shards []Shard, block int) []byte {
	t.Helper()
	f, err := os.Create(filepath.Join(t.TempDir(), "snapshot"))
	if err != nil {
		t.Fatal(err)
	}
	defer f.Close()
	sources := make([]Source, len(shards))
	for i, s := range shards {
		sources[i] = BytesSource(s.Data)
	}
	n, err := buildTo(f, sources, math.MaxInt, block)
	if err != nil {
		t.Fatal(err)
	}
	data, err := os.ReadFile(f.Name())
	if err != nil {
		t.Fatal(err)
	}
	if int64(len(data)) != n {
		t.Fatalf("BuildTo returned %d bytes, the file has %d", n, len(data))
	}
	return data
}

// The file the coordinator builds, written a level of a block at a time, is byte for byte
// the snapshot built in memory a node at a time, for blocks from one photon to more than a
// map: on every shape of input the vectors have, large enough for many blocks and for
// subtrees built on goroutines of their own (BuildFrom starts them from 65,536 photons).
func TestBuildToAFileInBlocksEqualsTheBuildInMemory(t *testing.T) {
	r := rand.New(rand.NewPCG(17, 100))
	big := uniformPhotons(r, 150_000)
	cases := append(testCases(),
		testCase{name: "uniform-150000", shards: append(splitShards(Global, big, 40_000, 100_000), splitShards(Caustic, uniformPhotons(r, 3000), 1000)...)},
		testCase{name: "plane-70000", shards: splitShards(Global, planePhotons(r, 70_000), 30_000)},
		testCase{name: "duplicates-70000", shards: splitShards(Global, duplicatePhotons(r, 70_000))},
	)
	for _, tc := range cases {
		t.Run(tc.name, func(t *testing.T) {
			want, err := Build(tc.shards)
			if err != nil {
				t.Fatal(err)
			}
			for _, block := range []int{1, 2, 3, 7, 64, 1000, fileBlock, 1 << 20} {
				if got := buildToFile(t, tc.shards, block); !bytes.Equal(got, want) {
					t.Errorf("blocks of %d: the file (%d bytes) differs from the build in memory (%d bytes) at byte %d",
						block, len(got), len(want), firstDifference(got, want))
				}
			}
		})
	}
}

func firstDifference(a, b []byte) int {
	for i := range min(len(a), len(b)) {
		if a[i] != b[i] {
			return i
		}
	}
	return min(len(a), len(b))
}

// failingOutput fails every write once `after` bytes were written.
type failingOutput struct {
	memOutput
	after int
	err   error
}

func (f *failingOutput) WriteAt(p []byte, off int64) (int, error) {
	if f.after -= len(p); f.after < 0 {
		return 0, f.err
	}
	return f.memOutput.WriteAt(p, off)
}

// A full disk under the snapshot file is the build's error, unchanged (the builder reports
// it as resource exhaustion), whether the header or a tree fails to be written.
func TestBuildToReturnsTheOutputsErrorUnchanged(t *testing.T) {
	full := errors.New("no space left on device")
	shards := splitShards(Global, uniformPhotons(rand.New(rand.NewPCG(3, 4)), 100_000), 50_000)
	sources := []Source{BytesSource(shards[0].Data), BytesSource(shards[1].Data)}
	for _, after := range []int{0, 100, 1_000_000} {
		out := &failingOutput{after: after, err: full}
		if _, err := buildTo(out, sources, math.MaxInt, 64); err != full {
			t.Errorf("failing after %d bytes: %v, want the output's error", after, err)
		}
	}
}

// The merge streams to its writer MergedSize bytes: the snapshot MergeIrradiance makes.
func TestMergeIrradianceToStreamsMergedSizeBytes(t *testing.T) {
	for _, tc := range irradianceCases() {
		snap, err := Build(tc.shards)
		if err != nil {
			t.Fatal(err)
		}
		want, err := MergeIrradiance(snap, tc.irradiance)
		if err != nil {
			t.Fatal(err)
		}
		var sources []Source
		for _, s := range tc.irradiance {
			sources = append(sources, BytesSource(s))
		}
		var out bytes.Buffer
		n, err := MergeIrradianceTo(&out, BytesSource(snap), int64(len(snap)), sources)
		if err != nil {
			t.Fatal(err)
		}
		var sites uint64 // what the shards cover
		for _, s := range tc.irradiance {
			sites += le.Uint64(s[24:])
		}
		if n != int64(len(want)) || MergedSize(int64(len(snap)), sites) != n || !bytes.Equal(out.Bytes(), want) {
			t.Errorf("%s: wrote %d bytes (returned %d, MergedSize %d), want MergeIrradiance's %d",
				tc.name, out.Len(), n, MergedSize(int64(len(snap)), sites), len(want))
		}
	}
}
