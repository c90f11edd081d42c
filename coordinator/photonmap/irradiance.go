package photonmap

import (
	"fmt"
	"math"

	"photonfarm/coordinator/errs"
)

// irradianceShard is a validated IRRADIANCE SHARD: its records decoded to binary32
// irradiance, exactly as a C++ reader decodes them.
type irradianceShard struct {
	first  uint64
	values [][3]float32
}

func irrShardErr(i int, format string, args ...any) error {
	return errs.Field(fmt.Sprintf("irradiance_shards[%d]", i), format, args...)
}

// parseIrradianceShard validates shard i (untrusted) completely: header, size and every
// record (each component relative to the shard's scale must lie in [0, 1], as the encoder
// writes them, so a forged exponent cannot overflow the irradiance).
func parseIrradianceShard(i int, data []byte) (irradianceShard, error) {
	var s irradianceShard
	if len(data) < irrShardHeaderSize {
		return s, irrShardErr(i, "%d bytes is shorter than the %d-byte header", len(data), irrShardHeaderSize)
	}
	if string(data[:8]) != irrShardMagic {
		return s, irrShardErr(i, "bad magic %q, want %q", data[:8], irrShardMagic)
	}
	if v := le.Uint32(data[8:]); v != irrShardVersion {
		return s, irrShardErr(i, "unsupported version %d, want %d", v, irrShardVersion)
	}
	if r := le.Uint32(data[12:]); r != irrRecordSize {
		return s, irrShardErr(i, "record_size %d, want %d", r, irrRecordSize)
	}
	s.first = le.Uint64(data[16:])
	count := le.Uint64(data[24:])
	scale := math.Float32frombits(le.Uint32(data[32:]))
	if le.Uint32(data[36:]) != 0 {
		return s, irrShardErr(i, "reserved bytes are not zero")
	}
	if !(scale > 0) || math.IsInf(float64(scale), 0) {
		return s, irrShardErr(i, "irradiance_scale %g must be finite and > 0", scale)
	}
	body := uint64(len(data) - irrShardHeaderSize)
	// Divide rather than multiply: a forged photon_count cannot overflow the check.
	if body%irrRecordSize != 0 || count != body/irrRecordSize {
		return s, irrShardErr(i, "photon_count %d does not match %d bytes of records", count, body)
	}
	s.values = make([][3]float32, count)
	for j := range s.values {
		rel := DecodeRGB9E5(le.Uint32(data[irrShardHeaderSize+j*irrRecordSize:]))
		for c, v := range rel {
			if v > 1 {
				return s, irrShardErr(i, "photon %d: component %g of the scale is above 1", s.first+uint64(j), v)
			}
			s.values[j][c] = v * scale // binary32, as the C++ reader decodes it
		}
	}
	return s, nil
}

// MergeIrradiance adds the precomputed irradiance to a snapshot (docs/photon-snapshot.md,
// "Irradiance section"): shards, in plan order, must tile the global map's photons [0, N)
// exactly, without gaps or overlaps. The result stores one RGB9E5 record per global photon
// relative to the largest component of all shards, re-encoded in binary64 so that the same
// inputs always give the same bytes. Shards are untrusted: a malformed one gives an
// InvalidArgument error naming it ("irradiance_shards[2]: ..."); a snapshot that is
// malformed, has no global map or already has irradiance gives InvalidArgument too.
func MergeIrradiance(snapshot []byte, shards [][]byte) ([]byte, error) {
	l, err := parseLayout(snapshot)
	if err != nil {
		return nil, errs.Field("photon_snapshot", "%v", err)
	}
	if l.irrOffset != 0 {
		return nil, errs.Field("photon_snapshot", "already has an irradiance section")
	}
	if len(l.maps) == 0 || l.maps[0].kind != Global {
		return nil, errs.Field("photon_snapshot", "has no global photon map to add irradiance to")
	}
	n := l.maps[0].count

	parsed := make([]irradianceShard, len(shards))
	var next uint64
	var scale float32
	for i, data := range shards {
		s, err := parseIrradianceShard(i, data)
		if err != nil {
			return nil, err
		}
		// A gap or an overlap means a shard is missing or repeated: some photons would
		// keep no irradiance or two.
		if s.first != next {
			return nil, irrShardErr(i, "starts at photon %d, want %d (shards must tile [0, %d) in order)", s.first, next, n)
		}
		if uint64(len(s.values)) > n-next {
			return nil, irrShardErr(i, "photons [%d, %d) run past the global map's %d", s.first, s.first+uint64(len(s.values)), n)
		}
		next += uint64(len(s.values))
		for _, v := range s.values {
			scale = max(scale, v[0], v[1], v[2])
		}
		parsed[i] = s
	}
	if next != n {
		return nil, errs.Field("irradiance_shards", "cover photons [0, %d) of the global map's %d", next, n)
	}
	if !(scale > 0) {
		scale = 1
	}

	offset := alignUp(int(l.photonsEnd), mapAlignment)
	out := make([]byte, offset+int(n)*irrRecordSize)
	copy(out, snapshot)
	le.PutUint64(out[24:], uint64(len(out)))
	le.PutUint64(out[irrOffsetAt:], uint64(offset))
	le.PutUint32(out[irrCountAt:], uint32(n))
	le.PutUint32(out[irrScaleAt:], math.Float32bits(scale))
	at := offset
	for _, s := range parsed {
		for _, v := range s.values {
			rel := [3]float64{float64(v[0]) / float64(scale), float64(v[1]) / float64(scale), float64(v[2]) / float64(scale)}
			le.PutUint32(out[at:], EncodeRGB9E5(rel))
			at += irrRecordSize
		}
	}
	return out, nil
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
