package photonmap

import (
	"bufio"
	"bytes"
	"errors"
	"fmt"
	"io"
	"math"

	"photonfarm/coordinator/errs"
)

// irradianceHeader is a validated IRRADIANCE SHARD header.
type irradianceHeader struct {
	first, count uint64
	scale        float32
}

func irrShardErr(i int, format string, args ...any) error {
	return errs.Field(fmt.Sprintf("irradiance_shards[%d]", i), format, args...)
}

// openIrradianceShard opens irradiance shard i (untrusted) and checks its header; its
// records are checked as they are read (nextIrradiance).
func openIrradianceShard(i int, src Source) (*scanner, irradianceHeader, error) {
	wrong := func(format string, args ...any) error { return irrShardErr(i, format, args...) }
	s, head, err := openScanner(src, irrShardHeaderSize, irrRecordSize, "photon_count", wrong)
	if err != nil {
		return nil, irradianceHeader{}, err
	}
	h := irradianceHeader{first: le.Uint64(head[16:]), count: le.Uint64(head[24:]), scale: math.Float32frombits(le.Uint32(head[32:]))}
	switch {
	case string(head[:8]) != irrShardMagic:
		err = wrong("bad magic %q, want %q", head[:8], irrShardMagic)
	case le.Uint32(head[8:]) != irrShardVersion:
		err = wrong("unsupported version %d, want %d", le.Uint32(head[8:]), irrShardVersion)
	case le.Uint32(head[12:]) != irrRecordSize:
		err = wrong("record_size %d, want %d", le.Uint32(head[12:]), irrRecordSize)
	case le.Uint32(head[36:]) != 0:
		err = wrong("reserved bytes are not zero")
	case !(h.scale > 0) || math.IsInf(float64(h.scale), 0):
		err = wrong("irradiance_scale %g must be finite and > 0", h.scale)
	}
	if err != nil {
		s.Close()
		return nil, irradianceHeader{}, err
	}
	s.count = h.count
	return s, h, nil
}

// nextIrradiance decodes shard i's next record to binary32 irradiance, exactly as a C++
// reader decodes it, or returns io.EOF. Each component relative to the shard's scale must
// lie in [0, 1], as the encoder writes them, so a forged exponent cannot overflow.
func nextIrradiance(i int, s *scanner, h irradianceHeader) ([3]float32, error) {
	var v [3]float32
	rec, err := s.next()
	if err != nil {
		return v, err
	}
	for c, rel := range DecodeRGB9E5(le.Uint32(rec)) {
		if rel > 1 {
			return v, irrShardErr(i, "photon %d: component %g of the scale is above 1", h.first+s.read-1, rel)
		}
		v[c] = rel * h.scale // binary32, as the C++ reader decodes it
	}
	return v, nil
}

// MergeIrradiance is MergeIrradianceTo on inputs held in memory.
func MergeIrradiance(snapshot []byte, shards [][]byte) ([]byte, error) {
	sources := make([]Source, len(shards))
	for i, d := range shards {
		sources[i] = BytesSource(d)
	}
	var out bytes.Buffer
	if _, err := MergeIrradianceTo(&out, BytesSource(snapshot), int64(len(snapshot)), sources); err != nil {
		return nil, err
	}
	return out.Bytes(), nil
}

// MergedSize is the size of a snapshot of snapshotSize bytes with an irradiance section
// of sites records.
func MergedSize(snapshotSize int64, sites uint64) int64 {
	return int64(alignUp(int(snapshotSize), mapAlignment)) + int64(sites)*irrRecordSize
}

// MergeIrradianceTo writes to w a snapshot of snapshotSize bytes with the precomputed
// irradiance added (docs/photon-snapshot.md, "Irradiance section") and returns the bytes
// written: shards, in plan order, must tile the global map's irradiance sites [0, S)
// without gaps or overlaps, S at most its N photons and at least one (the workers choose
// S, docs/photon-snapshot.md). The result stores one RGB9E5 record per site relative
// to the largest component of all shards, re-encoded in binary64 so that the same inputs
// always give the same bytes. Shards are untrusted: a malformed one gives an
// InvalidArgument error naming it ("irradiance_shards[2]: ..."); a snapshot that is
// malformed, has no global map or already has irradiance gives InvalidArgument too (naming
// photon_snapshot). Errors of w are returned unchanged. When it fails, w may have received
// part of a snapshot.
//
// The shards are read twice (to check them and find the scale, then to encode), the
// snapshot once, and everything is streamed to w: the merge holds a few buffers, whatever
// the size of the snapshot.
func MergeIrradianceTo(w io.Writer, snapshot Source, snapshotSize int64, shards []Source) (int64, error) {
	rc, err := snapshot()
	if err != nil {
		return 0, err
	}
	defer rc.Close()
	head, l, err := readHead(rc, snapshotSize)
	if err != nil {
		return 0, errs.Field("photon_snapshot", "%v", err)
	}
	if l.irrOffset != 0 {
		return 0, errs.Field("photon_snapshot", "already has an irradiance section")
	}
	if len(l.maps) == 0 || l.maps[0].kind != Global {
		return 0, errs.Field("photon_snapshot", "has no global photon map to add irradiance to")
	}
	scale, n, err := irradianceScale(shards, l.maps[0].count)
	if err != nil {
		return 0, err
	}

	size := MergedSize(snapshotSize, n)
	offset := size - int64(n)*irrRecordSize
	out := bufio.NewWriterSize(w, 1<<16)
	le.PutUint64(head[24:], uint64(size))
	le.PutUint64(head[irrOffsetAt:], uint64(offset))
	le.PutUint32(head[irrCountAt:], uint32(n))
	le.PutUint32(head[irrScaleAt:], math.Float32bits(scale))
	if _, err := out.Write(head); err != nil {
		return 0, err
	}
	if err := copyRest(out, rc, snapshotSize-int64(len(head))); err != nil {
		return 0, err
	}
	if _, err := out.Write(make([]byte, offset-snapshotSize)); err != nil {
		return 0, err
	}
	var rec [irrRecordSize]byte
	left := n
	for i, src := range shards {
		s, h, err := openIrradianceShard(i, src)
		if err != nil {
			return 0, err
		}
		for {
			v, err := nextIrradiance(i, s, h)
			if errors.Is(err, io.EOF) {
				break
			}
			if err == nil && left == 0 {
				err = errs.E(errs.Internal, "irradiance_shards[%d] changed between the two reads of the merge", i)
			}
			if err == nil {
				rel := [3]float64{float64(v[0]) / float64(scale), float64(v[1]) / float64(scale), float64(v[2]) / float64(scale)}
				le.PutUint32(rec[:], EncodeRGB9E5(rel))
				_, err = out.Write(rec[:])
				left--
			}
			if err != nil {
				s.Close()
				return 0, err
			}
		}
		s.Close()
	}
	if left != 0 {
		return 0, errs.E(errs.Internal, "the irradiance shards changed between the two reads of the merge")
	}
	return size, out.Flush()
}

// irradianceScale reads the irradiance shards once, checking each whole and that they tile
// the irradiance sites, a leading part of the global map's photons of at least one if it
// has any, and returns the largest component of all (1 if none is positive) and how many
// sites they cover.
func irradianceScale(shards []Source, photons uint64) (float32, uint64, error) {
	var next uint64
	var scale float32
	for i, src := range shards {
		s, h, err := openIrradianceShard(i, src)
		if err != nil {
			return 0, 0, err
		}
		// A gap or an overlap means a shard is missing or repeated: some sites would
		// keep no irradiance or two.
		if h.first != next {
			s.Close()
			return 0, 0, irrShardErr(i, "starts at photon %d, want %d (shards must tile the sites [0, S) in order)", h.first, next)
		}
		if h.count > photons-next {
			s.Close()
			return 0, 0, irrShardErr(i, "photons [%d, %d) run past the global map's %d", h.first, h.first+h.count, photons)
		}
		for {
			v, err := nextIrradiance(i, s, h)
			if errors.Is(err, io.EOF) {
				break
			}
			if err != nil {
				s.Close()
				return 0, 0, err
			}
			scale = max(scale, v[0], v[1], v[2])
		}
		s.Close()
		next += h.count
	}
	if next == 0 && photons > 0 {
		return 0, 0, errs.Field("irradiance_shards", "cover no site of the global map's %d photons", photons)
	}
	if !(scale > 0) {
		scale = 1
	}
	return scale, next, nil
}

// EncodeIrradianceShard writes an IRRADIANCE SHARD as a worker does (the worker's encoder is
// the product; this one serves tests and test vectors). Components must be finite and >= 0.
func EncodeIrradianceShard(first uint64, irradiance [][3]float32) []byte {
	var scale float32
	for _, v := range irradiance {
		scale = max(scale, v[0], v[1], v[2])
	}
	if !(scale > 0) {
		scale = 1
	}
	out := make([]byte, irrShardHeaderSize+irrRecordSize*len(irradiance))
	copy(out, irrShardMagic)
	le.PutUint32(out[8:], irrShardVersion)
	le.PutUint32(out[12:], irrRecordSize)
	le.PutUint64(out[16:], first)
	le.PutUint64(out[24:], uint64(len(irradiance)))
	le.PutUint32(out[32:], math.Float32bits(scale))
	for i, v := range irradiance {
		rel := [3]float64{float64(v[0]) / float64(scale), float64(v[1]) / float64(scale), float64(v[2]) / float64(scale)}
		le.PutUint32(out[irrShardHeaderSize+irrRecordSize*i:], EncodeRGB9E5(rel))
	}
	return out
}
