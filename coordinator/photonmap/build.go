package photonmap

import (
	"fmt"
	"math"

	"photonfarm/coordinator/errs"
)

// mapInput is one map's shards, validated, in plan order.
type mapInput struct {
	kind         Kind
	pathsEmitted uint64
	photons      int
	shards       []int // indices into the Build argument
}

// Build merges emission shards, given in plan order (all global shards in path order, then
// all caustic shards), into a snapshot: per map a left-balanced kd-tree of 20-byte photons
// (docs/photon-snapshot.md). Shards are untrusted: a malformed one gives an InvalidArgument
// error naming it ("shards[3]: ..."), a map over the photon limit ResourceExhausted. The
// same shards always give the same bytes.
func Build(shards []Shard) ([]byte, error) {
	maps, err := planMaps(shards)
	if err != nil {
		return nil, err
	}

	// Layout first, so the output is allocated once and each tree writes into it in place.
	offsets := make([]int, len(maps))
	size := headerSize + dirEntrySize*len(maps)
	for i, m := range maps {
		size = alignUp(size, mapAlignment)
		offsets[i] = size
		size += recordSize * m.photons
	}
	out := make([]byte, size)
	copy(out, snapshotMagic)
	le.PutUint32(out[8:], snapshotVersion)
	le.PutUint32(out[12:], headerSize)
	le.PutUint32(out[16:], uint32(len(maps)))
	le.PutUint32(out[20:], dirEntrySize)
	le.PutUint64(out[24:], uint64(size))

	for i, m := range maps {
		items, bounds, scale := gatherMap(shards, m)
		dir := out[headerSize+i*dirEntrySize:]
		le.PutUint32(dir[0:], uint32(m.kind))
		le.PutUint32(dir[4:], uint32(m.photons))
		le.PutUint64(dir[8:], m.pathsEmitted)
		le.PutUint64(dir[16:], uint64(offsets[i]))
		for c := 0; c < 3; c++ {
			le.PutUint32(dir[24+4*c:], math.Float32bits(bounds.min[c]))
			le.PutUint32(dir[36+4*c:], math.Float32bits(bounds.max[c]))
		}
		le.PutUint32(dir[48:], math.Float32bits(scale))
		le.PutUint32(dir[52:], recordSize)
		buildTree(items, out[offsets[i]:offsets[i]+recordSize*m.photons])
	}
	return out, nil
}

// planMaps validates every shard and the plan order, and groups shards by map.
func planMaps(shards []Shard) ([]mapInput, error) {
	var maps []mapInput
	for i, s := range shards {
		h, err := parseShard(i, s.Data)
		if err != nil {
			return nil, err
		}
		if len(maps) == 0 || maps[len(maps)-1].kind != h.kind {
			if len(maps) > 0 && maps[len(maps)-1].kind > h.kind {
				return nil, shardErr(i, "%s shard after %s shards: global shards come first", h.kind, maps[len(maps)-1].kind)
			}
			maps = append(maps, mapInput{kind: h.kind})
		}
		m := &maps[len(maps)-1]
		// Shards of a map must tile its path range exactly: a gap or an overlap means a
		// shard is missing or repeated, and the powers (divided by the total) would be wrong.
		if h.firstPhoton != m.pathsEmitted {
			return nil, shardErr(i, "%s shard starts at photon %d, want %d (shards must tile the path range in order)",
				h.kind, h.firstPhoton, m.pathsEmitted)
		}
		if h.photonCount > math.MaxUint64-m.pathsEmitted {
			return nil, shardErr(i, "photon_count %d overflows the path range", h.photonCount)
		}
		m.pathsEmitted += h.photonCount
		if h.records > maxMapPhotons-m.photons {
			return nil, errs.E(errs.ResourceExhausted, "%s photon map: more than %d photons (shards[%d])",
				h.kind, maxMapPhotons, i)
		}
		m.photons += h.records
		m.shards = append(m.shards, i)
	}
	return maps, nil
}

type box struct{ min, max [3]float32 }

// gatherMap concatenates a map's validated shards into working records, with the bounds and
// the power scale (largest power component, 1 if none is positive).
func gatherMap(shards []Shard, m mapInput) ([]item, box, float32) {
	var scale float32
	for _, si := range m.shards {
		data := shards[si].Data
		for r := shardHeaderSize; r < len(data); r += shardRecordSize {
			for c := 0; c < 3; c++ {
				scale = max(scale, math.Float32frombits(le.Uint32(data[r+12+4*c:])))
			}
		}
	}
	if !(scale > 0) {
		scale = 1
	}
	items := make([]item, 0, m.photons)
	for _, si := range m.shards {
		data := shards[si].Data
		for r := shardHeaderSize; r < len(data); r += shardRecordSize {
			var it item
			var rel [3]float64
			for c := 0; c < 3; c++ {
				it.pos[c] = math.Float32frombits(le.Uint32(data[r+4*c:]))
				rel[c] = float64(math.Float32frombits(le.Uint32(data[r+12+4*c:]))) / float64(scale)
			}
			it.power = EncodeRGB9E5(rel)
			it.wi = le.Uint16(data[r+24:])
			it.normal = le.Uint16(data[r+26:])
			it.src = uint32(len(items))
			items = append(items, it)
		}
	}
	return items, boundsOf(items), scale
}

func boundsOf(items []item) box {
	if len(items) == 0 {
		return box{}
	}
	b := box{min: items[0].pos, max: items[0].pos}
	for i := range items {
		for c := 0; c < 3; c++ {
			b.min[c] = min(b.min[c], items[i].pos[c])
			b.max[c] = max(b.max[c], items[i].pos[c])
		}
	}
	return b
}

func alignUp(n, a int) int { return (n + a - 1) / a * a }

// String helps failing tests print a box.
func (b box) String() string { return fmt.Sprintf("[%v, %v]", b.min, b.max) }
