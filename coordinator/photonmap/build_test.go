package photonmap

import (
	"bytes"
	"errors"
	"io"
	"math"
	"math/rand/v2"
	"slices"
	"strings"
	"testing"

	"photonfarm/coordinator/errs"
)

type testCase struct {
	name   string
	shards []Shard
	// Irradiance shards merged into the snapshot by MergeIrradiance, if any.
	irradiance [][]byte
}

func testCases() []testCase {
	r := rand.New(rand.NewPCG(1, 2))
	random := uniformPhotons(r, 1000)
	caustic := uniformPhotons(r, 300)
	return []testCase{
		{"random-1000", append(splitShards(Global, random, 100, 600), splitShards(Caustic, caustic, 150)...), nil},
		{"plane", splitShards(Global, planePhotons(r, 500), 250), nil},
		{"duplicates", splitShards(Global, duplicatePhotons(r, 200), 10, 20), nil},
		{"one-photon", append(splitShards(Global, uniformPhotons(r, 1)), splitShards(Caustic, nil)...), nil},
		{"empty-caustic", append(splitShards(Global, uniformPhotons(r, 300)), splitShards(Caustic, nil)...), nil},
		{"no-maps", nil, nil},
		{"three-maps", slices.Concat(splitShards(Global, uniformPhotons(r, 400), 150), splitShards(Caustic, uniformPhotons(r, 200), 50),
			splitShards(Volume, volumePhotons(r, 300), 100, 220)), nil},
		{"volume-only", splitShards(Volume, volumePhotons(r, 250), 120), nil},
	}
}

// inputPhotons decodes the shards of one kind in order: the ground truth a map must hold.
func inputPhotons(t *testing.T, shards []Shard, kind Kind) (photons []ShardPhoton, paths uint64) {
	t.Helper()
	for i, s := range shards {
		sc, h, err := openShard(i, BytesSource(s.Data))
		if err != nil {
			t.Fatal(err)
		}
		defer sc.Close()
		if h.kind != kind {
			continue
		}
		paths += h.photonCount
		for {
			rec, err := nextShardRecord(i, sc)
			if errors.Is(err, io.EOF) {
				break
			}
			if err != nil {
				t.Fatal(err)
			}
			photons = append(photons, shardPhoton(rec))
		}
	}
	return photons, paths
}

// key identifies a photon by its exact stored fields, for multiset comparison.
type key struct {
	pos        [3]float32
	power      uint32
	wi, normal uint16
}

func TestBuildKeepsEveryPhotonAndTheTreeInvariant(t *testing.T) {
	for _, tc := range testCases() {
		t.Run(tc.name, func(t *testing.T) {
			data, err := Build(tc.shards)
			if err != nil {
				t.Fatal(err)
			}
			snap, err := Decode(data)
			if err != nil {
				t.Fatal(err)
			}
			var kinds []Kind
			for _, s := range tc.shards {
				if k := Kind(le.Uint32(s.Data[12:])); !slices.Contains(kinds, k) {
					kinds = append(kinds, k)
				}
			}
			if len(snap.Maps) != len(kinds) {
				t.Fatalf("%d maps, want %d", len(snap.Maps), len(kinds))
			}
			for i, m := range snap.Maps {
				in, paths := inputPhotons(t, tc.shards, kinds[i])
				if m.Kind != kinds[i] || m.PathsEmitted != paths || len(m.Photons) != len(in) {
					t.Fatalf("map %d: kind %v paths %d photons %d, want %v %d %d",
						i, m.Kind, m.PathsEmitted, len(m.Photons), kinds[i], paths, len(in))
				}
				checkMap(t, m, in)
			}
		})
	}
}

func checkMap(t *testing.T, m Map, in []ShardPhoton) {
	t.Helper()
	if err := CheckTree(m.Photons); err != nil {
		t.Fatal(err)
	}
	// Scale, bounds and every photon, from the input alone.
	var scale float32
	lo, hi := [3]float32{}, [3]float32{}
	for i, p := range in {
		for c := 0; c < 3; c++ {
			scale = max(scale, p.Power[c])
			if i == 0 || p.Position[c] < lo[c] {
				lo[c] = p.Position[c]
			}
			if i == 0 || p.Position[c] > hi[c] {
				hi[c] = p.Position[c]
			}
		}
	}
	if scale == 0 {
		scale = 1
	}
	if m.PowerScale != scale || m.BoundsMin != lo || m.BoundsMax != hi {
		t.Fatalf("scale %g bounds %v %v, want %g %v %v", m.PowerScale, m.BoundsMin, m.BoundsMax, scale, lo, hi)
	}
	want := map[key]int{}
	for _, p := range in {
		// The power's quantisation is checked against the float input: within half a
		// mantissa step of the photon's brightest component.
		want[key{p.Position, 0, p.Wi, p.Normal}]++
	}
	for _, p := range m.Photons {
		k := key{p.Position, 0, p.Wi, p.Normal}
		if want[k] == 0 {
			t.Fatalf("photon %+v is not in the input (or is there fewer times)", p)
		}
		want[k]--
	}
	// Powers: match each stored photon to an input with the same fields, in input order.
	pending := map[key][]ShardPhoton{}
	for _, p := range in {
		k := key{p.Position, 0, p.Wi, p.Normal}
		pending[k] = append(pending[k], p)
	}
	for _, p := range m.Photons {
		k := key{p.Position, 0, p.Wi, p.Normal}
		cands := pending[k]
		rel := DecodeRGB9E5(p.Power)
		found := -1
		for j, c := range cands {
			maxc := max(c.Power[0], c.Power[1], c.Power[2])
			ok := true
			for ch := 0; ch < 3; ch++ {
				got := float64(rel[ch]) * float64(scale)
				if math.Abs(got-float64(c.Power[ch])) > float64(maxc)/512*1.01+1e-30 {
					ok = false
				}
			}
			if ok {
				found = j
				break
			}
		}
		if found < 0 {
			t.Fatalf("photon %+v: power %v matches no input photon at its position", p, rel)
		}
		pending[k] = append(cands[:found], cands[found+1:]...)
	}
}

func TestLeftSubtreeSizeMatchesTheHeapLayout(t *testing.T) {
	// Count, for a heap of m nodes, the nodes under node 1 (the root's left child).
	for m := 2; m < 2000; m++ {
		count := 0
		for level, first := 0, 1; first < m; level, first = level+1, 2*first+1 {
			width := 1 << level
			count += min(width, m-first)
		}
		if got := leftSubtreeSize(m); got != count {
			t.Fatalf("leftSubtreeSize(%d) = %d, heap layout has %d", m, got, count)
		}
	}
}

func TestBuildIsDeterministic(t *testing.T) {
	r := rand.New(rand.NewPCG(5, 6))
	photons := duplicatePhotons(r, 150000) // large enough to build subtrees in parallel
	photons = append(photons, planePhotons(r, 150000)...)
	a, err := Build(splitShards(Global, photons, 1000, 200000))
	if err != nil {
		t.Fatal(err)
	}
	for _, cuts := range [][]int{{1000, 200000}, {}, {1, 2, 3, 299999}} {
		// Any tiling of the same photons gives the same snapshot.
		b, err := Build(splitShards(Global, photons, cuts...))
		if err != nil {
			t.Fatal(err)
		}
		if !bytes.Equal(a, b) {
			t.Fatalf("cuts %v: snapshot differs", cuts)
		}
	}
}

func TestBuildRefusesMalformedShards(t *testing.T) {
	good := EncodeShard(Global, 0, 10, uniformPhotons(rand.New(rand.NewPCG(1, 1)), 3))
	edit := func(f func(b []byte) []byte) []byte { return f(bytes.Clone(good)) }
	putF32 := func(b []byte, off int, v float32) []byte { le.PutUint32(b[off:], math.Float32bits(v)); return b }
	rec := func(r, field int) int { return shardHeaderSize + r*shardRecordSize + field }
	nextGlobal := EncodeShard(Global, 10, 5, nil)
	caustic := EncodeShard(Caustic, 0, 5, nil)
	volume := EncodeShard(Volume, 0, 5, nil)
	cases := []struct {
		name   string
		shards [][]byte
		bad    int
		want   string
	}{
		{"empty", [][]byte{{}}, 0, "shorter"},
		{"magic", [][]byte{edit(func(b []byte) []byte { b[0] = 'X'; return b })}, 0, "magic"},
		{"version", [][]byte{edit(func(b []byte) []byte { b[8] = 2; return b })}, 0, "version"},
		{"kind past volume", [][]byte{edit(func(b []byte) []byte { b[12] = byte(Volume + 1); return b })}, 0, "unknown map kind 4"},
		{"kind 0", [][]byte{edit(func(b []byte) []byte { b[12] = 0; return b })}, 0, "unknown map kind 0"},
		{"record count too big", [][]byte{edit(func(b []byte) []byte { le.PutUint64(b[32:], 1<<62); return b })}, 0, "record_count"},
		{"truncated", [][]byte{good[:len(good)-1]}, 0, "record_count"},
		{"trailing", [][]byte{append(bytes.Clone(good), 0)}, 0, "record_count"},
		{"nan position", [][]byte{edit(func(b []byte) []byte { return putF32(b, rec(1, 4), float32(math.NaN())) })}, 0, "record 1: position"},
		{"inf position", [][]byte{edit(func(b []byte) []byte { return putF32(b, rec(2, 8), float32(math.Inf(-1))) })}, 0, "record 2: position"},
		{"negative power", [][]byte{edit(func(b []byte) []byte { return putF32(b, rec(0, 16), -1) })}, 0, "power"},
		{"nan power", [][]byte{edit(func(b []byte) []byte { return putF32(b, rec(0, 12), float32(math.NaN())) })}, 0, "power"},
		{"inf power", [][]byte{edit(func(b []byte) []byte { return putF32(b, rec(0, 20), float32(math.Inf(1))) })}, 0, "power"},
		{"normal low bits", [][]byte{edit(func(b []byte) []byte { b[rec(1, 26)] |= 2; return b })}, 0, "normal"},
		{"gap", [][]byte{good, EncodeShard(Global, 11, 5, nil)}, 1, "starts at photon 11, want 10"},
		{"overlap", [][]byte{good, EncodeShard(Global, 9, 5, nil)}, 1, "want 10"},
		{"not from zero", [][]byte{nextGlobal}, 0, "want 0"},
		{"global after caustic", [][]byte{caustic, good}, 1, "global shard after caustic shards: shards come in plan order"},
		{"caustic after volume", [][]byte{good, volume, caustic}, 2, "caustic shard after volume shards"},
		{"path overflow", [][]byte{good, EncodeShard(Global, 10, math.MaxUint64, nil)}, 1, "overflows"},
		{"bad shard after good ones", [][]byte{good, nextGlobal, caustic, {1, 2, 3}}, 3, "shorter"},
	}
	for _, tc := range cases {
		t.Run(tc.name, func(t *testing.T) {
			var shards []Shard
			for _, d := range tc.shards {
				shards = append(shards, Shard{Data: d})
			}
			_, err := Build(shards)
			if err == nil {
				t.Fatal("Build accepted a malformed shard")
			}
			var e *errs.Error
			if !errs.Is(err, errs.InvalidArgument) || !asErr(err, &e) || e.Field != "shards["+itoa(tc.bad)+"]" {
				t.Fatalf("error %v: want InvalidArgument on shards[%d]", err, tc.bad)
			}
			if !strings.Contains(err.Error(), tc.want) {
				t.Fatalf("error %q does not mention %q", err, tc.want)
			}
		})
	}
}

func TestRGB9E5(t *testing.T) {
	r := rand.New(rand.NewPCG(9, 9))
	for i := 0; i < 100000; i++ {
		c := [3]float64{r.Float64(), r.Float64() * math.Pow(2, -float64(r.IntN(30))), 0}
		if i%3 == 0 {
			c[2] = r.Float64()
		}
		got := DecodeRGB9E5(EncodeRGB9E5(c))
		maxc := max(c[0], c[1], c[2])
		for ch := 0; ch < 3; ch++ {
			// Round to nearest on a grid of maxc's exponent: error at most half a step.
			if err := math.Abs(float64(got[ch]) - c[ch]); err > maxc/512+0x1p-25 {
				t.Fatalf("%v -> %v: component %d off by %g", c, got, ch, err)
			}
		}
	}
	for _, exact := range [][3]float64{{0, 0, 0}, {1, 1, 1}, {1, 0.5, 0.25}, {0x1p-24, 0, 0x1p-24}} {
		got := DecodeRGB9E5(EncodeRGB9E5(exact))
		if [3]float64{float64(got[0]), float64(got[1]), float64(got[2])} != exact {
			t.Errorf("%v decodes to %v", exact, got)
		}
	}
}

func TestBuildFromStopsAtTheSnapshotLimitCountingEveryMap(t *testing.T) {
	r := rand.New(rand.NewPCG(3, 4))
	shards := append(splitShards(Global, uniformPhotons(r, 10), 6), splitShards(Caustic, uniformPhotons(r, 10), 4)...)
	var sources []Source
	for _, s := range shards {
		sources = append(sources, BytesSource(s.Data))
	}
	if _, err := BuildFrom(sources, 20); err != nil {
		t.Fatalf("20 photons at a limit of 20: %v", err)
	}
	_, err := BuildFrom(sources, 15) // 10 global photons, 4 caustic; the last 6 go over
	var many *TooManyPhotons
	paths := le.Uint64(shards[2].Data[24:]) + le.Uint64(shards[3].Data[24:])
	if !errors.As(err, &many) || *many != (TooManyPhotons{Limit: 15, Shard: 3, Map: Caustic, MapPhotons: 10, MapPaths: paths}) {
		t.Fatalf("BuildFrom at a limit of 15 = %v, want TooManyPhotons at shards[3]", err)
	}
}

// failingAtEnd is a source whose reader fails where the input ends, as the blob store's
// checked reader does for a damaged blob.
func failingAtEnd(data []byte, err error) Source {
	return func() (io.ReadCloser, error) {
		return io.NopCloser(io.MultiReader(bytes.NewReader(data), errReader{err})), nil
	}
}

type errReader struct{ err error }

func (e errReader) Read([]byte) (int, error) { return 0, e.err }

func TestBuildAndMergeReturnTheirSourcesErrorsUnchanged(t *testing.T) {
	damaged := errs.E(errs.DataLoss, "blob is damaged")
	shards := splitShards(Global, uniformPhotons(rand.New(rand.NewPCG(5, 6)), 10))
	if _, err := BuildFrom([]Source{failingAtEnd(shards[0].Data, damaged)}, math.MaxInt); err != damaged {
		t.Errorf("BuildFrom = %v, want the source's error %v", err, damaged)
	}
	snap := snapshotOf(t, 10)
	irr := EncodeIrradianceShard(0, make([][3]float32, 10))
	if _, err := MergeIrradianceTo(io.Discard, failingAtEnd(snap, damaged), int64(len(snap)), []Source{BytesSource(irr)}); err != damaged {
		t.Errorf("MergeIrradianceTo, damaged snapshot = %v, want %v", err, damaged)
	}
	if _, err := MergeIrradianceTo(io.Discard, BytesSource(snap), int64(len(snap)), []Source{failingAtEnd(irr, damaged)}); err != damaged {
		t.Errorf("MergeIrradianceTo, damaged shard = %v, want %v", err, damaged)
	}
}
