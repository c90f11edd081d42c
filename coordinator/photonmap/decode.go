package photonmap

import (
	"fmt"
	"math"
)

// Photon is a snapshot record, fields as stored.
type Photon struct {
	Position [3]float32
	Power    uint32 // RGB9E5, relative to the map's PowerScale
	Wi       uint16 // oct8
	Normal   uint16 // oct7 in bits 2-15, bits 0-1 cleared
	Axis     int    // 0-2 split axis, 3 leaf
}

// Map is one decoded photon map: its photons in kd-tree (array) order.
type Map struct {
	Kind         Kind
	PathsEmitted uint64
	BoundsMin    [3]float32
	BoundsMax    [3]float32
	PowerScale   float32
	Photons      []Photon
}

// Snapshot is a decoded snapshot.
type Snapshot struct {
	Maps []Map
}

// Decode parses and validates a snapshot; tests and tools use it to check what Build wrote.
// It checks the layout and the axis field, not the kd-tree ordering (see CheckTree).
func Decode(data []byte) (*Snapshot, error) {
	bad := func(format string, args ...any) error {
		return fmt.Errorf("photon snapshot: "+format, args...)
	}
	if len(data) < headerSize {
		return nil, bad("%d bytes is shorter than the header", len(data))
	}
	if string(data[:8]) != snapshotMagic {
		return nil, bad("bad magic %q", data[:8])
	}
	if v := le.Uint32(data[8:]); v != snapshotVersion {
		return nil, bad("unsupported version %d", v)
	}
	if h := le.Uint32(data[12:]); h != headerSize {
		return nil, bad("header_size %d, want %d", h, headerSize)
	}
	count := le.Uint32(data[16:])
	if count > 2 {
		return nil, bad("map_count %d > 2", count)
	}
	if e := le.Uint32(data[20:]); e != dirEntrySize {
		return nil, bad("directory_entry_size %d, want %d", e, dirEntrySize)
	}
	if fs := le.Uint64(data[24:]); fs != uint64(len(data)) {
		return nil, bad("file_size %d, but %d bytes", fs, len(data))
	}
	dirEnd := uint64(headerSize + dirEntrySize*int(count))
	if dirEnd > uint64(len(data)) {
		return nil, bad("directory runs past the end")
	}
	snap := &Snapshot{}
	end := dirEnd
	for i := 0; i < int(count); i++ {
		d := data[headerSize+i*dirEntrySize:]
		m := Map{
			Kind:         Kind(le.Uint32(d[0:])),
			PathsEmitted: le.Uint64(d[8:]),
			PowerScale:   math.Float32frombits(le.Uint32(d[48:])),
		}
		n := uint64(le.Uint32(d[4:]))
		off := le.Uint64(d[16:])
		switch {
		case m.Kind != Global && m.Kind != Caustic:
			return nil, bad("map %d: unknown kind %d", i, m.Kind)
		case i > 0 && m.Kind <= snap.Maps[i-1].Kind:
			return nil, bad("map %d: kinds not increasing", i)
		case n > maxMapPhotons:
			return nil, bad("map %d: photon_count %d over the limit", i, n)
		case off%mapAlignment != 0 || off < end || off > uint64(len(data)):
			return nil, bad("map %d: offset %d not 64-aligned after byte %d", i, off, end)
		case n > (uint64(len(data))-off)/recordSize:
			return nil, bad("map %d: %d photons run past the end", i, n)
		case !(m.PowerScale > 0) || math.IsInf(float64(m.PowerScale), 0):
			return nil, bad("map %d: power_scale %g", i, m.PowerScale)
		case le.Uint32(d[52:]) != recordSize:
			return nil, bad("map %d: record_size %d", i, le.Uint32(d[52:]))
		}
		for c := 0; c < 3; c++ {
			m.BoundsMin[c] = math.Float32frombits(le.Uint32(d[24+4*c:]))
			m.BoundsMax[c] = math.Float32frombits(le.Uint32(d[36+4*c:]))
		}
		m.Photons = make([]Photon, n)
		for j := range m.Photons {
			rec := data[off+uint64(j)*recordSize:]
			p := &m.Photons[j]
			for c := 0; c < 3; c++ {
				p.Position[c] = math.Float32frombits(le.Uint32(rec[4*c:]))
			}
			p.Power = le.Uint32(rec[12:])
			p.Wi = le.Uint16(rec[16:])
			nrm := le.Uint16(rec[18:])
			p.Normal = nrm &^ normalAxisMask
			p.Axis = int(nrm & normalAxisMask)
			if leaf := 2*uint64(j)+1 >= n; leaf != (p.Axis == axisLeaf) {
				return nil, bad("map %d: photon %d: axis %d, but leaf is %v", i, j, p.Axis, leaf)
			}
		}
		end = off + n*recordSize
		snap.Maps = append(snap.Maps, m)
	}
	if end != uint64(len(data)) {
		return nil, bad("%d trailing bytes", uint64(len(data))-end)
	}
	return snap, nil
}

// CheckTree reports the first node that violates the kd-tree invariant: every photon in a
// node's left subtree has coordinate <= the node's on its split axis, every photon in the
// right subtree >=. It walks the tree once, narrowing per-axis bounds on the way down.
func CheckTree(photons []Photon) error {
	inf := float32(math.Inf(1))
	var walk func(i int, lo, hi [3]float32) error
	walk = func(i int, lo, hi [3]float32) error {
		if i >= len(photons) {
			return nil
		}
		p := photons[i]
		for c := 0; c < 3; c++ {
			if p.Position[c] < lo[c] || p.Position[c] > hi[c] {
				return fmt.Errorf("photon %d at %v lies outside [%v, %v] set by its ancestors", i, p.Position, lo, hi)
			}
		}
		if p.Axis == axisLeaf {
			return nil
		}
		a := p.Axis
		l, r := hi, lo
		l[a] = p.Position[a]
		r[a] = p.Position[a]
		if err := walk(2*i+1, lo, l); err != nil {
			return err
		}
		return walk(2*i+2, r, hi)
	}
	return walk(0, [3]float32{-inf, -inf, -inf}, [3]float32{inf, inf, inf})
}
