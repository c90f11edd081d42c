package photonmap

import (
	"bytes"
	"flag"
	"fmt"
	"os"
	"path/filepath"
	"slices"
	"testing"
)

// The test vectors are shared with the C++ reader's tests (worker/photonmap): each case
// folder holds shard-NNN.bin (the input, in plan order) and snapshot.bin (Build's output).
// Regenerate after an intended format change with
//
//	go test ./coordinator/photonmap -run TestVectors -update
var update = flag.Bool("update", false, "rewrite tests/vectors/photon-snapshot from testCases")

const vectorDir = "../../tests/vectors/photon-snapshot"

func TestVectors(t *testing.T) {
	if *update {
		writeVectors(t)
	}
	entries, err := os.ReadDir(vectorDir)
	if err != nil {
		t.Fatal(err)
	}
	cases := 0
	for _, e := range entries {
		if !e.IsDir() {
			continue
		}
		cases++
		t.Run(e.Name(), func(t *testing.T) {
			dir := filepath.Join(vectorDir, e.Name())
			names, err := filepath.Glob(filepath.Join(dir, "shard-*.bin"))
			if err != nil {
				t.Fatal(err)
			}
			slices.Sort(names)
			var shards []Shard
			for _, n := range names {
				data, err := os.ReadFile(n)
				if err != nil {
					t.Fatal(err)
				}
				shards = append(shards, Shard{Data: data})
			}
			want, err := os.ReadFile(filepath.Join(dir, "snapshot.bin"))
			if err != nil {
				t.Fatal(err)
			}
			irrNames, err := filepath.Glob(filepath.Join(dir, "irradiance-*.bin"))
			if err != nil {
				t.Fatal(err)
			}
			slices.Sort(irrNames)
			var irr [][]byte
			for _, n := range irrNames {
				data, err := os.ReadFile(n)
				if err != nil {
					t.Fatal(err)
				}
				irr = append(irr, data)
			}
			// In memory a node at a time, and into a file in blocks of 5 photons, as the
			// coordinator builds (blocks of 65,536 there: these maps would fit in one).
			for _, built := range []struct {
				how  string
				snap func() ([]byte, error)
			}{
				{"Build", func() ([]byte, error) { return Build(shards) }},
				{"BuildTo a file", func() ([]byte, error) { return buildToFile(t, shards, 5), nil }},
			} {
				got, err := built.snap()
				if err != nil {
					t.Fatal(err)
				}
				if len(irr) > 0 {
					if got, err = MergeIrradiance(got, irr); err != nil {
						t.Fatal(err)
					}
				}
				if !bytes.Equal(got, want) {
					t.Fatalf("%s of %d shards differs from snapshot.bin (%d vs %d bytes)", built.how, len(shards), len(got), len(want))
				}
			}
		})
	}
	// Every case the generator writes, and no stale one it no longer does.
	if want := len(testCases()) + len(irradianceCases()); cases != want {
		t.Fatalf("%d vector cases in %s, want the %d of testCases and irradianceCases (regenerate with -update)", cases, vectorDir, want)
	}
}

func writeVectors(t *testing.T) {
	for _, tc := range append(testCases(), irradianceCases()...) {
		dir := filepath.Join(vectorDir, tc.name)
		if err := os.RemoveAll(dir); err != nil {
			t.Fatal(err)
		}
		if err := os.MkdirAll(dir, 0o755); err != nil {
			t.Fatal(err)
		}
		for i, s := range tc.shards {
			if err := os.WriteFile(filepath.Join(dir, fmt.Sprintf("shard-%03d.bin", i)), s.Data, 0o644); err != nil {
				t.Fatal(err)
			}
		}
		for i, s := range tc.irradiance {
			if err := os.WriteFile(filepath.Join(dir, fmt.Sprintf("irradiance-%03d.bin", i)), s, 0o644); err != nil {
				t.Fatal(err)
			}
		}
		snap, err := Build(tc.shards)
		if err != nil {
			t.Fatal(err)
		}
		if len(tc.irradiance) > 0 {
			if snap, err = MergeIrradiance(snap, tc.irradiance); err != nil {
				t.Fatal(err)
			}
		}
		if err := os.WriteFile(filepath.Join(dir, "snapshot.bin"), snap, 0o644); err != nil {
			t.Fatal(err)
		}
	}
}
