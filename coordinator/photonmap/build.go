package photonmap

import (
	"errors"
	"fmt"
	"io"
	"math"

	"photonfarm/coordinator/errs"
)

// mapInput is one map's shards, checked, in plan order, with what the first pass learnt.
type mapInput struct {
	kind         Kind
	pathsEmitted uint64
	photons      int
	shards       []int // indices into the Build argument
	scale        float32
	bounds       box
}

// Build merges emission shards held in memory into a snapshot: BuildFrom with no limit
// but the format's (2^31 - 1 photons a map).
func Build(shards []Shard) ([]byte, error) {
	sources := make([]Source, len(shards))
	for i, s := range shards {
		sources[i] = BytesSource(s.Data)
	}
	return BuildFrom(sources, math.MaxInt)
}

// TooManyPhotons is BuildFrom's error when the shards store more photons than a snapshot
// may hold: the shard at which the count went over, and what the map it belongs to
// stores so far.
type TooManyPhotons struct {
	Limit      int
	Shard      int
	Map        Kind
	MapPhotons int    // stored by the map's shards up to and including Shard
	MapPaths   uint64 // traced by them
}

func (e *TooManyPhotons) Error() string {
	return fmt.Sprintf("shards[%d]: more than the %d photons a snapshot may hold: the %s map's shards up to this one store %d photons from %d paths",
		e.Shard, e.Limit, e.Map, e.MapPhotons, e.MapPaths)
}

// BuildFrom is BuildTo with the snapshot in memory: each node is copied to its place as
// it is chosen, the builder's original way, which tests hold the blocked writes of BuildTo
// to.
func BuildFrom(shards []Source, maxPhotons int) ([]byte, error) {
	var out memOutput
	if _, err := buildTo(&out, shards, maxPhotons, 1); err != nil {
		return nil, err
	}
	return out.b, nil
}

// Output is where BuildTo writes a snapshot: an *os.File, or memory. Truncate is called
// once, first, with the snapshot's size; the writes then fill it, from several goroutines
// at once at disjoint offsets.
type Output interface {
	io.WriterAt
	Truncate(size int64) error
}

// fileBlock is the largest subtree BuildTo builds in a buffer of its own and writes a level
// at a time (1.3 MB a buffer): about 17 writes per 65,536 photons.
const fileBlock = 1 << 16

// BuildTo merges emission shards, given in plan order (all global shards in path order,
// then all caustic shards, then all volume shards), into a snapshot of at most maxPhotons
// photons over all maps written to out: per map a left-balanced kd-tree of 20-byte photons
// (docs/photon-snapshot.md). It returns the snapshot's size. Shards are untrusted: a
// malformed one gives an InvalidArgument error naming it ("shards[3]: ..."), a map over
// the format's limit ResourceExhausted, more photons than maxPhotons a *TooManyPhotons;
// errors of out are returned unchanged. The same shards always give the same bytes.
//
// Each shard is read twice, record by record, and never held, and the output is written
// as it is decided, never held: at its peak a build holds the working records of its
// largest map (24 bytes a photon) and a few block buffers.
func BuildTo(out Output, shards []Source, maxPhotons int) (int64, error) {
	return buildTo(out, shards, maxPhotons, fileBlock)
}

func buildTo(out Output, shards []Source, maxPhotons, block int) (int64, error) {
	maps, err := planMaps(shards, maxPhotons)
	if err != nil {
		return 0, err
	}

	// Layout first, so the output has its size before each tree writes into it in place.
	offsets := make([]int, len(maps))
	size := headerSize + dirEntrySize*len(maps)
	for i, m := range maps {
		size = alignUp(size, mapAlignment)
		offsets[i] = size
		size += recordSize * m.photons
	}
	if err := out.Truncate(int64(size)); err != nil {
		return 0, err
	}
	head := make([]byte, headerSize+dirEntrySize*len(maps))
	copy(head, snapshotMagic)
	le.PutUint32(head[8:], snapshotVersion)
	le.PutUint32(head[12:], headerSize)
	le.PutUint32(head[16:], uint32(len(maps)))
	le.PutUint32(head[20:], dirEntrySize)
	le.PutUint64(head[24:], uint64(size))
	for i, m := range maps {
		dir := head[headerSize+i*dirEntrySize:]
		le.PutUint32(dir[0:], uint32(m.kind))
		le.PutUint32(dir[4:], uint32(m.photons))
		le.PutUint64(dir[8:], m.pathsEmitted)
		le.PutUint64(dir[16:], uint64(offsets[i]))
		for c := 0; c < 3; c++ {
			le.PutUint32(dir[24+4*c:], math.Float32bits(m.bounds.min[c]))
			le.PutUint32(dir[36+4*c:], math.Float32bits(m.bounds.max[c]))
		}
		le.PutUint32(dir[48:], math.Float32bits(m.scale))
		le.PutUint32(dir[52:], recordSize)
	}
	if _, err := out.WriteAt(head, 0); err != nil {
		return 0, err
	}
	for i, m := range maps {
		items, err := gatherMap(shards, m)
		if err != nil {
			return 0, err
		}
		if err := buildTree(items, &treeWriter{out: out, base: int64(offsets[i]), block: block}); err != nil {
			return 0, err
		}
	}
	return int64(size), nil
}

// memOutput is an Output in memory.
type memOutput struct{ b []byte }

func (m *memOutput) Truncate(size int64) error {
	m.b = make([]byte, size)
	return nil
}

func (m *memOutput) WriteAt(p []byte, off int64) (int, error) {
	if off < 0 || off+int64(len(p)) > int64(len(m.b)) {
		return 0, fmt.Errorf("photonmap: write of %d bytes at %d past the snapshot's %d", len(p), off, len(m.b))
	}
	return copy(m.b[off:], p), nil
}

// planMaps reads every shard once: it checks each whole and the plan order, groups the
// shards by map and finds each map's power scale (largest power component, 1 if none is
// positive) and bounds.
func planMaps(shards []Source, maxPhotons int) ([]mapInput, error) {
	var maps []mapInput
	total := 0
	for i, src := range shards {
		s, h, err := openShard(i, src)
		if err != nil {
			return nil, err
		}
		if len(maps) == 0 || maps[len(maps)-1].kind != h.kind {
			if len(maps) > 0 && maps[len(maps)-1].kind > h.kind {
				s.Close()
				return nil, shardErr(i, "%s shard after %s shards: shards come in plan order, global, caustic, volume", h.kind, maps[len(maps)-1].kind)
			}
			maps = append(maps, mapInput{kind: h.kind})
		}
		m := &maps[len(maps)-1]
		// Shards of a map must tile its path range exactly: a gap or an overlap means a
		// shard is missing or repeated, and the powers (divided by the total) would be wrong.
		if h.firstPhoton != m.pathsEmitted {
			s.Close()
			return nil, shardErr(i, "%s shard starts at photon %d, want %d (shards must tile the path range in order)",
				h.kind, h.firstPhoton, m.pathsEmitted)
		}
		if h.photonCount > math.MaxUint64-m.pathsEmitted {
			s.Close()
			return nil, shardErr(i, "photon_count %d overflows the path range", h.photonCount)
		}
		m.pathsEmitted += h.photonCount
		n, err := scanShard(i, s, m)
		s.Close()
		if err != nil {
			return nil, err
		}
		// Counted from the records read, not the header's claim: the shard is whole here.
		if n > maxPhotons-total {
			return nil, &TooManyPhotons{Limit: maxPhotons, Shard: i, Map: h.kind, MapPhotons: m.photons + n, MapPaths: m.pathsEmitted}
		}
		if n > maxMapPhotons-m.photons {
			return nil, errs.E(errs.ResourceExhausted, "%s photon map: more than %d photons (shards[%d])", h.kind, maxMapPhotons, i)
		}
		m.photons += n
		total += n
		m.shards = append(m.shards, i)
	}
	for i := range maps {
		if !(maps[i].scale > 0) {
			maps[i].scale = 1
		}
	}
	return maps, nil
}

// scanShard reads shard i's records, checking each, and grows m's power scale and bounds;
// it returns how many there were.
func scanShard(i int, s *scanner, m *mapInput) (int, error) {
	n := 0
	for {
		rec, err := nextShardRecord(i, s)
		if errors.Is(err, io.EOF) {
			return n, nil
		}
		if err != nil {
			return n, err
		}
		p := shardPhoton(rec)
		if m.photons == 0 && n == 0 {
			m.bounds = box{min: p.Position, max: p.Position}
		}
		for c := 0; c < 3; c++ {
			m.scale = max(m.scale, p.Power[c])
			m.bounds.min[c] = min(m.bounds.min[c], p.Position[c])
			m.bounds.max[c] = max(m.bounds.max[c], p.Position[c])
		}
		n++
	}
}

type box struct{ min, max [3]float32 }

// gatherMap reads a map's shards again into working records, powers encoded relative to
// the map's scale. A shard that no longer holds what the first pass read (changed between
// the reads) is an error.
func gatherMap(shards []Source, m mapInput) ([]item, error) {
	items := make([]item, 0, m.photons)
	for _, si := range m.shards {
		s, _, err := openShard(si, shards[si])
		if err != nil {
			return nil, err
		}
		for {
			rec, err := nextShardRecord(si, s)
			if errors.Is(err, io.EOF) {
				break
			}
			if err == nil && len(items) == m.photons {
				err = errs.E(errs.Internal, "shards[%d] changed between the two reads of the build", si)
			}
			if err != nil {
				s.Close()
				return nil, err
			}
			p := shardPhoton(rec)
			it := item{pos: p.Position, wi: p.Wi, normal: p.Normal, src: uint32(len(items))}
			var rel [3]float64
			for c := 0; c < 3; c++ {
				rel[c] = float64(p.Power[c]) / float64(m.scale)
			}
			it.power = EncodeRGB9E5(rel)
			items = append(items, it)
		}
		s.Close()
	}
	if len(items) != m.photons {
		return nil, errs.E(errs.Internal, "the %s map's shards changed between the two reads of the build", m.kind)
	}
	return items, nil
}

func alignUp(n, a int) int { return (n + a - 1) / a * a }

// String helps failing tests print a box.
func (b box) String() string { return fmt.Sprintf("[%v, %v]", b.min, b.max) }
