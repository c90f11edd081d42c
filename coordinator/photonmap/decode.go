package photonmap

import (
	"errors"
	"fmt"
	"io"
	"math"

	"photonfarm/coordinator/errs"
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
	// Irradiance per irradiance site (RGB9E5 relative to IrradianceScale): the global map's
	// first IrradianceSites(N) photons in array order; nil when the snapshot has no
	// irradiance section.
	Irradiance      []uint32
	IrradianceScale float32
}

// mapLayout is one validated directory entry.
type mapLayout struct {
	kind   Kind
	count  uint64
	offset uint64
}

// snapshotLayout is a validated header and directory: where each map's records and the
// irradiance section lie. Records themselves are not read.
type snapshotLayout struct {
	maps      []mapLayout
	irrOffset uint64 // 0: no irradiance section
	irrCount  uint64
	irrScale  float32
	// End of the last photon array: where an irradiance section may start (aligned).
	photonsEnd uint64
}

func snapErr(format string, args ...any) error {
	return fmt.Errorf("photon snapshot: "+format, args...)
}

// parseLayout checks everything about a snapshot but its records, in O(maps): sizes,
// offsets, alignment, counts, power scales and the irradiance section.
func parseLayout(data []byte) (snapshotLayout, error) { return parseHead(data, uint64(len(data))) }

// parseHead is parseLayout for a snapshot of size bytes of which data holds at least the
// header and the directory: nothing it checks lies past them.
func parseHead(data []byte, size uint64) (snapshotLayout, error) {
	var l snapshotLayout
	bad := snapErr
	if size < headerSize || len(data) < headerSize {
		return l, bad("%d bytes is shorter than the header", size)
	}
	if string(data[:8]) != snapshotMagic {
		return l, bad("bad magic %q", data[:8])
	}
	if v := le.Uint32(data[8:]); v != snapshotVersion {
		return l, bad("unsupported version %d", v)
	}
	if h := le.Uint32(data[12:]); h != headerSize {
		return l, bad("header_size %d, want %d", h, headerSize)
	}
	count := le.Uint32(data[16:])
	if count > maxMaps {
		return l, bad("map_count %d > %d", count, maxMaps)
	}
	if e := le.Uint32(data[20:]); e != dirEntrySize {
		return l, bad("directory_entry_size %d, want %d", e, dirEntrySize)
	}
	if fs := le.Uint64(data[24:]); fs != size {
		return l, bad("file_size %d, but %d bytes", fs, size)
	}
	dirEnd := uint64(headerSize + dirEntrySize*int(count))
	if dirEnd > size || dirEnd > uint64(len(data)) {
		return l, bad("directory runs past the end")
	}
	end := dirEnd
	for i := 0; i < int(count); i++ {
		d := data[headerSize+i*dirEntrySize:]
		m := mapLayout{kind: Kind(le.Uint32(d[0:])), count: uint64(le.Uint32(d[4:])), offset: le.Uint64(d[16:])}
		scale := math.Float32frombits(le.Uint32(d[48:]))
		switch {
		case !m.kind.known():
			return l, bad("map %d: unknown kind %d", i, m.kind)
		case i > 0 && m.kind <= l.maps[i-1].kind:
			return l, bad("map %d: kinds not increasing", i)
		case m.count > maxMapPhotons:
			return l, bad("map %d: photon_count %d over the limit", i, m.count)
		case m.offset%mapAlignment != 0 || m.offset < end || m.offset > size:
			return l, bad("map %d: offset %d not 64-aligned after byte %d", i, m.offset, end)
		case m.count > (size-m.offset)/recordSize:
			return l, bad("map %d: %d photons run past the end", i, m.count)
		case !(scale > 0) || math.IsInf(float64(scale), 0):
			return l, bad("map %d: power_scale %g", i, scale)
		case le.Uint32(d[52:]) != recordSize:
			return l, bad("map %d: record_size %d", i, le.Uint32(d[52:]))
		}
		end = m.offset + m.count*recordSize
		l.maps = append(l.maps, m)
	}
	l.photonsEnd = end
	l.irrOffset = le.Uint64(data[irrOffsetAt:])
	l.irrCount = uint64(le.Uint32(data[irrCountAt:]))
	l.irrScale = math.Float32frombits(le.Uint32(data[irrScaleAt:]))
	if l.irrOffset == 0 {
		if l.irrCount != 0 || l.irrScale != 0 {
			return l, bad("irradiance_count or irradiance_scale set without an irradiance section")
		}
	} else {
		if len(l.maps) == 0 || l.maps[0].kind != Global {
			return l, bad("irradiance section without a global map")
		}
		switch {
		case l.irrCount > l.maps[0].count || (l.irrCount == 0 && l.maps[0].count > 0):
			return l, bad("irradiance_count %d, but the global map has %d photons (want 1 to all of them)", l.irrCount, l.maps[0].count)
		case !(l.irrScale > 0) || math.IsInf(float64(l.irrScale), 0):
			return l, bad("irradiance_scale %g", l.irrScale)
		case l.irrOffset%mapAlignment != 0 || l.irrOffset < end || l.irrOffset > size:
			return l, bad("irradiance_offset %d not 64-aligned after byte %d", l.irrOffset, end)
		case l.irrCount > (size-l.irrOffset)/irrRecordSize:
			return l, bad("irradiance runs past the end")
		}
		end = l.irrOffset + l.irrCount*irrRecordSize
	}
	if end != size {
		return l, bad("%d trailing bytes", size-end)
	}
	return l, nil
}

// readHead reads the header and directory at the start of r, a snapshot of size bytes, and
// checks them (parseHead); it returns the bytes read and the layout.
func readHead(r io.Reader, size int64) ([]byte, snapshotLayout, error) {
	head := make([]byte, headerSize, headerSize+maxMaps*dirEntrySize)
	if _, err := io.ReadFull(r, head); err != nil {
		return nil, snapshotLayout{}, snapErr("reading the header: %v", err)
	}
	if count := le.Uint32(head[16:]); count <= maxMaps {
		head = head[:headerSize+dirEntrySize*int(count)]
		if _, err := io.ReadFull(r, head[headerSize:]); err != nil {
			return nil, snapshotLayout{}, snapErr("reading the directory: %v", err)
		}
	}
	l, err := parseHead(head, uint64(max(size, 0)))
	return head, l, err
}

// copyRest copies the rest of a snapshot after its head, n bytes, from r to w, then reads
// its end: a snapshot shorter or longer than its size, or one its source finds damaged, is
// an error.
func copyRest(w io.Writer, r io.Reader, n int64) error {
	if _, err := io.CopyN(w, r, n); err != nil {
		if isShort(err) {
			return errs.Field("photon_snapshot", "shorter than its file_size")
		}
		return err
	}
	var b [1]byte
	k, err := r.Read(b[:])
	if k > 0 {
		return errs.Field("photon_snapshot", "longer than its file_size")
	}
	if errors.Is(err, io.EOF) {
		return nil
	}
	return err
}

// Decode parses and validates a snapshot; tests and tools use it to check what Build wrote.
// It checks the layout and the axis field, not the kd-tree ordering (see CheckTree).
func Decode(data []byte) (*Snapshot, error) {
	l, err := parseLayout(data)
	if err != nil {
		return nil, err
	}
	snap := &Snapshot{}
	for i, ml := range l.maps {
		d := data[headerSize+i*dirEntrySize:]
		m := Map{
			Kind:         ml.kind,
			PathsEmitted: le.Uint64(d[8:]),
			PowerScale:   math.Float32frombits(le.Uint32(d[48:])),
		}
		for c := 0; c < 3; c++ {
			m.BoundsMin[c] = math.Float32frombits(le.Uint32(d[24+4*c:]))
			m.BoundsMax[c] = math.Float32frombits(le.Uint32(d[36+4*c:]))
		}
		n := ml.count
		m.Photons = make([]Photon, n)
		for j := range m.Photons {
			rec := data[ml.offset+uint64(j)*recordSize:]
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
				return nil, snapErr("map %d: photon %d: axis %d, but leaf is %v", i, j, p.Axis, leaf)
			}
		}
		snap.Maps = append(snap.Maps, m)
	}
	if l.irrOffset != 0 {
		snap.IrradianceScale = l.irrScale
		snap.Irradiance = make([]uint32, l.irrCount)
		for j := range snap.Irradiance {
			snap.Irradiance[j] = le.Uint32(data[l.irrOffset+uint64(j)*irrRecordSize:])
		}
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
