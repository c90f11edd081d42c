package photonmap

import (
	"bytes"
	"math"
	"math/rand/v2"
	"strings"
	"testing"

	"photonfarm/coordinator/errs"
)

func randomIrradiance(r *rand.Rand, n int, scale float32) [][3]float32 {
	v := make([][3]float32, n)
	for i := range v {
		v[i] = [3]float32{r.Float32() * scale, r.Float32() * scale, r.Float32() * scale}
	}
	return v
}

// irradianceCases are the shared vectors with an irradiance section: shards of very
// different scales (so the merge must re-encode), an empty shard and an all-black one.
func irradianceCases() []testCase {
	r := rand.New(rand.NewPCG(3, 4))
	shards := append(splitShards(Global, uniformPhotons(r, 400), 200), splitShards(Caustic, uniformPhotons(r, 100))...)
	// 127 irradiance sites of the 400 photons: the tree's top 7 levels.
	irr := [][]byte{
		EncodeIrradianceShard(0, randomIrradiance(r, 50, 10)),
		EncodeIrradianceShard(50, nil),
		EncodeIrradianceShard(50, make([][3]float32, 50)),
		EncodeIrradianceShard(100, randomIrradiance(r, 27, 0.01)),
	}
	return []testCase{{"irradiance", shards, irr}}
}

// snapshotOf builds a snapshot of n global photons (and a few caustic ones).
func snapshotOf(t *testing.T, n int) []byte {
	t.Helper()
	r := rand.New(rand.NewPCG(5, 6))
	shards := append(splitShards(Global, uniformPhotons(r, n)), splitShards(Caustic, uniformPhotons(r, 7))...)
	snap, err := Build(shards)
	if err != nil {
		t.Fatal(err)
	}
	return snap
}

func TestMergeIrradianceStoresEverySitesIrradianceInTreeOrder(t *testing.T) {
	snap := snapshotOf(t, 300)
	const sites = 63 // the tree's top 6 levels, as a worker might choose
	r := rand.New(rand.NewPCG(7, 8))
	a, b := randomIrradiance(r, 20, 4), randomIrradiance(r, sites-20, 0.5)
	merged, err := MergeIrradiance(snap, [][]byte{EncodeIrradianceShard(0, a), EncodeIrradianceShard(20, b)})
	if err != nil {
		t.Fatal(err)
	}
	if len(merged)%4 != 0 || len(merged) < len(snap)+4*sites {
		t.Fatalf("merged snapshot of %d bytes for %d + 4 x %d", len(merged), len(snap), sites)
	}
	// The photon arrays are untouched.
	if !bytes.Equal(merged[headerSize:len(snap)], snap[headerSize:]) {
		t.Fatal("merge changed the directory or the photons")
	}
	d, err := Decode(merged)
	if err != nil {
		t.Fatal(err)
	}
	want := append(a, b...)
	if len(d.Irradiance) != len(want) {
		t.Fatalf("%d irradiance records, want %d", len(d.Irradiance), len(want))
	}
	for i, w := range want {
		got := DecodeRGB9E5(d.Irradiance[i])
		for c := 0; c < 3; c++ {
			g := float64(got[c] * d.IrradianceScale)
			// Two RGB9E5 roundings, each within half a step of 1/256 of the brightest component.
			tol := float64(max(w[0], w[1], w[2])) / 256
			if math.Abs(g-float64(w[c])) > tol {
				t.Fatalf("photon %d component %d: %g, want %g ± %g", i, c, g, w[c], tol)
			}
		}
	}
	again, err := MergeIrradiance(snap, [][]byte{EncodeIrradianceShard(0, a), EncodeIrradianceShard(20, b)})
	if err != nil || !bytes.Equal(again, merged) {
		t.Fatal("the same shards gave different bytes")
	}
}

func TestMergeIrradianceRefusesMalformedInput(t *testing.T) {
	snap := snapshotOf(t, 200) // shards of 63 irradiance sites
	good := func(first uint64, n int) []byte { return EncodeIrradianceShard(first, make([][3]float32, n)) }
	patch := func(b []byte, at int, p ...byte) []byte {
		c := bytes.Clone(b)
		copy(c[at:], p)
		return c
	}
	le32 := func(v uint32) []byte { return le.AppendUint32(nil, v) }
	le64 := func(v uint64) []byte { return le.AppendUint64(nil, v) }
	merged, err := MergeIrradiance(snap, [][]byte{good(0, 63)})
	if err != nil {
		t.Fatal(err)
	}
	noGlobal, err := Build(splitShards(Caustic, uniformPhotons(rand.New(rand.NewPCG(1, 1)), 5)))
	if err != nil {
		t.Fatal(err)
	}
	tooBright := good(0, 63)
	copy(tooBright[irrShardHeaderSize:], le32(31<<27|511)) // 511 * 2^7 of the scale
	tests := []struct {
		name     string
		snapshot []byte
		shards   [][]byte
		want     string // in the message
	}{
		{"gap", snap, [][]byte{good(0, 30), good(40, 23)}, "irradiance_shards[1]: starts at photon 40, want 30"},
		{"overlap", snap, [][]byte{good(0, 30), good(20, 43)}, "irradiance_shards[1]: starts at photon 20"},
		{"out of order", snap, [][]byte{good(30, 33), good(0, 30)}, "irradiance_shards[0]: starts at photon 30, want 0"},
		{"none", snap, nil, "cover no site of the global map's 200 photons"},
		{"empty", snap, [][]byte{good(0, 0)}, "cover no site"},
		{"too many", snap, [][]byte{good(0, 201)}, "run past the global map's 200"},
		{"short", snap, [][]byte{good(0, 63)[:39]}, "shorter than the 40-byte header"},
		{"magic", snap, [][]byte{patch(good(0, 63), 0, 'X')}, "bad magic"},
		{"version", snap, [][]byte{patch(good(0, 63), 8, le32(2)...)}, "unsupported version 2"},
		{"record size", snap, [][]byte{patch(good(0, 63), 12, le32(8)...)}, "record_size 8"},
		{"count vs size", snap, [][]byte{patch(good(0, 63), 24, le64(1<<62)...)}, "run past the global map's 200"}, // caught by the header, before the records
		{"truncated", snap, [][]byte{good(0, 63)[:40+4*63-1]}, "does not match"},
		{"nan scale", snap, [][]byte{patch(good(0, 63), 32, le32(math.Float32bits(float32(math.NaN())))...)}, "irradiance_scale"},
		{"zero scale", snap, [][]byte{patch(good(0, 63), 32, le32(0)...)}, "irradiance_scale"},
		{"infinite scale", snap, [][]byte{patch(good(0, 63), 32, le32(math.Float32bits(float32(math.Inf(1))))...)}, "irradiance_scale"},
		{"reserved", snap, [][]byte{patch(good(0, 63), 36, 1)}, "reserved"},
		{"record above scale", snap, [][]byte{tooBright}, "above 1"},
		{"bad snapshot", snap[:len(snap)-1], [][]byte{good(0, 63)}, "photon_snapshot"},
		{"already merged", merged, [][]byte{good(0, 63)}, "already has an irradiance section"},
		{"no global map", noGlobal, [][]byte{good(0, 0)}, "no global photon map"},
	}
	for _, tc := range tests {
		t.Run(tc.name, func(t *testing.T) {
			out, err := MergeIrradiance(tc.snapshot, tc.shards)
			if err == nil {
				t.Fatalf("accepted (%d bytes)", len(out))
			}
			if errs.KindOf(err) != errs.InvalidArgument {
				t.Errorf("kind %v, want InvalidArgument: %v", errs.KindOf(err), err)
			}
			if !strings.Contains(err.Error(), tc.want) {
				t.Errorf("error %q does not contain %q", err, tc.want)
			}
		})
	}
}

func TestDecodeRefusesAForgedIrradianceSection(t *testing.T) {
	snap := snapshotOf(t, 10)
	merged, err := MergeIrradiance(snap, [][]byte{EncodeIrradianceShard(0, randomIrradiance(rand.New(rand.NewPCG(1, 2)), 10, 1))})
	if err != nil {
		t.Fatal(err)
	}
	patch := func(at int, v []byte) []byte {
		c := bytes.Clone(merged)
		copy(c[at:], v)
		return c
	}
	for name, b := range map[string][]byte{
		"count past the map": patch(irrCountAt, le.AppendUint32(nil, 11)),
		"count zero":         patch(irrCountAt, le.AppendUint32(nil, 0)),
		"scale":              patch(irrScaleAt, le.AppendUint32(nil, 0)),
		"offset misaligned":  patch(irrOffsetAt, le.AppendUint64(nil, le.Uint64(merged[irrOffsetAt:])+4)),
		"no section, count":  patch(irrOffsetAt, le.AppendUint64(nil, 0)),
		"truncated":          merged[:len(merged)-4],
	} {
		if _, err := Decode(b); err == nil {
			t.Errorf("%s: accepted", name)
		}
	}
	if _, err := Decode(merged); err != nil {
		t.Fatal(err)
	}
}
